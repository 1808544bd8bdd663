//! Material features: what a bit of a material's flag word switches on, and
//! the parameters it reads. Feature id `n` is flag `1 << n` (Emeshe's
//! convention: the id is the exponent, the flag the power of two). Ids 0..16
//! belong to built-in features (0..=12 but 6 exist now; 13..=15 are kept for
//! the ones to come), 16..=31 are free for custom features.
//!
//! Mirrored by the `FEATURE_*` constants of `shaders/lib/material.wgsl`.

use super::FeatureError;

pub const FEATURE_COOK_TORRANCE: u32 = 0;
pub const FEATURE_EMISSION: u32 = 1;
pub const FEATURE_FAKE_SSS: u32 = 2;
pub const FEATURE_REFLECTION: u32 = 3;
pub const FEATURE_MATCAP: u32 = 4;
pub const FEATURE_AMBIENT_OCCLUSION: u32 = 5;
/// A glTF material's maps (`maps::SurfaceMaps`): set with
/// `Material::set_maps`, not as a [`Feature`], since its parameters are
/// texture places the world assigns when it packs.
pub const FEATURE_SURFACE_MAPS: u32 = 6;
/// A clear lacquer over the surface (glTF's `KHR_materials_clearcoat`).
pub const FEATURE_CLEARCOAT: u32 = 7;
/// Shown as its albedo, unlit (glTF's `KHR_materials_unlit`).
pub const FEATURE_UNLIT: u32 = 8;
/// Light through the surface, refracted (glTF's `KHR_materials_transmission`
/// with `KHR_materials_ior` and `KHR_materials_volume`): drawn by lit
/// transparency, which samples the opaque image along the refracted ray.
pub const FEATURE_TRANSMISSION: u32 = 9;
/// A thin film over the surface (glTF's `KHR_materials_iridescence`): its
/// interference colours replace Schlick's Fresnel in the specular lobes.
pub const FEATURE_IRIDESCENCE: u32 = 11;
/// A specular highlight stretched along a direction on the surface
/// (glTF's `KHR_materials_anisotropy`): strength and rotation.
pub const FEATURE_ANISOTROPY: u32 = 12;
/// A velvet-like sheen over the surface (glTF's `KHR_materials_sheen`):
/// CookTorrance's `SHEEN` lobe, Reflection's and lit transparency's.
pub const FEATURE_SHEEN: u32 = 10;
/// The first id free for custom features.
pub const FIRST_CUSTOM_FEATURE: u32 = 16;
/// One bit of a `u32` per feature.
pub const MAX_FEATURES: u32 = 32;

/// How a parameter component is kept physical: clamped into its range.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Range {
    /// 0..=1: roughness, metallic, reflectance.
    Unit,
    /// >= 0: strengths and colours.
    NonNegative,
    /// Read by nothing; stored as 0 so equal settings pack equally.
    Unused,
    /// Any finite value (custom features: their shader knows the meaning).
    Free,
}

/// The parameter layout of a built-in feature: one vec4, named and ranged per component.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ParamLayout {
    pub names: [&'static str; 4],
    pub ranges: [Range; 4],
    pub default: [f32; 4],
}

use Range::{NonNegative, Unit, Unused};

