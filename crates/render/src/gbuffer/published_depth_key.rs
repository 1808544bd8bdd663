//! The typed key of the published depth, [`PublishedDepthKey`] (`gbuffer/published_depth.wgsl`). It
//! declares its shader file (`shader_file!`), so no table below the effects names it;
//! `gbuffer/published_depth.rs` re-exports it.

crate::flag_key! {
    /// `gbuffer/published_depth.wgsl`.
    pub struct PublishedDepthKey("gbuffer/published_depth.wgsl") {
        /// Depth from the compute raster's 64-bit buffer (else the hardware raster's depth).
        compute_raster: "COMPUTE_RASTER",
    }
}
