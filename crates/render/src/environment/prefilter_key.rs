//! The typed key of the environment maps' prefilter, [`PrefilterKey`]
//! (`environment/prefilter.wgsl`). It declares its shader file (`shader_file!`), so no table below
//! the effects names it; `environment/prefilter.rs` re-exports it.

crate::flag_key! {
    /// `environment/prefilter.wgsl`: one permutation, an entry per step.
    pub struct PrefilterKey("environment/prefilter.wgsl");
}
