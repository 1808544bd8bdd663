//! The typed key of `MotionBlur`, [`MotionBlurKey`] (`post/motion_blur.wgsl`). It stands in a file
//! of its own that imports no pass, so that `shaders::SHADERS` names it without a circle through
//! the renderer (docs/architecture.md, "Layers inside render"); `post/motion_blur.rs` re-exports
//! it.

crate::flag_key! {
    /// `post/motion_blur.wgsl`: one permutation, three entry points.
    pub struct MotionBlurKey("post/motion_blur.wgsl");
}
