//! `lighting/cook_torrance.wgsl`'s permutations as a type, [`CookTorranceKey`]:
//! what the string rules said is its shape. Suns have no range to cluster
//! by, so only point and spot lights choose a walk, and only spots project
//! textures ([`Lights`]); a light shader node's function replaces the BRDF
//! and its extras (energy compensation, FakeSSS, clear coat), and the
//! extras read the material buffer ([`Shading`]); a shadow filter is a kind
//! of shadows ([`ShadowSampling`]). `CookTorrance` and the light shader
//! node's check (`shader_nodes/light.rs`) both build it; it declares its
//! shader file (`shader_file!`) and imports no pass.

use crate::light_kind::LightKind;
use crate::shaders::permutation::Permutation;
use crate::shadows::filter::ShadowFilter;

/// One permutation of the light loop.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct CookTorranceKey {
    pub lights: Lights,
    pub shading: Shading,
    pub shadows: Option<ShadowSampling>,
    /// Roughness and metallic where the G-buffer resolved them (its surface target).
    pub surface_target: bool,
}

/// The walk a recipe does, `LightLoop` resolved for its lights and adapter.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Walk {
    Clustered,
    Tiled,
    PerPixel,
    Naive,
}

impl Walk {
    /// Whether the walk reads froxel lists (and so needs the light assignment).
    pub fn uses_froxels(self) -> bool {
        self != Walk::Naive
    }

    /// Whether Light Merge may apply: the walks whose pixels read their
    /// own froxel's list (the naive walk reads every light, and the tiled
    /// one culls by depth bins that a band does not follow).
    pub fn merges(self) -> bool {
        matches!(self, Walk::Clustered | Walk::PerPixel)
    }

    const ALL: [Walk; 4] = [Walk::Naive, Walk::Clustered, Walk::Tiled, Walk::PerPixel];

    fn features(self) -> impl Iterator<Item = &'static str> {
        let other = match self {
            Walk::Tiled => Some("TILED"),
            Walk::PerPixel => Some("PER_PIXEL"),
            Walk::Clustered | Walk::Naive => None,
        };
        // The other walks of the froxel lists are CLUSTERED walked another way.
        self.uses_froxels()
            .then_some("CLUSTERED")
            .into_iter()
            .chain(other)
    }
}

/// The light type of the buffer and how the loop finds its lights.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Lights {
    Point(Walk),
    /// Point lights with Light Merge (MERGED): each pixel keeps, of a
    /// cube's members and their merged light, the side of the band it lies
    /// on. Only the walks that read a pixel's own froxel list merge
    /// ([`Walk::merges`]).
    PointMerged(Walk),
    Spot {
        walk: Walk,
        /// Spots projecting texture layers.
        textured: bool,
    },
    /// Every sun for every pixel.
    Sun,
}

impl Lights {
    /// A buffer of `kind` walked by `walk` (suns always walk every light),
    /// with spot textures `textured` (spots only).
    pub fn new(kind: LightKind, walk: Walk, textured: bool) -> Self {
        match kind {
            LightKind::Point => Lights::Point(walk),
            LightKind::Spot => Lights::Spot { walk, textured },
            LightKind::Sun => Lights::Sun,
        }
    }

    fn features(self) -> impl Iterator<Item = &'static str> {
        let (kind, walk, textured) = match self {
            Lights::Point(walk) => (None, walk, false),
            Lights::PointMerged(walk) => (Some("MERGED"), walk, false),
            Lights::Spot { walk, textured } => (Some("LIGHT_SPOT"), walk, textured),
            Lights::Sun => (Some("LIGHT_SUN"), Walk::Naive, false),
        };
        kind.into_iter()
            .chain(walk.features())
            .chain(textured.then_some("SPOT_TEXTURE"))
    }

    fn all() -> Vec<Lights> {
        let mut all: Vec<Lights> = Walk::ALL.into_iter().map(Lights::Point).collect();
        all.extend(
            Walk::ALL
                .into_iter()
                .filter(|w| w.merges())
                .map(Lights::PointMerged),
        );
        for walk in Walk::ALL {
            for textured in [false, true] {
                all.push(Lights::Spot { walk, textured });
            }
        }
        all.push(Lights::Sun);
        all
    }
}

