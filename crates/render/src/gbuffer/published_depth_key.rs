//! The typed key of the published depth, [`PublishedDepthKey`] (`gbuffer/published_depth.wgsl`). It
//! stands in a file of its own that imports no pass, so that `shaders::SHADERS` names it without a
//! circle through the renderer (docs/architecture.md, "Layers inside render");
//! `gbuffer/published_depth.rs` re-exports it.

crate::flag_key! {
    /// `gbuffer/published_depth.wgsl`.
    pub struct PublishedDepthKey("gbuffer/published_depth.wgsl") {
        /// Depth from the compute raster's 64-bit buffer (else the hardware raster's depth).
        compute_raster: "COMPUTE_RASTER",
    }
}
