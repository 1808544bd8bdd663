//! The typed key of PN Triangles, [`PnTrianglesKey`] (`geometry/pn_triangles.wgsl`). It stands in a
//! file of its own that imports no pass, so that `shaders::SHADERS` names it without a circle
//! through the renderer (docs/architecture.md, "Layers inside render"); `geometry/pn_triangles.rs`
//! re-exports it.

crate::flag_key! {
    /// `geometry/pn_triangles.wgsl`.
    pub struct PnTrianglesKey("geometry/pn_triangles.wgsl") {
        /// Subdivided, not curved.
        flat: "FLAT",
    }
}
