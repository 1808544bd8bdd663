//! The typed key of `Tonemap`, [`TonemapKey`] (`post/tonemap.wgsl`). It stands in a file of its own
//! that imports no pass, so that `shaders::SHADERS` names it without a circle through the renderer
//! (docs/architecture.md, "Layers inside render"); `post/tonemap.rs` re-exports it.

crate::flag_key! {
    /// `post/tonemap.wgsl`.
    pub struct TonemapKey("post/tonemap.wgsl") {
        /// Exposure from the adapted luminance (an Eye Adaptation input).
        eye_adaptation: "EYE_ADAPTATION",
    }
}
