//! The typed key of the clustered light assignment, [`ClustersKey`] (`lighting/clusters.wgsl`). It
//! declares its shader file (`shader_file!`), so no table below the effects names it;
//! `lighting/clusters.rs` re-exports it.

crate::flag_key! {
    /// `lighting/clusters.wgsl`: an entry per step; `occupied` lists only the
    /// froxels lit transparency's fragments marked (OCCUPIED), CookTorrance's
    /// walk lists every froxel; `merged` lists merged lights and their
    /// members by their bands (MERGED, CookTorrance's Light Merge).
    pub struct ClustersKey("lighting/clusters.wgsl") {
        occupied: "OCCUPIED",
        merged: "MERGED",
    }
}
