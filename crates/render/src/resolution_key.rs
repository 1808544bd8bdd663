//! The typed key of the half-resolution upsample, [`UpsampleKey`] (`resolution/upsample.wgsl`). It
//! declares its shader file (`shader_file!`), so no table below the effects names it;
//! `resolution.rs` re-exports it.

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
