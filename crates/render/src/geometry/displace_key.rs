//! The typed key of Displace, [`DisplaceKey`] (`geometry/displace.wgsl`). It stands in a file of
//! its own that imports no pass, so that `shaders::SHADERS` names it without a circle through the
//! renderer (docs/architecture.md, "Layers inside render"); `geometry/displace.rs` re-exports it.

crate::choice_key! {
    /// `geometry/displace.wgsl`: the pass that moves the vertices, or one of
    /// the two that make their normals afterwards.
    pub enum DisplaceKey("geometry/displace.wgsl") {
        Move,
        /// Face normals summed per vertex.
        Accumulate: "ACCUMULATE",
        /// The sums normalized.
        Normals: "NORMALS",
    }
}