/// What a lit pixel's light is computed by.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Shading {
    /// The built-in Cook-Torrance BRDF.
    Brdf {
        energy_compensation: bool,
        materials: Option<BrdfMaterials>,
    },
    /// A light shader node's `light` function in place of the BRDF.
    Custom { materials: Option<MaterialReads> },
}

/// The material buffer read by the built-in BRDF (MATERIALS).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct BrdfMaterials {
    pub reads: MaterialReads,
    /// Some material has FakeSSS: the subsurface term is written.
    pub fake_sss: bool,
    /// Some material has a clear coat: its lobe is compiled in.
    pub clearcoat: bool,
    /// Some surface-mapped material has the Anisotropy feature: the
    /// G-buffer's anisotropy target is read and the anisotropic lobe
    /// compiled in (ANISOTROPY; only with the surface target, which every
    /// G-buffer with surface maps has).
    pub anisotropy: bool,
    /// Some material has a thin film (Iridescence): its Fresnel is
    /// compiled in (`spreadlight::iridescence`).
    pub iridescence: bool,
    /// Some material has a sheen: its lobe is compiled in.
    pub sheen: bool,
}

/// The material buffer (MATERIALS), and whether some material's
/// parameters read its texture array (MATERIAL_TEXTURES).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct MaterialReads {
    pub textures: bool,
}

impl MaterialReads {
    fn features(self) -> impl Iterator<Item = &'static str> {
        std::iter::once("MATERIALS").chain(self.textures.then_some("MATERIAL_TEXTURES"))
    }
}

impl Shading {
    fn features(self) -> impl Iterator<Item = &'static str> {
        let mut f: Vec<&'static str> = Vec::with_capacity(6);
        match self {
            Shading::Brdf {
                energy_compensation,
                materials,
            } => {
                f.extend(energy_compensation.then_some("ENERGY_COMPENSATION"));
                if let Some(m) = materials {
                    f.extend(m.reads.features());
                    f.extend(m.fake_sss.then_some("FAKE_SSS"));
                    f.extend(m.clearcoat.then_some("CLEARCOAT"));
                    f.extend(m.anisotropy.then_some("ANISOTROPY"));
                    f.extend(m.iridescence.then_some("IRIDESCENCE"));
                    f.extend(m.sheen.then_some("SHEEN"));
                }
            }
            Shading::Custom { materials } => {
                f.push("CUSTOM_LIGHT");
                f.extend(materials.into_iter().flat_map(MaterialReads::features));
            }
        }
        f.into_iter()
    }

    fn all() -> Vec<Shading> {
        let reads = [false, true].map(|textures| MaterialReads { textures });
        let mut brdf_materials = vec![None];
        for reads in reads {
            for fake_sss in [false, true] {
                for clearcoat in [false, true] {
                    for anisotropy in [false, true] {
                        for iridescence in [false, true] {
                            for sheen in [false, true] {
                                brdf_materials.push(Some(BrdfMaterials {
                                    reads,
                                    fake_sss,
                                    clearcoat,
                                    anisotropy,
                                    iridescence,
                                    sheen,
                                }));
                            }
                        }
                    }
                }
            }
        }
        let mut all = Vec::new();
        for energy_compensation in [false, true] {
            for &materials in &brdf_materials {
                all.push(Shading::Brdf {
                    energy_compensation,
                    materials,
                });
            }
        }
        all.push(Shading::Custom { materials: None });
        all.extend(reads.map(|r| Shading::Custom { materials: Some(r) }));
        all
    }
}

/// The shadow filter compiled in: `ShadowFilter` without its settings
/// (SHADOWS alone samples raw; the others choose a filter).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ShadowSampling {
    Raw,
    Pcf,
    Pcss,
    Vsm,
}

