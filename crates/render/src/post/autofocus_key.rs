//! The typed key of `Autofocus`, [`AutofocusKey`] (`post/autofocus.wgsl`). It declares its shader
//! file (`shader_file!`), so no table below the effects names it; `post/autofocus.rs` re-exports
//! it.

crate::flag_key! {
    /// `post/autofocus.wgsl`: one permutation.
    pub struct AutofocusKey("post/autofocus.wgsl");
}
