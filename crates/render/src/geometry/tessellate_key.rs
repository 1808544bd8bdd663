//! The typed key of Tessellate, [`TessellateKey`] (`geometry/tessellate.wgsl`). It stands in a file
//! of its own that imports no pass, so that `shaders::SHADERS` names it without a circle through
//! the renderer (docs/architecture.md, "Layers inside render"); `geometry/tessellate.rs` re-exports
//! it.

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
