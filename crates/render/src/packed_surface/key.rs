//! The typed key of the packed surface pass, [`PackKey`] (`packed_surface/pack.wgsl`). It
//! declares its shader file (`shader_file!`); `packed_surface/mod.rs` re-exports it.

crate::flag_key! {
    /// `packed_surface/pack.wgsl`: one permutation.
    pub struct PackKey("packed_surface/pack.wgsl");
}
