//! The typed key of GPU skinning, [`SkinningKey`] (`geometry/skinning.wgsl`). It declares its
//! shader file (`shader_file!`), so no table below the effects names it; `geometry/skinning.rs`
//! re-exports it.

crate::flag_key! {
    /// `geometry/skinning.wgsl`: one permutation.
    pub struct SkinningKey("geometry/skinning.wgsl");
}
