//! The typed key of the half-resolution upsample, [`UpsampleKey`] (`resolution/upsample.wgsl`). It
//! stands in a file of its own that imports no pass, so that `shaders::SHADERS` names it without a
//! circle through the renderer (docs/architecture.md, "Layers inside render"); `resolution.rs` re-
//! exports it.

crate::choice_key! {
    /// `resolution/upsample.wgsl`.
    pub enum UpsampleKey("resolution/upsample.wgsl") {
        /// RGBA16F radiance.
        Rgba16,
        /// R32F visibility.
        R32: "R32",
        /// RGBA16F, keeping the full-size image where it is in focus.
        Detail: "DETAIL",
    }
}
