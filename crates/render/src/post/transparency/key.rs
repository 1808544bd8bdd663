//! `Transparency`'s permutations as types: what a layer's surface reads
//! (`SurfaceKey`) and which pass draws it (`TransparencyPass`: the unlit
//! base, or the lights of one buffer with its type, walk and shadow filter
//! compiled in). A light type no connected buffer has is never compiled,
//! and a combination the shader cannot serve cannot be written (a glTF
//! layer's surface maps and a DeferredBase layer's own maps are one choice:
//! `LayerMaps`; suns have no range to cluster by).

use crate::light_kind::LightKind;
use crate::shaders::permutation::Permutation;
pub use crate::shadows::ShadowKey;

/// One permutation of `post/transparency.wgsl`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct TransparencyKey {
    pub surface: SurfaceKey,
    pub pass: TransparencyPass,
    /// The clear coat (CLEARCOAT): a light pass of a layer whose world has
    /// a Clearcoat material adds the coat's lobe; a base pass of such a
    /// layer that records fragments writes their coat records, and one that
    /// reads the environment adds the coat's reflection of it; the compute
    /// shading of a node with a coated layer reads them. Never for the
    /// composite and resolve entry points, nor for a surface without a
    /// material world (it has no coat), nor a base pass that records nothing
    /// and reads no environment.
    pub coat: bool,
    /// The anisotropic lobe (ANISOTROPY): a forward light pass of a layer
    /// with surface maps whose world has an Anisotropy material stretches
    /// its fragments' highlights along the direction its tangents and
    /// anisotropy map give (`KHR_materials_anisotropy`); a recording base
    /// pass of such a layer writes each fragment's direction and strength,
    /// and the compute shading of a node with such a layer reads them. Never
    /// for a surface without surface maps, nor a base pass recording nothing.
    pub anisotropy: bool,
    /// The sheen and the thin film (SHEEN): a forward light pass of a layer
    /// whose world has a Sheen material adds the sheen's lobe and dims the
    /// base under it; a recording base pass of such a layer writes each
    /// fragment's sheen, and the compute shading of a node with such a layer
    /// reads them. A light pass of a layer whose world has an Iridescence
    /// material mixes the film's Fresnel into the specular and diffuse
    /// weights (one switch for both extension lobes, branched per material
    /// in the shader; the compute records keep no film, so a filmed layer
    /// shades forward under Auto). Only those passes of a surface with a
    /// material world.
    pub sheen: bool,
}

/// What a layer's fragments read.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct SurfaceKey {
    pub maps: LayerMaps,
    /// COLOR_0 and the second UV set (VERTEX_EXTRAS).
    pub vertex_extras: bool,
    /// Roughness, metallic, reflectance and emission from a material world
    /// (MATERIALS); surface maps always read one.
    pub materials: bool,
}

/// The textures a layer's surface samples.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum LayerMaps {
    None,
    /// A glTF material world's surface maps (MATERIAL_MAPS), with
    /// `extensions` its material extensions' maps too, specular and
    /// thickness (EXTENSION_MAPS: some material of the world has one).
    Surface {
        extensions: bool,
    },
    /// A DeferredBase layer's Color Texture and normal map, by its UVs or a
    /// planar projection.
    Layer {
        uv: LayerUv,
        color: bool,
        normal: bool,
    },
}

impl LayerMaps {
    /// A glTF material world's surface maps, with or without the extensions'.
    pub fn is_surface(self) -> bool {
        matches!(self, LayerMaps::Surface { .. })
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum LayerUv {
    Texcoords,
    Triplanar,
}

/// Which pass draws the layer.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum TransparencyPass {
    /// Alpha, revealage and the unlit colour (ambient, emission, the built-in
    /// key light, with `environment` the Environment's image-based light,
    /// and the layer's MatCap); without it, also the clear and the resolve.
    /// With `marks` (some light pass walks froxel lists) its fragments mark
    /// the froxels they lie in, the only ones the assignment fills
    /// (FROXEL_MARKS).
    /// With `transmission` (TRANSMISSION: the layer's world has a
    /// Transmission material, or the node's Transmission is on), what shows
    /// through is the opaque image sampled along the refracted ray, tinted
    /// and absorbed, instead of the straight blend.
    /// With `records` (the lights are shaded in compute: `compute.rs`), each
    /// fragment also stores what lighting it needs in its pixel's fragment
    /// list (FRAGMENT_RECORDS).
    Base {
        environment: bool,
        matcap: MatCapKey,
        marks: bool,
        transmission: RefractionKey,
        records: bool,
    },
    /// One light buffer's Cook-Torrance light, added to the colour.
    Light(LightKey),
    /// One light buffer's Cook-Torrance light on the fragment lists' records,
    /// in compute (COMPUTE_SHADE, with the light pass's switches); no surface.
    Shade(LightKey),
    /// `Shade` with each 8x8 tile sharing its froxels' lights through
    /// workgroup memory (SHADE_TILED, entry `shade_tiled`); clustered only.
    ShadeTiled(LightKey),
    /// The resolve that adds the compute-shaded light sums (LIGHT_SUMS); no surface.
    ShadedResolve,
}

/// A base pass's refraction: compiled only for a layer that transmits, its
/// blur the settings' (`RefractionBlur`, resolved).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum RefractionKey {
    /// The straight blend: no refraction code, the opaque image unbound.
    Off,
    /// The opaque image read by hand over the settings' taps (TRANSMISSION).
    Taps,
    /// One trilinear read of the opaque image's mip chain (TRANSMISSION,
    /// REFRACTION_MIPS): the chain is bound instead of the image.
    Mips,
}

