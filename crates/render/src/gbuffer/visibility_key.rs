//! The typed key of the G-buffer's visibility pass, [`VisibilityKey`] (`gbuffer/visibility.wgsl`).
//! It declares its shader file (`shader_file!`), so no table below the effects names it;
//! `gbuffer/passes.rs` re-exports it.

crate::flag_key! {
    /// `gbuffer/visibility.wgsl`.
    pub struct VisibilityKey("gbuffer/visibility.wgsl") {
        /// Texels of the colour map below the cutoff are discarded.
        alpha_mask: "ALPHA_MASK",
    }
}
