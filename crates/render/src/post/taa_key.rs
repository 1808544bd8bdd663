//! The typed key of `TAA`, [`TaaQuality`] (`post/taa.wgsl`): the quality setting the node library
//! names is itself the shader's permutation. It declares its shader file (`shader_file!`), so no
//! table below the effects names it; `post/taa.rs` re-exports it.

use crate::shaders::permutation::Permutation;

/// How the history is checked against the current frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TaaQuality {
    /// Clamp to the 3x3 neighbourhood's YCoCg box; bilinear history.
    Low,
    /// Clip towards the neighbourhood's mean (variance clipping); bilinear history.
    Medium,
    /// Variance clipping and a bicubic (Catmull-Rom) history read, sharper in motion.
    High,
}

/// Each quality is one permutation of `post/taa.wgsl`: the bicubic read
/// comes only with variance clipping.
impl Permutation for TaaQuality {
    crate::shader_file!("post/taa.wgsl");
    const FEATURES: &'static [&'static str] = &["VARIANCE_CLIP", "CATMULL_ROM"];

    fn features(self) -> impl Iterator<Item = &'static str> {
        let on = match self {
            TaaQuality::Low => 0,
            TaaQuality::Medium => 1,
            TaaQuality::High => 2,
        };
        Self::FEATURES[..on].iter().copied()
    }

    fn all() -> Vec<Self> {
        vec![TaaQuality::Low, TaaQuality::Medium, TaaQuality::High]
    }
}