impl RefractionKey {
    pub fn on(self) -> bool {
        self != RefractionKey::Off
    }

    fn features(self) -> impl Iterator<Item = &'static str> {
        self.on()
            .then_some("TRANSMISSION")
            .into_iter()
            .chain((self == RefractionKey::Mips).then_some("REFRACTION_MIPS"))
    }

    const ALL: [RefractionKey; 3] = [RefractionKey::Off, RefractionKey::Taps, RefractionKey::Mips];
}

/// A base pass's matcap: compiled only for a layer whose material world has
/// a MatCap material (and so only with MATERIALS).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum MatCapKey {
    Off,
    /// The built-in clay matcap (MATCAP).
    BuiltIn,
    /// Some MatCap material names an image of the world's texture array
    /// (MATCAP, MATCAP_TEXTURE).
    Images,
}

impl MatCapKey {
    fn features(self) -> impl Iterator<Item = &'static str> {
        let (on, images) = match self {
            MatCapKey::Off => (false, false),
            MatCapKey::BuiltIn => (true, false),
            MatCapKey::Images => (true, true),
        };
        on.then_some("MATCAP")
            .into_iter()
            .chain(images.then_some("MATCAP_TEXTURE"))
    }
}

/// A light pass: the buffer's type, how it finds its lights, its shadows.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct LightKey {
    pub kind: LightKind,
    /// The froxel lists of the clustered assignment (never for suns).
    pub clustered: bool,
    pub shadows: ShadowKey,
    /// Spots projecting texture layers.
    pub spot_texture: bool,
}

impl SurfaceKey {
    fn features(self) -> impl Iterator<Item = &'static str> {
        let mut f: Vec<&'static str> = Vec::new();
        match self.maps {
            LayerMaps::None => {}
            LayerMaps::Surface { extensions } => {
                f.push("MATERIAL_MAPS");
                f.extend(extensions.then_some("EXTENSION_MAPS"));
            }
            LayerMaps::Layer { uv, color, normal } => {
                f.push(match uv {
                    LayerUv::Texcoords => "TEXCOORDS",
                    LayerUv::Triplanar => "TRIPLANAR",
                });
                f.extend(color.then_some("COLOR_MAP"));
                f.extend(normal.then_some("NORMAL_MAP"));
            }
        }
        f.extend(self.reads_materials().then_some("MATERIALS"));
        f.extend(self.vertex_extras.then_some("VERTEX_EXTRAS"));
        f.into_iter()
    }

    /// Whether the surface reads a material world (MATERIALS): surface maps
    /// read the world's parameters too.
    pub fn reads_materials(self) -> bool {
        self.materials || self.maps.is_surface()
    }

    fn all() -> Vec<SurfaceKey> {
        let mut maps = vec![
            LayerMaps::None,
            LayerMaps::Surface { extensions: false },
            LayerMaps::Surface { extensions: true },
        ];
        for uv in [LayerUv::Texcoords, LayerUv::Triplanar] {
            for (color, normal) in [(true, false), (false, true), (true, true)] {
                maps.push(LayerMaps::Layer { uv, color, normal });
            }
        }
        let mut all = Vec::new();
        for maps in maps {
            for vertex_extras in [false, true] {
                // Surface maps always read the world: one permutation, not two.
                let worlds: &[bool] = if maps.is_surface() {
                    &[true]
                } else {
                    &[false, true]
                };
                for &materials in worlds {
                    all.push(SurfaceKey {
                        maps,
                        vertex_extras,
                        materials,
                    });
                }
            }
        }
        all
    }
}