const COOK_TORRANCE: ParamLayout = ParamLayout {
    names: ["roughness", "metallic", "reflectance", ""],
    ranges: [Unit, Unit, Unit, Unused],
    // 0.04: the f0 of common dielectrics (index of refraction about 1.5).
    default: [0.5, 0.0, 0.04, 0.0],
};
const COLOR_STRENGTH: [Range; 4] = [NonNegative, NonNegative, NonNegative, NonNegative];
const EMISSION: ParamLayout = ParamLayout {
    names: ["red", "green", "blue", "strength"],
    ranges: COLOR_STRENGTH,
    default: [1.0, 1.0, 1.0, 1.0],
};
const FAKE_SSS: ParamLayout = ParamLayout {
    names: ["red", "green", "blue", "strength"],
    ranges: COLOR_STRENGTH,
    default: [1.0, 0.2, 0.1, 1.0],
};
/// A weight of a screen-space input, 0..1 (CompositeLight mixes by it).
const STRENGTH: ParamLayout = ParamLayout {
    names: ["strength", "", "", ""],
    ranges: [Unit, Unused, Unused, Unused],
    default: [1.0, 0.0, 0.0, 0.0],
};
/// A second, colourless GGX lobe over the base (f0 0.04, index of
/// refraction 1.5): how much of it (the coat's coverage) and its roughness.
const CLEARCOAT: ParamLayout = ParamLayout {
    names: ["factor", "roughness", "", ""],
    ranges: [Unit, Unit, Unused, Unused],
    default: [1.0, 0.0, 0.0, 0.0],
};
/// The anisotropic GGX lobe (`KHR_materials_anisotropy`): how much the
/// highlight stretches (0..1: the width along the direction is
/// mix(alpha, 1, strength²)) and the direction's rotation from the tangent
/// (radians, counter-clockwise; any finite angle).
const ANISOTROPY: ParamLayout = ParamLayout {
    names: ["strength", "rotation", "", ""],
    ranges: [Unit, Range::Free, Unused, Unused],
    default: [0.0, 0.0, 0.0, 0.0],
};
/// The sheen's colour (each channel 0..1: glTF's sheenColorFactor, linear)
/// and its roughness (0..1): the Charlie lobe's tint and width.
const SHEEN: ParamLayout = ParamLayout {
    names: ["red", "green", "blue", "roughness"],
    ranges: [Unit, Unit, Unit, Unit],
    default: [1.0, 1.0, 1.0, 0.5],
};
/// Two vec4s ([`transmission_params`]): how much of what shows through is
/// refracted (0..1), the index of refraction and the volume's thickness
/// (world units, 0: thin-walled); then the volume's absorption coefficient
/// per channel (1 / world unit, Beer-Lambert) and its dispersion
/// (`KHR_materials_dispersion`, 20 / the Abbe number; 0: none). Every
/// component is kept non-negative (the coefficients are unbounded, so the
/// factor's 0..1 is the shader's clamp); the first vec4's fourth is 0.
const TRANSMISSION: ParamLayout = ParamLayout {
    names: ["factor", "ior", "thickness", ""],
    ranges: [NonNegative, NonNegative, NonNegative, NonNegative],
    default: [1.0, 1.5, 0.0, 0.0],
};

/// A thin dielectric film over the surface: how much of the surface it
/// covers (the factor, 0..1), its index of refraction and its thickness's
/// minimum and maximum in nanometres (a thickness map picks between them;
/// without one the film is the maximum thick). The shaders keep the index
/// at 1 or more, and a film of no thickness has no factor.
const IRIDESCENCE: ParamLayout = ParamLayout {
    names: ["factor", "ior", "thickness minimum", "thickness maximum"],
    ranges: [Unit, NonNegative, NonNegative, NonNegative],
    default: [1.0, 1.3, 100.0, 400.0],
};

/// The largest absorption coefficient kept (1 / world unit): a black
/// attenuation colour absorbs everything within a millionth of a unit, and
/// the coefficient stays finite.
pub const MAX_ABSORPTION: f32 = 1e6;

