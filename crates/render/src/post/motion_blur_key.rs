//! The typed key of `MotionBlur`, [`MotionBlurKey`] (`post/motion_blur.wgsl`). It declares its
//! shader file (`shader_file!`), so no table below the effects names it; `post/motion_blur.rs`
//! re-exports it.

crate::flag_key! {
    /// `post/motion_blur.wgsl`: one permutation, three entry points.
    pub struct MotionBlurKey("post/motion_blur.wgsl");
}
