//! The typed key of `EyeAdaptation`, [`EyeAdaptationKey`] (`post/eye_adaptation.wgsl`). It
//! declares its shader file (`shader_file!`), so no table below the effects names it;
//! `post/eye_adaptation.rs` re-exports it.

crate::flag_key! {
    /// `post/eye_adaptation.wgsl`: one permutation, an entry per step.
    pub struct EyeAdaptationKey("post/eye_adaptation.wgsl");
}