/// The Transmission feature's two vec4s: `factor` (0..1) of what shows
/// through refracted with index `ior` through a volume `thickness` deep,
/// absorbing as `attenuation_color` after `attenuation_distance` (glTF's
/// `KHR_materials_volume`; infinite or white: nothing). Every input made
/// finite: a NaN or non-positive ior is 1 (no bend), a NaN or infinite
/// thickness 0 (thin-walled), a black channel [`MAX_ABSORPTION`]; a NaN,
/// infinite or negative `dispersion` 0 (red, green and blue refract alike).
pub fn transmission_params(
    factor: f32,
    ior: f32,
    thickness: f32,
    attenuation_color: [f32; 3],
    attenuation_distance: f32,
    dispersion: f32,
) -> [[f32; 4]; 2] {
    let factor = if factor.is_finite() {
        factor.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let ior = if ior.is_finite() && ior > 0.0 {
        ior
    } else {
        1.0
    };
    let thickness = if thickness.is_finite() {
        thickness.max(0.0)
    } else {
        0.0
    };
    let d = attenuation_distance;
    let sigma = attenuation_color.map(|c| {
        // sigma = -ln(c) / d: none for no distance, an infinite one or white.
        let no_distance = d.is_nan() || d <= 0.0 || d == f32::INFINITY;
        if no_distance || !c.is_finite() || c >= 1.0 {
            0.0
        } else if c <= 0.0 {
            MAX_ABSORPTION
        } else {
            (-c.ln() / d).clamp(0.0, MAX_ABSORPTION)
        }
    });
    // KHR_materials_dispersion: red and blue refract by ior -/+ (ior - 1) x
    // dispersion / 40 (lit transparency's `transmitted`).
    let dispersion = if dispersion.is_finite() {
        dispersion.max(0.0)
    } else {
        0.0
    };
    [
        [factor, ior, thickness, 0.0],
        [sigma[0], sigma[1], sigma[2], dispersion],
    ]
}

/// Strength, then two switches kept as 0 or 1 ([`MatCapMode`], [`MatCapMapping`]).
const MATCAP: ParamLayout = ParamLayout {
    names: ["strength", "mode", "mapping", ""],
    ranges: [NonNegative, Unit, Unit, Unused],
    default: [1.0, 0.0, 0.0, 0.0],
};

/// What a matcap does with the colour it looks up.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum MatCapMode {
    /// The matcap is light tinted by the surface: matcap x albedo.
    #[default]
    Multiply,
    /// The matcap's colour is added as light, untinted.
    Add,
}

/// How a pixel finds its place on the matcap image.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum MatCapMapping {
    /// By the view-space normal (ZBrush's matcaps).
    #[default]
    Normal,
    /// By the view vector reflected about the normal (classic sphere mapping):
    /// the image slides over the surface as the camera moves, like a reflection.
    Reflected,
}

/// The MatCap feature's one vec4: strength, mode and mapping as the shader reads them
/// (`shaders/lib/matcap.wgsl`).
pub fn matcap_params(strength: f32, mode: MatCapMode, mapping: MatCapMapping) -> [f32; 4] {
    let switch = |on: bool| if on { 1.0 } else { 0.0 };
    [
        strength,
        switch(mode == MatCapMode::Add),
        switch(mapping == MatCapMapping::Reflected),
        0.0,
    ]
}

/// A feature a material can have.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Feature {
    /// GGX specular and Lambert diffuse: roughness, metallic, reflectance (f0 of dielectrics).
    CookTorrance,
    /// Light the surface emits: rgb colour, strength.
    Emission,
    /// Faked subsurface scattering: rgb scatter colour, strength.
    FakeSss,
    /// Environment reflection: strength.
    Reflection,
    /// Matcap shading: strength, mode, mapping ([`matcap_params`]). Its
    /// texture layer is the matcap image itself, looked up by the normal;
    /// without one, a neutral built-in matcap.
    MatCap,
    /// Screen-space ambient occlusion: strength.
    AmbientOcclusion,
    /// A clear coat over the base layer: factor (coverage, 0..1), roughness.
    /// CookTorrance adds its specular lobe and dims the base by the coat's
    /// Fresnel reflectance (`CLEARCOAT`).
    Clearcoat,
    /// Unlit: CompositeLight shows the pixel's albedo, mixed over the lit
    /// colour by strength (1: albedo alone; compiled with `EMISSION`).
    Unlit,
    /// Refracted transmission: two vec4s ([`transmission_params`]). Lit
    /// transparency draws what shows through a layer of such a material as
    /// the opaque image along the refracted ray, tinted and absorbed.
    Transmission,
    /// A thin film (soap bubble, oil slick): factor, film ior, thickness
    /// minimum and maximum (nm). Its Fresnel reflectance (Belcour & Barla,
    /// `spreadlight::iridescence`) replaces Schlick's in CookTorrance's
    /// lobes and Reflection's, mixed by the factor (`IRIDESCENCE`).
    Iridescence,
    /// An anisotropic specular lobe: strength (0..1), rotation (radians).
    /// The G-buffer resolve turns the surface's tangent by the rotation and
    /// the material's anisotropy map into a direction per pixel (its own
    /// target, `ANISOTROPY`), along which CookTorrance stretches the
    /// highlight.
    Anisotropy,
    /// A sheen (glTF's `KHR_materials_sheen`): rgb colour, roughness.
    /// CookTorrance adds its Charlie lobe and dims the base by
    /// 1 - max(colour) x its albedo (`SHEEN`).
    Sheen,
    /// A user feature, id 16..=31, with as many vec4 parameters as it is given.
    Custom(u32),
}

