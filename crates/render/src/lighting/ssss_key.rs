//! The typed key of `SSSS`, [`SsssKey`] (`lighting/ssss.wgsl`). It stands in a file of its own that
//! imports no pass, so that `shaders::SHADERS` names it without a circle through the renderer
//! (docs/architecture.md, "Layers inside render"); `lighting/ssss.rs` re-exports it.

crate::flag_key! {
    /// `lighting/ssss.wgsl`: the pass's direction and how many sources it blurs.
    pub struct SsssKey("lighting/ssss.wgsl") {
        vertical: "VERTICAL",
        /// A second source (the second light type's subsurface term).
        sources_2: "SOURCES_2",
        sources_3: "SOURCES_3",
    }
}
