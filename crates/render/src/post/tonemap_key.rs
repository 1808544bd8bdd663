//! The typed key of `Tonemap`, [`TonemapKey`] (`post/tonemap.wgsl`). It declares its shader file
//! (`shader_file!`), so no table below the effects names it; `post/tonemap.rs` re-exports it.

crate::flag_key! {
    /// `post/tonemap.wgsl`.
    pub struct TonemapKey("post/tonemap.wgsl") {
        /// Exposure from the adapted luminance (an Eye Adaptation input).
        eye_adaptation: "EYE_ADAPTATION",
    }
}
