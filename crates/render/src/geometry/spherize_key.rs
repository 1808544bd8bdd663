//! The typed key of Spherize, [`SpherizeKey`] (`geometry/spherize.wgsl`). It stands in a file of
//! its own that imports no pass, so that `shaders::SHADERS` names it without a circle through the
//! renderer (docs/architecture.md, "Layers inside render"); `geometry/spherize.rs` re-exports it.

crate::flag_key! {
    /// `geometry/spherize.wgsl`: one permutation.
    pub struct SpherizeKey("geometry/spherize.wgsl");
}
