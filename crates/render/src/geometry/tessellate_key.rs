//! The typed key of Tessellate, [`TessellateKey`] (`geometry/tessellate.wgsl`). It declares its
//! shader file (`shader_file!`), so no table below the effects names it; `geometry/tessellate.rs`
//! re-exports it.

crate::choice_key! {
    /// `geometry/tessellate.wgsl`: the pass that writes the triangles, or
    /// one of the two that count them first.
    pub enum TessellateKey("geometry/tessellate.wgsl") {
        Write,
        /// Triangles per face.
        Count: "COUNT",
        /// Their prefix sums.
        Sums: "SUMS",
    }
}
