//! The typed key of `SSGI`, [`SsgiKey`] (`lighting/ssgi.wgsl`). It declares its shader file
//! (`shader_file!`), so no table below the effects names it; `lighting/ssgi.rs` re-exports it.

use crate::shaders::permutation::Permutation;

/// `lighting/ssgi.wgsl`'s permutations: the gather (at full or half
/// resolution), the temporal blend (with the gather in the same pass at full
/// resolution), or a blur pass (adding the ambient light in the last one).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SsgiKey {
    Gather { half: bool },
    Temporal { gather: bool },
    Blur { ambient: bool },
}

impl Permutation for SsgiKey {
    crate::shader_file!("lighting/ssgi.wgsl");
    const FEATURES: &'static [&'static str] = &["TEMPORAL", "GATHER", "BLUR", "AMBIENT", "HALF"];

    fn features(self) -> impl Iterator<Item = &'static str> {
        let on: &[&'static str] = match self {
            SsgiKey::Gather { half: false } => &[],
            SsgiKey::Gather { half: true } => &["HALF"],
            SsgiKey::Temporal { gather: false } => &["TEMPORAL"],
            SsgiKey::Temporal { gather: true } => &["TEMPORAL", "GATHER"],
            SsgiKey::Blur { ambient: false } => &["BLUR"],
            SsgiKey::Blur { ambient: true } => &["BLUR", "AMBIENT"],
        };
        on.iter().copied()
    }

    fn all() -> Vec<Self> {
        vec![
            SsgiKey::Gather { half: false },
            SsgiKey::Temporal { gather: false },
            SsgiKey::Temporal { gather: true },
            SsgiKey::Blur { ambient: false },
            SsgiKey::Blur { ambient: true },
            SsgiKey::Gather { half: true },
        ]
    }
}

/// `lighting/ssgi_blur_tiled.wgsl`: the blur's x and y in one dispatch over
/// tiles in workgroup memory; with `ambient` the ambient added; with
/// `toward_zero` the x result rounded to half float as a store on a CPU
/// adapter rounds it (toward zero), else to nearest.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct SsgiTiledBlurKey {
    pub ambient: bool,
    pub toward_zero: bool,
}

impl Permutation for SsgiTiledBlurKey {
    crate::shader_file!("lighting/ssgi_blur_tiled.wgsl");
    const FEATURES: &'static [&'static str] = &["AMBIENT", "HALF_TOWARD_ZERO"];

    fn features(self) -> impl Iterator<Item = &'static str> {
        let ambient = self.ambient.then_some("AMBIENT");
        ambient
            .into_iter()
            .chain(self.toward_zero.then_some("HALF_TOWARD_ZERO"))
    }

    fn all() -> Vec<Self> {
        [false, true]
            .into_iter()
            .flat_map(|toward_zero| {
                [false, true].map(|ambient| SsgiTiledBlurKey {
                    ambient,
                    toward_zero,
                })
            })
            .collect()
    }
}