impl LightKey {
    fn features(self) -> impl Iterator<Item = &'static str> {
        let kind = match self.kind {
            LightKind::Point => None,
            LightKind::Spot => Some("LIGHT_SPOT"),
            LightKind::Sun => Some("LIGHT_SUN"),
        };
        std::iter::once("LIGHT_PASS")
            .chain(kind)
            .chain(self.clustered.then_some("CLUSTERED"))
            .chain(self.clustered.then_some("FROXELS"))
            .chain(self.spot_texture.then_some("SPOT_TEXTURE"))
            .chain(self.shadows.features())
    }

    fn all() -> Vec<LightKey> {
        let mut all = Vec::new();
        for kind in [LightKind::Point, LightKind::Spot, LightKind::Sun] {
            let walks: &[bool] = if kind == LightKind::Sun {
                &[false]
            } else {
                &[false, true]
            };
            let textures: &[bool] = if kind == LightKind::Spot {
                &[false, true]
            } else {
                &[false]
            };
            for &clustered in walks {
                for &spot_texture in textures {
                    for shadows in ShadowKey::ALL {
                        all.push(LightKey {
                            kind,
                            clustered,
                            shadows,
                            spot_texture,
                        });
                    }
                }
            }
        }
        all
    }
}

impl Permutation for TransparencyKey {
    crate::shader_file!("post/transparency.wgsl");
    const FEATURES: &'static [&'static str] = &[
        "MATERIAL_MAPS",
        "EXTENSION_MAPS",
        "VERTEX_EXTRAS",
        "MATERIALS",
        "ENVIRONMENT",
        "MATCAP",
        "MATCAP_TEXTURE",
        "TEXCOORDS",
        "TRIPLANAR",
        "COLOR_MAP",
        "NORMAL_MAP",
        "LIGHT_PASS",
        "LIGHT_SPOT",
        "LIGHT_SUN",
        "CLUSTERED",
        "FROXELS",
        "FROXEL_MARKS",
        "SPOT_TEXTURE",
        "SHADOWS",
        "SHADOW_PCF",
        "SHADOW_PCSS",
        "SHADOW_VSM",
        "TRANSMISSION",
        "REFRACTION_MIPS",
        "FRAGMENT_RECORDS",
        "COMPUTE_SHADE",
        "LIGHT_SUMS",
        "SHADE_TILED",
        "CLEARCOAT",
        "ANISOTROPY",
        "SHEEN",
    ];

    fn features(self) -> impl Iterator<Item = &'static str> {
        let light: Vec<&'static str> = match self.pass {
            TransparencyPass::Base {
                environment,
                matcap,
                marks,
                transmission,
                records,
            } => environment
                .then_some("ENVIRONMENT")
                .into_iter()
                .chain(matcap.features())
                .chain(marks.then_some("FROXELS"))
                .chain(marks.then_some("FROXEL_MARKS"))
                .chain(transmission.features())
                .chain(records.then_some("FRAGMENT_RECORDS"))
                .collect(),
            TransparencyPass::Light(light) => light.features().collect(),
            TransparencyPass::Shade(light) => light
                .features()
                .chain(std::iter::once("COMPUTE_SHADE"))
                .collect(),
            TransparencyPass::ShadeTiled(light) => light
                .features()
                .chain(["COMPUTE_SHADE", "SHADE_TILED"])
                .collect(),
            TransparencyPass::ShadedResolve => vec!["LIGHT_SUMS"],
        };
        self.surface
            .features()
            .chain(light)
            .chain(self.coat.then_some("CLEARCOAT"))
            .chain(self.anisotropy.then_some("ANISOTROPY"))
            .chain(self.sheen.then_some("SHEEN"))
    }

    /// Every surface with the base passes (a matcap only with a material
    /// world; marking froxels or not; recording fragments or not), each
    /// without transmission and with either blur, and with every light pass;
    /// the compute shading of every light pass and its resolve, without a
    /// surface; each with the coat, the sheen and the anisotropic lobe where
    /// it can have them ([`TransparencyKey::coat`], `sheen`, `anisotropy`).
    /// The validation test composes each.
    fn all() -> Vec<Self> {
        let lights: Vec<TransparencyPass> = LightKey::all()
            .into_iter()
            .map(TransparencyPass::Light)
            .collect();
        SurfaceKey::all()
            .into_iter()
            .flat_map(|surface| {
                let matcaps: &[MatCapKey] = if surface.reads_materials() {
                    &[MatCapKey::Off, MatCapKey::BuiltIn, MatCapKey::Images]
                } else {
                    &[MatCapKey::Off]
                };
                let bases = [false, true].into_iter().flat_map(move |environment| {
                    matcaps.iter().flat_map(move |&matcap| {
                        [false, true].into_iter().flat_map(move |marks| {
                            RefractionKey::ALL
                                .into_iter()
                                .flat_map(move |transmission| {
                                    [false, true].map(|records| TransparencyPass::Base {
                                        environment,
                                        matcap,
                                        marks,
                                        transmission,
                                        records,
                                    })
                                })
                        })
                    })
                });
                let coated = surface.reads_materials();
                let anisotropic = surface.maps.is_surface();
                bases
                    .chain(lights.iter().copied())
                    .flat_map(move |pass| {
                        let coats = match pass {
                            TransparencyPass::Base {
                                records,
                                environment,
                                ..
                            } => coated && (records || environment),
                            _ => coated,
                        };
                        // The lobes' inputs are read by the light passes and
                        // the recording base passes.
                        let reads_lobes = matches!(
                            pass,
                            TransparencyPass::Light(_)
                                | TransparencyPass::Base { records: true, .. }
                        );
                        let stretches = anisotropic && reads_lobes;
                        let sheens = coated && reads_lobes;
                        [false, true]
                            .into_iter()
                            .filter(move |&coat| !coat || coats)
                            .flat_map(move |coat| {
                                [false, true]
                                    .into_iter()
                                    .filter(move |&anisotropy| !anisotropy || stretches)
                                    .flat_map(move |anisotropy| {
                                        [false, true]
                                            .into_iter()
                                            .filter(move |&sheen| !sheen || sheens)
                                            .map(move |sheen| TransparencyKey {
                                                surface,
                                                pass,
                                                coat,
                                                anisotropy,
                                                sheen,
                                            })
                                    })
                            })
                    })
                    .collect::<Vec<_>>()
            })
            .chain(
                LightKey::all()
                    .into_iter()
                    .flat_map(|light| {
                        let tiled = light
                            .clustered
                            .then_some(TransparencyPass::ShadeTiled(light));
                        std::iter::once(TransparencyPass::Shade(light)).chain(tiled)
                    })
                    .flat_map(|pass| {
                        // Every set of lobes some node's layers can have.
                        (0..8u8).map(move |lobes| TransparencyKey {
                            surface: Self::COMPOSITE.surface,
                            pass,
                            coat: lobes & 1 != 0,
                            anisotropy: lobes & 2 != 0,
                            sheen: lobes & 4 != 0,
                        })
                    })
                    .chain([TransparencyKey::SHADED_RESOLVE]),
            )
            .collect()
    }
}

