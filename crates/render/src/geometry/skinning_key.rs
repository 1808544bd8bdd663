//! The typed key of GPU skinning, [`SkinningKey`] (`geometry/skinning.wgsl`). It stands in a file
//! of its own that imports no pass, so that `shaders::SHADERS` names it without a circle through
//! the renderer (docs/architecture.md, "Layers inside render"); `geometry/skinning.rs` re-exports
//! it.

crate::flag_key! {
    /// `geometry/skinning.wgsl`: one permutation.
    pub struct SkinningKey("geometry/skinning.wgsl");
}
