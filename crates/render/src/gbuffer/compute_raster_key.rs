//! The typed key of the compute rasterizer, [`RasterKey`] (`gbuffer/raster.wgsl`). It declares its
//! shader file (`shader_file!`), so no table below the effects names it;
//! `gbuffer/compute_raster.rs` re-exports it.

crate::flag_key! {
    /// `gbuffer/raster.wgsl`.
    pub struct RasterKey("gbuffer/raster.wgsl") {
        /// Back faces are drawn too.
        two_sided: "TWO_SIDED",
        /// Positions fetched alone (a CPU adapter with no particle system drawn).
        meshes_only: "MESHES_ONLY",
        /// 32-bit depth words, no triangle ids.
        depth_only: "DEPTH_ONLY",
        /// Every layer of a shadow map in one chain: the layer a dispatch
        /// dimension, each with its camera and words (`record_layers`).
        layered: "LAYERED",
    }
}
