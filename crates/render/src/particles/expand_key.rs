//! The typed key of the drawn particles' read-back, [`ExpandKey`] (`particles/expand.wgsl`). It
//! stands in a file of its own that imports no pass, so that `shaders::SHADERS` names it without a
//! circle through the renderer (docs/architecture.md, "Layers inside render");
//! `particles/expand.rs` re-exports it.

crate::flag_key! {
    /// `particles/expand.wgsl`: one permutation.
    pub struct ExpandKey("particles/expand.wgsl");
}