impl ShadowSampling {
    pub fn of(filter: ShadowFilter) -> Self {
        match filter {
            ShadowFilter::Raw => ShadowSampling::Raw,
            ShadowFilter::Pcf { .. } => ShadowSampling::Pcf,
            ShadowFilter::Pcss { .. } => ShadowSampling::Pcss,
            ShadowFilter::Vsm { .. } => ShadowSampling::Vsm,
        }
    }

    fn features(self) -> impl Iterator<Item = &'static str> {
        let filter = match self {
            ShadowSampling::Raw => None,
            ShadowSampling::Pcf => Some("SHADOW_PCF"),
            ShadowSampling::Pcss => Some("SHADOW_PCSS"),
            ShadowSampling::Vsm => Some("SHADOW_VSM"),
        };
        std::iter::once("SHADOWS").chain(filter)
    }

    const ALL: [Option<ShadowSampling>; 5] = [
        None,
        Some(ShadowSampling::Raw),
        Some(ShadowSampling::Pcf),
        Some(ShadowSampling::Pcss),
        Some(ShadowSampling::Vsm),
    ];
}

/// The library a light shader node's file takes the place of in the light
/// loop's `CUSTOM_LIGHT` permutations (the shader-node compiler splices it).
pub const LIGHT_MODULE: &str = "spreadlight::custom_light";

/// The group a light shader node's own bindings are in (group 0 is the
/// light loop's, group 1 the material world's).
pub const LIGHT_GROUP: u32 = 2;

impl CookTorranceKey {
    /// The light loop a light shader node of `kind` is checked against
    /// (`shader_nodes/light.rs`): its own function, nothing else the scene
    /// may add (what the scene adds composes the same function).
    pub fn custom_light(kind: LightKind) -> Self {
        CookTorranceKey {
            lights: Lights::new(kind, Walk::Naive, false),
            shading: Shading::Custom { materials: None },
            shadows: None,
            surface_target: false,
        }
    }
}

impl Permutation for CookTorranceKey {
    crate::shader_file!("lighting/cook_torrance.wgsl");
    const FEATURES: &'static [&'static str] = &[
        "CLUSTERED",
        "ENERGY_COMPENSATION",
        "LIGHT_SPOT",
        "LIGHT_SUN",
        "MATERIALS",
        "FAKE_SSS",
        "SPOT_TEXTURE",
        "MATERIAL_TEXTURES",
        "SHADOWS",
        "SHADOW_PCF",
        "SHADOW_PCSS",
        "SHADOW_VSM",
        "SURFACE_TARGET",
        "CLEARCOAT",
        "IRIDESCENCE",
        "SHEEN",
        "CUSTOM_LIGHT",
        "TILED",
        "PER_PIXEL",
        "ANISOTROPY",
        "MERGED",
    ];

    fn features(self) -> impl Iterator<Item = &'static str> {
        self.lights
            .features()
            .chain(self.shading.features())
            .chain(self.shadows.into_iter().flat_map(ShadowSampling::features))
            .chain(self.surface_target.then_some("SURFACE_TARGET"))
    }

    /// 15 light walks x 5 shadow samplings x (69 shadings x 2, and the 64
    /// anisotropic ones with the surface target): the 15,150 feature sets
    /// the string rules allow (13,130 before Light Merge's two walks; 2,730
    /// before ANISOTROPY, IRIDESCENCE and SHEEN each doubled the built-in
    /// BRDF's material shadings: 2 x 16 + 1 per energy compensation, and as
    /// many anisotropic ones; the 3 custom ones unchanged).
    fn all() -> Vec<Self> {
        let mut all = Vec::new();
        for lights in Lights::all() {
            for shading in Shading::all() {
                let anisotropic = matches!(
                    shading,
                    Shading::Brdf {
                        materials: Some(BrdfMaterials {
                            anisotropy: true,
                            ..
                        }),
                        ..
                    }
                );
                for shadows in ShadowSampling::ALL {
                    for surface_target in [false, true] {
                        if anisotropic && !surface_target {
                            continue;
                        }
                        all.push(CookTorranceKey {
                            lights,
                            shading,
                            shadows,
                            surface_target,
                        });
                    }
                }
            }
        }
        all
    }
}
