//! The typed key of the environment maps' prefilter, [`PrefilterKey`]
//! (`environment/prefilter.wgsl`). It stands in a file of its own that imports no pass, so that
//! `shaders::SHADERS` names it without a circle through the renderer (docs/architecture.md, "Layers
//! inside render"); `environment/prefilter.rs` re-exports it.

crate::flag_key! {
    /// `environment/prefilter.wgsl`: one permutation, an entry per step.
    pub struct PrefilterKey("environment/prefilter.wgsl");
}
