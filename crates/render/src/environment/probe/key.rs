//! The typed key of an environment probe's faces, [`ProbeFacesKey`]
//! (`environment/environment_probe.wgsl`). It declares its shader file (`shader_file!`), so no
//! table below the effects names it; `environment/probe/faces.rs` uses it.

use crate::shaders::permutation::Permutation;

/// `environment/environment_probe.wgsl`'s permutations: how a layer's
/// Color Texture and Normal Map reach the probe's faces (one pipeline per
/// kind of layer), and whether the sun's shadow map darkens them.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ProbeFacesKey {
    /// How the layer's textures are mapped; [`ProbeUv::None`] only for a
    /// layer with neither texture.
    pub uv: ProbeUv,
    /// The Color Texture scales the instance colour (COLOR_MAP).
    pub color_map: bool,
    /// The Normal Map perturbs the normal (NORMAL_MAP), as the G-buffer resolve does.
    pub normal_map: bool,
    /// The sun's light is shadowed by a ShadowMap (Sun)'s maps (SHADOWS,
    /// read with PCF: SHADOW_PCF).
    pub sun_shadow: bool,
}

/// Where a probe face's texture coordinates come from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ProbeUv {
    None,
    /// The mesh's UVs (and tangents, for a normal map) (TEXCOORDS).
    Texcoords,
    /// Three planar projections blended by the normal (TRIPLANAR; a uniform of their sharpness).
    Triplanar,
}

impl Permutation for ProbeFacesKey {
    crate::shader_file!("environment/environment_probe.wgsl");
    const FEATURES: &'static [&'static str] = &[
        "COLOR_MAP",
        "NORMAL_MAP",
        "TEXCOORDS",
        "TRIPLANAR",
        "SHADOWS",
        "SHADOW_PCF",
    ];

    fn features(self) -> impl Iterator<Item = &'static str> {
        let uv = match self.uv {
            ProbeUv::None => None,
            ProbeUv::Texcoords => Some("TEXCOORDS"),
            ProbeUv::Triplanar => Some("TRIPLANAR"),
        };
        let shadow: &[&'static str] = if self.sun_shadow {
            &["SHADOWS", "SHADOW_PCF"]
        } else {
            &[]
        };
        (self.color_map.then_some("COLOR_MAP"))
            .into_iter()
            .chain(self.normal_map.then_some("NORMAL_MAP"))
            .chain(uv)
            .chain(shadow.iter().copied())
    }

    /// A layer without textures, or with a Color Texture, a Normal Map or
    /// both by either mapping; each with and without the sun's shadow.
    fn all() -> Vec<Self> {
        let mut textures = vec![(ProbeUv::None, false, false)];
        for uv in [ProbeUv::Texcoords, ProbeUv::Triplanar] {
            for (color_map, normal_map) in [(true, false), (false, true), (true, true)] {
                textures.push((uv, color_map, normal_map));
            }
        }
        let mut all = Vec::new();
        for sun_shadow in [false, true] {
            for &(uv, color_map, normal_map) in &textures {
                all.push(ProbeFacesKey {
                    uv,
                    color_map,
                    normal_map,
                    sun_shadow,
                });
            }
        }
        all
    }
}
