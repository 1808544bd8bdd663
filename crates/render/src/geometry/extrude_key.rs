//! The typed key of Extrude, [`ExtrudeKey`] (`geometry/extrude.wgsl`). It stands in a file of its
//! own that imports no pass, so that `shaders::SHADERS` names it without a circle through the
//! renderer (docs/architecture.md, "Layers inside render"); `geometry/extrude.rs` re-exports it.

crate::flag_key! {
    /// `geometry/extrude.wgsl`.
    pub struct ExtrudeKey("geometry/extrude.wgsl") {
        /// The height is read from a texture.
        texture: "TEXTURE",
    }
}
