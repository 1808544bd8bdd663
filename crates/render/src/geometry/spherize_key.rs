//! The typed key of Spherize, [`SpherizeKey`] (`geometry/spherize.wgsl`). It declares its shader
//! file (`shader_file!`), so no table below the effects names it; `geometry/spherize.rs`
//! re-exports it.

crate::flag_key! {
    /// `geometry/spherize.wgsl`: one permutation.
    pub struct SpherizeKey("geometry/spherize.wgsl");
}
