//! The typed key of the post passes' copy, [`CopyKey`] (`post/copy.wgsl`). It declares its shader
//! file (`shader_file!`), so no table below the effects names it; `post/mod.rs` re-exports it.

crate::flag_key! {
    /// `post/copy.wgsl`: one permutation.
    pub struct CopyKey("post/copy.wgsl");
}
