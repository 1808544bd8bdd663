//! The typed key of an environment probe's faces, [`ProbeFacesKey`]
//! (`environment/environment_probe.wgsl`). It declares its shader file (`shader_file!`), so no
//! table below the effects names it; `environment/probe/faces.rs` uses it.

use crate::shaders::permutation::Permutation;

/// `environment/environment_probe.wgsl`'s permutations: how a layer's Color
/// Texture reaches the probe's faces (one pipeline per kind of layer).
///
/// The string rules this key replaced also allowed `COLOR_MAP` alone, which
/// no probe built; it compiles as [`ProbeFacesKey::Texcoords`] does (the
/// shader samples by UVs unless `TRIPLANAR`), so the key has three values
/// of the rules' four.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ProbeFacesKey {
    /// No Color Texture: the instances' colours alone.
    Plain,
    /// The Color Texture by the mesh's UVs.
    Texcoords,
    /// The Color Texture by three planar projections (and a uniform of their sharpness).
    Triplanar,
}

impl Permutation for ProbeFacesKey {
    crate::shader_file!("environment/environment_probe.wgsl");
    const FEATURES: &'static [&'static str] = &["COLOR_MAP", "TEXCOORDS", "TRIPLANAR"];

    fn features(self) -> impl Iterator<Item = &'static str> {
        let on: &[&'static str] = match self {
            ProbeFacesKey::Plain => &[],
            ProbeFacesKey::Texcoords => &["COLOR_MAP", "TEXCOORDS"],
            ProbeFacesKey::Triplanar => &["COLOR_MAP", "TRIPLANAR"],
        };
        on.iter().copied()
    }

    fn all() -> Vec<Self> {
        vec![
            ProbeFacesKey::Plain,
            ProbeFacesKey::Texcoords,
            ProbeFacesKey::Triplanar,
        ]
    }
}