impl Feature {
    /// In ascending id (6, SurfaceMaps, is set through `Material::set_maps`).
    pub const BUILT_IN: [Feature; 12] = [
        Feature::CookTorrance,
        Feature::Emission,
        Feature::FakeSss,
        Feature::Reflection,
        Feature::MatCap,
        Feature::AmbientOcclusion,
        Feature::Clearcoat,
        Feature::Unlit,
        Feature::Transmission,
        Feature::Sheen,
        Feature::Iridescence,
        Feature::Anisotropy,
    ];

    /// The feature with id `id`: a built-in one, or a custom one for 16..=31.
    /// Id 6 is SurfaceMaps (not set as a feature); 13..=15 are reserved for built-ins to come.
    pub fn from_id(id: i64) -> Result<Feature, FeatureError> {
        if let Some(f) = Feature::BUILT_IN.iter().find(|f| i64::from(f.id()) == id) {
            return Ok(*f);
        }
        match u32::try_from(id) {
            Ok(id) if (FIRST_CUSTOM_FEATURE..MAX_FEATURES).contains(&id) => Ok(Feature::Custom(id)),
            _ => Err(FeatureError::UnknownFeature { id }),
        }
    }

    pub fn id(self) -> u32 {
        match self {
            Feature::CookTorrance => FEATURE_COOK_TORRANCE,
            Feature::Emission => FEATURE_EMISSION,
            Feature::FakeSss => FEATURE_FAKE_SSS,
            Feature::Reflection => FEATURE_REFLECTION,
            Feature::MatCap => FEATURE_MATCAP,
            Feature::AmbientOcclusion => FEATURE_AMBIENT_OCCLUSION,
            Feature::Clearcoat => FEATURE_CLEARCOAT,
            Feature::Unlit => FEATURE_UNLIT,
            Feature::Transmission => FEATURE_TRANSMISSION,
            Feature::Iridescence => FEATURE_IRIDESCENCE,
            Feature::Anisotropy => FEATURE_ANISOTROPY,
            Feature::Sheen => FEATURE_SHEEN,
            Feature::Custom(id) => id,
        }
    }

    /// The bit of the flag word: `1 << id`.
    pub fn flag(self) -> u32 {
        1 << self.id()
    }

    pub fn name(self) -> String {
        match self {
            Feature::CookTorrance => "CookTorrance".to_owned(),
            Feature::Emission => "Emission".to_owned(),
            Feature::FakeSss => "FakeSSS".to_owned(),
            Feature::Reflection => "Reflection".to_owned(),
            Feature::MatCap => "MatCap".to_owned(),
            Feature::AmbientOcclusion => "AmbientOcclusion".to_owned(),
            Feature::Clearcoat => "Clearcoat".to_owned(),
            Feature::Unlit => "Unlit".to_owned(),
            Feature::Transmission => "Transmission".to_owned(),
            Feature::Iridescence => "Iridescence".to_owned(),
            Feature::Anisotropy => "Anisotropy".to_owned(),
            Feature::Sheen => "Sheen".to_owned(),
            Feature::Custom(id) => format!("Custom{id}"),
        }
    }

