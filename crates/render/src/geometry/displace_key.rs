//! The typed key of Displace, [`DisplaceKey`] (`geometry/displace.wgsl`). It declares its shader
//! file (`shader_file!`), so no table below the effects names it; `geometry/displace.rs`
//! re-exports it.

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
