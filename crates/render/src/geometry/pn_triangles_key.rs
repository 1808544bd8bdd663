//! The typed key of PN Triangles, [`PnTrianglesKey`] (`geometry/pn_triangles.wgsl`). It declares
//! its shader file (`shader_file!`), so no table below the effects names it;
//! `geometry/pn_triangles.rs` re-exports it.

crate::flag_key! {
    /// `geometry/pn_triangles.wgsl`.
    pub struct PnTrianglesKey("geometry/pn_triangles.wgsl") {
        /// Subdivided, not curved.
        flat: "FLAT",
    }
}
