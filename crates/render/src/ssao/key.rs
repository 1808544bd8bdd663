//! SSAO's permutations as types. Each value is one permutation of its
//! shader; a combination the shader does not support cannot be written
//! (half resolution blends its history after the upsample, so `AoTarget`
//! has no "half and temporal"; the combine comes with the vertical blur).
//! These replace the string rules a table of shaders held for these files,
//! and each declares its shader file (`shader_file!`).

use crate::shaders::permutation::Permutation;

/// Which estimator.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum AoMode {
    /// Emeshe's stochastic wide-range AO: rays in a cosine-weighted
    /// hemisphere, each marched `steps` times against the depth buffer; a
    /// ray is blocked where it passes behind a surface within `radius`.
    /// Matches ray-cast AO of the same radius as samples grow.
    Stochastic,
    /// Scalable Ambient Obscurance (McGuire, Mara, Luebke 2012): a spiral of
    /// taps over a view-depth mip chain, the obscurance estimator with a
    /// smooth falloff. Cheap at large radii; not calibrated to ray-cast AO.
    Sao,
    /// Horizon-based AO (Bavoil 2008): `samples` directions in screen space,
    /// `steps` taps each; per direction the square of the highest horizon's
    /// sine is the (cosine-weighted) occluded share of that slice. Short
    /// range, local detail.
    Hbao,
}

impl AoMode {
    pub(super) fn name(self) -> &'static str {
        match self {
            AoMode::Stochastic => "SSAO",
            AoMode::Sao => "SAO",
            AoMode::Hbao => "HBAO",
        }
    }
}

/// `ssao/ao.wgsl`: which estimator, and where its result goes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct AoKey {
    /// The plain estimator (`Stochastic`) also serves AO switched off, whose
    /// early exit writes 1.
    pub estimator: AoMode,
    pub target: AoTarget,
    /// The plain estimator's rays read the packed surface's view z
    /// (crate::packed_surface); the other estimators never do.
    pub packed: bool,
}

/// Where the raw estimate goes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum AoTarget {
    /// A full-resolution target the temporal pass or the blur reads.
    Full,
    /// Full resolution, with the history blended in the same pass.
    FullTemporal,
    /// Half resolution, upsampled (and blurred) by later passes.
    Half,
    /// Half resolution, with the half-size history blended in the same pass.
    HalfTemporal,
}

impl Permutation for AoKey {
    crate::shader_file!("ssao/ao.wgsl");
    const FEATURES: &'static [&'static str] = &["SAO", "HBAO", "HALF", "TEMPORAL", "PACKED_Z"];

    fn features(self) -> impl Iterator<Item = &'static str> {
        let estimator = match self.estimator {
            AoMode::Stochastic => None,
            AoMode::Sao => Some("SAO"),
            AoMode::Hbao => Some("HBAO"),
        };
        let target = match self.target {
            AoTarget::Full => None,
            AoTarget::FullTemporal => Some("TEMPORAL"),
            AoTarget::Half | AoTarget::HalfTemporal => Some("HALF"),
        };
        let blended = (self.target == AoTarget::HalfTemporal).then_some("TEMPORAL");
        estimator
            .into_iter()
            .chain(target)
            .chain(blended)
            .chain(self.packed.then_some("PACKED_Z"))
    }

    fn all() -> Vec<Self> {
        let estimators = [AoMode::Stochastic, AoMode::Sao, AoMode::Hbao];
        let targets = [
            AoTarget::Full,
            AoTarget::FullTemporal,
            AoTarget::Half,
            AoTarget::HalfTemporal,
        ];
        let plain = |packed| {
            move |(estimator, target)| AoKey {
                estimator,
                target,
                packed,
            }
        };
        let every = estimators
            .into_iter()
            .flat_map(|estimator| targets.map(|target| (estimator, target)));
        let packed = targets.map(|target| (AoMode::Stochastic, target));
        every
            .map(plain(false))
            .chain(packed.into_iter().map(plain(true)))
            .collect()
    }
}

/// `ssao/linear_depth.wgsl`: SAO's view depth from the G-buffer's depth
/// (level 0), or one mip of it from the level above.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum DepthKey {
    FromGBuffer,
    Downsample,
}

impl Permutation for DepthKey {
    crate::shader_file!("ssao/linear_depth.wgsl");
    const FEATURES: &'static [&'static str] = &["DOWNSAMPLE"];

    fn features(self) -> impl Iterator<Item = &'static str> {
        (self == DepthKey::Downsample)
            .then_some("DOWNSAMPLE")
            .into_iter()
    }

    fn all() -> Vec<Self> {
        vec![DepthKey::FromGBuffer, DepthKey::Downsample]
    }
}

/// `ssao/blur.wgsl`: one direction of the depth-aware blur (the vertical
/// one writes the output and may multiply another AO in), reading each
/// tap's surface from the G-buffer or from its packed surface
/// (crate::packed_surface). `half`: AO's half-resolution chain, both
/// passes at half size from the G-buffer (never packed, never combining:
/// the upsample that follows writes the output and combines).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct BlurKey {
    pub pass: BlurPass,
    pub packed: bool,
    pub half: bool,
}

/// Which pass of the blur.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum BlurPass {
    Horizontal,
    Vertical,
    VerticalCombine,
}

impl Permutation for BlurKey {
    crate::shader_file!("ssao/blur.wgsl");
    const FEATURES: &'static [&'static str] = &["VERTICAL", "COMBINE", "PACKED", "HALF"];

    fn features(self) -> impl Iterator<Item = &'static str> {
        let (vertical, combine) = match self.pass {
            BlurPass::Horizontal => (false, false),
            BlurPass::Vertical => (true, false),
            BlurPass::VerticalCombine => (true, true),
        };
        vertical
            .then_some("VERTICAL")
            .into_iter()
            .chain(combine.then_some("COMBINE"))
            .chain(self.packed.then_some("PACKED"))
            .chain(self.half.then_some("HALF"))
    }

    fn all() -> Vec<Self> {
        let passes = [
            BlurPass::Horizontal,
            BlurPass::Vertical,
            BlurPass::VerticalCombine,
        ];
        let full = [false, true].into_iter().flat_map(|packed| {
            passes.map(|pass| BlurKey {
                pass,
                packed,
                half: false,
            })
        });
        let half = [BlurPass::Horizontal, BlurPass::Vertical].map(|pass| BlurKey {
            pass,
            packed: false,
            half: true,
        });
        full.chain(half).collect()
    }
}
