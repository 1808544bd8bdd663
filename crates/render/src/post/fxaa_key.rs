//! The typed key of `FXAA`, [`FxaaKey`] (`post/fxaa.wgsl`). It stands in a file of its own that
//! imports no pass, so that `shaders::SHADERS` names it without a circle through the renderer
//! (docs/architecture.md, "Layers inside render"); `post/fxaa.rs` re-exports it.

crate::flag_key! {
    /// `post/fxaa.wgsl`: one permutation.
    pub struct FxaaKey("post/fxaa.wgsl");
}
