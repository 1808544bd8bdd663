//! The typed key of the clustered light assignment, [`ClustersKey`] (`lighting/clusters.wgsl`). It
//! stands in a file of its own that imports no pass, so that `shaders::SHADERS` names it without a
//! circle through the renderer (docs/architecture.md, "Layers inside render");
//! `lighting/clusters.rs` re-exports it.

crate::flag_key! {
    /// `lighting/clusters.wgsl`: an entry per step; `occupied` lists only the
    /// froxels lit transparency's fragments marked (OCCUPIED), CookTorrance's
    /// walk lists every froxel.
    pub struct ClustersKey("lighting/clusters.wgsl") {
        occupied: "OCCUPIED",
    }
}
