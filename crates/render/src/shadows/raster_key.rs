//! The typed keys of drawing shadow-map layers: [`ShadowDepthKey`] (`shadows/depth.wgsl`),
//! [`MomentsKey`] (`shadows/moments.wgsl`), [`ShadowResolveKey`] (`shadows/resolve.wgsl`). They
//! declare their shader file (`shader_file!`), so no table below the effects names them;
//! `shadows/raster.rs` re-exports them.

crate::flag_key! {
    /// `shadows/depth.wgsl`: one permutation.
    pub struct ShadowDepthKey("shadows/depth.wgsl");
}

crate::flag_key! {
    /// `shadows/moments.wgsl`: one permutation.
    pub struct MomentsKey("shadows/moments.wgsl");
}

crate::flag_key! {
    /// `shadows/resolve.wgsl`.
    pub struct ShadowResolveKey("shadows/resolve.wgsl") {
        /// Composited over the cached maps of what stands still.
        over_still: "OVER_STILL",
    }
}
