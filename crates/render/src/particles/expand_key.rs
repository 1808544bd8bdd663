//! The typed key of the drawn particles' read-back, [`ExpandKey`] (`particles/expand.wgsl`). It
//! declares its shader file (`shader_file!`), so no table below the effects names it;
//! `particles/expand.rs` re-exports it.

crate::flag_key! {
    /// `particles/expand.wgsl`: one permutation.
    pub struct ExpandKey("particles/expand.wgsl");
}
