//! The typed key of the G-buffer's visibility pass, [`VisibilityKey`] (`gbuffer/visibility.wgsl`).
//! It stands in a file of its own that imports no pass, so that `shaders::SHADERS` names it without
//! a circle through the renderer (docs/architecture.md, "Layers inside render");
//! `gbuffer/passes.rs` re-exports it.

crate::flag_key! {
    /// `gbuffer/visibility.wgsl`.
    pub struct VisibilityKey("gbuffer/visibility.wgsl") {
        /// Texels of the colour map below the cutoff are discarded.
        alpha_mask: "ALPHA_MASK",
    }
}
