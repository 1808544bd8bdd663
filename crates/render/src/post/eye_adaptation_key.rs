//! The typed key of `EyeAdaptation`, [`EyeAdaptationKey`] (`post/eye_adaptation.wgsl`). It stands
//! in a file of its own that imports no pass, so that `shaders::SHADERS` names it without a circle
//! through the renderer (docs/architecture.md, "Layers inside render"); `post/eye_adaptation.rs`
//! re-exports it.

crate::flag_key! {
    /// `post/eye_adaptation.wgsl`: one permutation, an entry per step.
    pub struct EyeAdaptationKey("post/eye_adaptation.wgsl");
}
