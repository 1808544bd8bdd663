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
        /// AO's half chain: its blurred R32F visibility into the RGBA16F
        /// output (grey, alpha 1), as AO's last blur pass writes it at Full.
        Ao: "AO",
        /// `Ao`, multiplying another AO in (the blur's `COMBINE` at Full).
        AoCombine: "AO_COMBINE",
        /// SSGI's half chain: the bounce plus the ambient light times the
        /// escaped share (the blur's `AMBIENT` at Full).
        Ambient: "AMBIENT",
    }
}