impl TransparencyKey {
    /// The clear and resolve compute entry points: no surface, no lights.
    pub const COMPOSITE: TransparencyKey = TransparencyKey {
        surface: SurfaceKey {
            maps: LayerMaps::None,
            vertex_extras: false,
            materials: false,
        },
        pass: TransparencyPass::Base {
            environment: false,
            matcap: MatCapKey::Off,
            marks: false,
            transmission: RefractionKey::Off,
            records: false,
        },
        coat: false,
        anisotropy: false,
        sheen: false,
    };

    /// The resolve of a frame whose lights were shaded in compute.
    pub const SHADED_RESOLVE: TransparencyKey = TransparencyKey {
        surface: Self::COMPOSITE.surface,
        pass: TransparencyPass::ShadedResolve,
        coat: false,
        anisotropy: false,
        sheen: false,
    };
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn light_code_is_compiled_only_for_the_pass_that_calls_for_it() {
        let base = TransparencyKey::COMPOSITE;
        assert_eq!(base.features().count(), 0);
        let spot = TransparencyKey {
            pass: TransparencyPass::Light(LightKey {
                kind: LightKind::Spot,
                clustered: true,
                shadows: ShadowKey::Pcf,
                spot_texture: false,
            }),
            ..base
        };
        let features: Vec<_> = spot.features().collect();
        assert_eq!(
            features,
            [
                "LIGHT_PASS",
                "LIGHT_SPOT",
                "CLUSTERED",
                "FROXELS",
                "SHADOWS",
                "SHADOW_PCF"
            ]
        );
        // A base pass marks froxels only when a light pass walks their lists.
        let marking = TransparencyKey {
            pass: TransparencyPass::Base {
                environment: false,
                matcap: MatCapKey::Off,
                marks: true,
                transmission: RefractionKey::Off,
                records: false,
            },
            ..base
        };
        assert_eq!(
            marking.features().collect::<Vec<_>>(),
            ["FROXELS", "FROXEL_MARKS"]
        );
        // Refraction is a base-pass switch alone.
        let glass = TransparencyKey {
            pass: TransparencyPass::Base {
                environment: false,
                matcap: MatCapKey::Off,
                marks: false,
                transmission: RefractionKey::Taps,
                records: false,
            },
            ..base
        };
        assert_eq!(glass.features().collect::<Vec<_>>(), ["TRANSMISSION"]);
        // The mip chain's read is the same pass with the chain bound.
        let mips = TransparencyKey {
            pass: TransparencyPass::Base {
                environment: false,
                matcap: MatCapKey::Off,
                marks: false,
                transmission: RefractionKey::Mips,
                records: false,
            },
            ..base
        };
        assert_eq!(
            mips.features().collect::<Vec<_>>(),
            ["TRANSMISSION", "REFRACTION_MIPS"]
        );
        let all = TransparencyKey::all();
        assert!(all.contains(&glass) && all.contains(&mips));
        let keys: std::collections::HashSet<_> = all.iter().map(|k| k.key()).collect();
        assert_eq!(
            keys.len(),
            all.len(),
            "every permutation is a different shader"
        );
        // No sun is clustered, and only spots project textures.
        assert!(all.iter().all(|k| match k.pass {
            TransparencyPass::Light(l) =>
                !(l.kind == LightKind::Sun && l.clustered)
                    && (l.kind == LightKind::Spot || !l.spot_texture),
            _ => true,
        }));
        // Compute shading: the light pass's switches and its own entry, no surface.
        let shade = TransparencyKey {
            pass: TransparencyPass::Shade(LightKey {
                kind: LightKind::Point,
                clustered: true,
                shadows: ShadowKey::None,
                spot_texture: false,
            }),
            ..base
        };
        assert_eq!(
            shade.features().collect::<Vec<_>>(),
            ["LIGHT_PASS", "CLUSTERED", "FROXELS", "COMPUTE_SHADE"]
        );
        assert!(all.contains(&shade) && all.contains(&TransparencyKey::SHADED_RESOLVE));
        // The coat: compiled for the light passes and the recording or
        // environment-reading base passes of surfaces with a material world,
        // and for compute shading.
        let coated_shade = TransparencyKey {
            coat: true,
            sheen: false,
            ..shade
        };
        assert!(all.contains(&coated_shade));
        assert_eq!(coated_shade.features().last(), Some("CLEARCOAT"));
        // The sheen: light and recording base passes of surfaces with a
        // material world, and compute shading; the anisotropic lobe the
        // same over surface maps.
        assert!(all.iter().any(|k| k.sheen) && all.iter().any(|k| k.anisotropy));
        for (lobe, surface_ok) in [
            (
                (|k: &TransparencyKey| k.sheen) as fn(&TransparencyKey) -> bool,
                (|s: SurfaceKey| s.reads_materials()) as fn(SurfaceKey) -> bool,
            ),
            (|k| k.anisotropy, |s| s.maps.is_surface()),
        ] {
            assert!(all.iter().filter(|k| lobe(k)).all(|k| match k.pass {
                TransparencyPass::Light(_) | TransparencyPass::Base { records: true, .. } =>
                    surface_ok(k.surface),
                TransparencyPass::Shade(_) | TransparencyPass::ShadeTiled(_) => true,
                _ => false,
            }));
        }
        let lobed_shade = TransparencyKey {
            coat: true,
            sheen: true,
            anisotropy: true,
            ..shade
        };
        assert!(all.contains(&lobed_shade));
        assert_eq!(
            lobed_shade.features().collect::<Vec<_>>(),
            [
                "LIGHT_PASS",
                "CLUSTERED",
                "FROXELS",
                "COMPUTE_SHADE",
                "CLEARCOAT",
                "ANISOTROPY",
                "SHEEN"
            ]
        );
        assert!(all.iter().filter(|k| k.coat).all(|k| match k.pass {
            TransparencyPass::Base {
                records,
                environment,
                ..
            } => (records || environment) && k.surface.reads_materials(),
            TransparencyPass::Light(_) => k.surface.reads_materials(),
            TransparencyPass::Shade(_) | TransparencyPass::ShadeTiled(_) => true,
            TransparencyPass::ShadedResolve => false,
        }));
        assert!(!all.contains(&TransparencyKey {
            coat: true,
            sheen: false,
            ..TransparencyKey::COMPOSITE
        }));
    }
}
