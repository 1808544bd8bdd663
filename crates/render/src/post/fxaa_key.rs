//! The typed key of `FXAA`, [`FxaaKey`] (`post/fxaa.wgsl`). It declares its shader file
//! (`shader_file!`), so no table below the effects names it; `post/fxaa.rs` re-exports it.

crate::flag_key! {
    /// `post/fxaa.wgsl`: one permutation.
    pub struct FxaaKey("post/fxaa.wgsl");
}