    /// The layout of a built-in feature's vec4 (each of Transmission's two);
    /// `None` for custom features.
    pub fn layout(self) -> Option<&'static ParamLayout> {
        match self {
            Feature::CookTorrance => Some(&COOK_TORRANCE),
            Feature::Emission => Some(&EMISSION),
            Feature::FakeSss => Some(&FAKE_SSS),
            Feature::Reflection | Feature::AmbientOcclusion | Feature::Unlit => Some(&STRENGTH),
            Feature::Clearcoat => Some(&CLEARCOAT),
            Feature::MatCap => Some(&MATCAP),
            Feature::Transmission => Some(&TRANSMISSION),
            Feature::Iridescence => Some(&IRIDESCENCE),
            Feature::Anisotropy => Some(&ANISOTROPY),
            Feature::Sheen => Some(&SHEEN),
            Feature::Custom(_) => None,
        }
    }

    /// Whether a shader reads this feature's texture layer: CookTorrance,
    /// Emission and FakeSSS scale their parameter by it, MatCap looks its
    /// image up in it, custom features' own shaders decide. Reflection and
    /// AmbientOcclusion weight screen-space inputs and read none; Clearcoat
    /// and Unlit read none either (their parameters are per material).
    pub fn reads_texture(self) -> bool {
        !matches!(
            self,
            Feature::Reflection
                | Feature::AmbientOcclusion
                | Feature::Clearcoat
                | Feature::Unlit
                | Feature::Transmission
                | Feature::Iridescence
                | Feature::Anisotropy
                | Feature::Sheen
        )
    }

    /// The named parameters of a built-in feature's vec4, each with the
    /// components it spans (a colour three, a number one): what a
    /// per-parameter texture layer scales ([`super::Material::set_param_texture`]).
    /// Empty for custom features, whose shaders read their own textures, and
    /// for Clearcoat and Unlit, which no shader reads through a layer.
    pub fn parameters(self) -> &'static [(&'static str, std::ops::Range<usize>)] {
        type Params = &'static [(&'static str, std::ops::Range<usize>)];
        const CT_PARAMS: Params = &[
            ("Roughness", 0..1),
            ("Metallic", 1..2),
            ("Reflectance", 2..3),
        ];
        const COLOR_PARAMS: Params = &[("Color", 0..3), ("Strength", 3..4)];
        const STRENGTH_PARAMS: Params = &[("Strength", 0..1)];
        match self {
            Feature::CookTorrance => CT_PARAMS,
            Feature::Emission | Feature::FakeSss => COLOR_PARAMS,
            Feature::Reflection | Feature::AmbientOcclusion | Feature::MatCap => STRENGTH_PARAMS,
            // Per material: no shader samples a texture layer for them.
            Feature::Clearcoat
            | Feature::Unlit
            | Feature::Transmission
            | Feature::Sheen
            | Feature::Iridescence
            | Feature::Anisotropy
            | Feature::Custom(_) => &[],
        }
    }

    /// How many vec4 parameters the feature takes; `None`: any number (custom).
    pub fn param_count(self) -> Option<usize> {
        match self {
            // Refraction, then absorption.
            Feature::Transmission => Some(2),
            _ => self.layout().map(|_| 1),
        }
    }

    /// Check `params` and keep them physical: non-finite values are an
    /// error, the rest is clamped to each component's range.
    pub fn sanitize(self, params: &[[f32; 4]]) -> Result<Vec<[f32; 4]>, FeatureError> {
        if let Some(expected) = self.param_count()
            && params.len() != expected
        {
            return Err(FeatureError::ParamCount {
                feature: self.name(),
                expected,
                got: params.len(),
            });
        }
        let ranges = self.layout().map_or([Range::Free; 4], |l| l.ranges);
        params
            .iter()
            .enumerate()
            .map(|(index, p)| {
                let mut out = [0.0; 4];
                for (component, ((v, range), o)) in p.iter().zip(ranges).zip(&mut out).enumerate() {
                    if !v.is_finite() {
                        return Err(FeatureError::NonFinite {
                            feature: self.name(),
                            index,
                            component,
                        });
                    }
                    *o = match range {
                        Range::Unit => v.clamp(0.0, 1.0),
                        Range::NonNegative => v.max(0.0),
                        Range::Unused => 0.0,
                        Range::Free => *v,
                    };
                }
                Ok(out)
            })
            .collect()
    }
}

impl std::fmt::Display for Feature {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.name())
    }
}
