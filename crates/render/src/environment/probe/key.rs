//! The typed key of an environment probe's faces, [`ProbeFacesKey`]
//! (`environment/environment_probe.wgsl`). It declares its shader file (`shader_file!`), so no
//! table below the effects names it; `environment/probe/faces.rs` uses it.

use crate::shaders::permutation::Permutation;
use crate::shadows::ShadowKey;

/// `environment/environment_probe.wgsl`'s permutations: how a layer's
/// surface reaches the probe's faces (one pipeline per kind of layer), and
/// which pass draws it: the base (ambient, the probe's sun and its shadow)
/// or a light buffer's.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ProbeFacesKey {
    /// How the layer's textures are mapped; [`ProbeUv::None`] only for a
    /// layer with neither texture (and for glTF surface maps, which carry their own).
    pub uv: ProbeUv,
    /// The Color Texture scales the instance colour (COLOR_MAP).
    pub color_map: bool,
    /// The Normal Map perturbs the normal (NORMAL_MAP), as the G-buffer resolve does.
    pub normal_map: bool,
    /// A glTF layer's surface maps (MATERIAL_MAPS; never with the layer's own textures).
    pub surface_maps: bool,
    pub pass: ProbePass,
    /// The material extensions' lobes a light pass over surface maps draws
    /// (none for any other pass: the probe's sun and ambient light the
    /// diffuse alone).
    pub lobes: ProbeLobes,
}

/// The material extensions' lobes on a probe's faces, each compiled only
/// for a layer whose world has such a material.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct ProbeLobes {
    /// The clear coat's lobe and the dimming under it (CLEARCOAT).
    pub coat: bool,
    /// The sheen's Charlie lobe and the dimming under it (SHEEN).
    pub sheen: bool,
    /// The specular lobe stretched along the anisotropy direction (ANISOTROPY).
    pub anisotropy: bool,
    /// The thin film's Fresnel (IRIDESCENCE).
    pub iridescence: bool,
}

impl ProbeLobes {
    /// Every set of lobes.
    fn all() -> impl Iterator<Item = ProbeLobes> {
        (0..16u8).map(|b| ProbeLobes {
            coat: b & 1 != 0,
            sheen: b & 2 != 0,
            anisotropy: b & 4 != 0,
            iridescence: b & 8 != 0,
        })
    }

    fn features(self) -> impl Iterator<Item = &'static str> {
        [
            (self.coat, "CLEARCOAT"),
            (self.sheen, "SHEEN"),
            (self.anisotropy, "ANISOTROPY"),
            (self.iridescence, "IRIDESCENCE"),
        ]
        .into_iter()
        .filter_map(|(on, name)| on.then_some(name))
    }
}

/// Which of a face's passes a pipeline draws.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ProbePass {
    /// The probe's ambient and sun; `sun_shadow`: shadowed by a ShadowMap
    /// (Sun)'s maps (SHADOWS, read with PCF: SHADOW_PCF).
    Base { sun_shadow: bool },
    /// A point or spot light buffer's light added (LIGHT_PASS; LIGHT_SPOT,
    /// SPOT_TEXTURE), shadowed by its ShadowMap's maps with their filter.
    Light {
        spot: bool,
        spot_texture: bool,
        shadows: ShadowKey,
    },
}

impl ProbePass {
    /// Every pass the node set can ask for.
    fn all() -> Vec<ProbePass> {
        let mut all = vec![
            ProbePass::Base { sun_shadow: false },
            ProbePass::Base { sun_shadow: true },
        ];
        for (spot, spot_texture) in [(false, false), (true, false), (true, true)] {
            for shadows in ShadowKey::ALL {
                all.push(ProbePass::Light {
                    spot,
                    spot_texture,
                    shadows,
                });
            }
        }
        all
    }

    fn features(self) -> Vec<&'static str> {
        match self {
            ProbePass::Base { sun_shadow: true } => vec!["SHADOWS", "SHADOW_PCF"],
            ProbePass::Base { sun_shadow: false } => Vec::new(),
            ProbePass::Light {
                spot,
                spot_texture,
                shadows,
            } => std::iter::once("LIGHT_PASS")
                .chain(spot.then_some("LIGHT_SPOT"))
                .chain(spot_texture.then_some("SPOT_TEXTURE"))
                .chain(shadows.features())
                .collect(),
        }
    }
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
        "MATERIAL_MAPS",
        "SHADOWS",
        "SHADOW_PCF",
        "SHADOW_PCSS",
        "SHADOW_VSM",
        "LIGHT_PASS",
        "LIGHT_SPOT",
        "SPOT_TEXTURE",
        "CLEARCOAT",
        "SHEEN",
        "ANISOTROPY",
        "IRIDESCENCE",
    ];

    fn features(self) -> impl Iterator<Item = &'static str> {
        let uv = match self.uv {
            ProbeUv::None => None,
            ProbeUv::Texcoords => Some("TEXCOORDS"),
            ProbeUv::Triplanar => Some("TRIPLANAR"),
        };
        (self.color_map.then_some("COLOR_MAP"))
            .into_iter()
            .chain(self.normal_map.then_some("NORMAL_MAP"))
            .chain(uv)
            .chain(self.surface_maps.then_some("MATERIAL_MAPS"))
            .chain(self.pass.features())
            .chain(self.lobes.features())
    }

    /// A layer without textures, with a Color Texture, a Normal Map or
    /// both by either mapping, or with glTF surface maps; each in every
    /// pass; a light pass over surface maps with every set of lobes.
    fn all() -> Vec<Self> {
        let mut surfaces = vec![(ProbeUv::None, false, false, false)];
        for uv in [ProbeUv::Texcoords, ProbeUv::Triplanar] {
            for (color_map, normal_map) in [(true, false), (false, true), (true, true)] {
                surfaces.push((uv, color_map, normal_map, false));
            }
        }
        surfaces.push((ProbeUv::None, false, false, true));
        let mut all = Vec::new();
        for pass in ProbePass::all() {
            for &(uv, color_map, normal_map, surface_maps) in &surfaces {
                let lobed = surface_maps && matches!(pass, ProbePass::Light { .. });
                for lobes in ProbeLobes::all().filter(|l| lobed || *l == ProbeLobes::default()) {
                    all.push(ProbeFacesKey {
                        uv,
                        color_map,
                        normal_map,
                        surface_maps,
                        pass,
                        lobes,
                    });
                }
            }
        }
        all
    }
}
