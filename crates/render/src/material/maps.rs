//! Surface maps: the textures of a glTF metallic-roughness material (base
//! colour, metallic-roughness, normal, occlusion, emissive) and of its
//! extensions (clearcoat, clearcoat roughness, specular, specular colour,
//! thickness, clearcoat normal, anisotropy, sheen colour and roughness,
//! iridescence and its thickness), each with its UV set, `KHR_texture_transform` and sampler,
//! plus the alpha mode and double-sidedness. A [`Material`](super::Material)
//! carries them as the built-in feature
//! [`FEATURE_SURFACE_MAPS`](super::FEATURE_SURFACE_MAPS): its flag bit and,
//! when packed, 11 parameter vec4s that `shaders/lib/material_maps.wgsl`
//! reads in the G-buffer resolve, 35 when it has an extension's map (so a
//! material without one packs, and shades, as before). The factors stay
//! where every other material keeps them: roughness, metallic and
//! reflectance in CookTorrance, emissive colour and strength in Emission,
//! the coat's in Clearcoat, the thickness in Transmission, the base colour
//! factor in the instance colour; maps multiply them. The one exception is
//! the specular maps' factors ([`SpecularFactors`]): the reflectance is one
//! number made of three, so a map of one of them needs the others; and the
//! clearcoat normal map's scale, which belongs to no factor.

use std::sync::Arc;

/// The map slots, in the order their parameters are packed: the core
/// material's five, then the extensions' ([`MapSlot::EXTENSIONS`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum MapSlot {
    BaseColor = 0,
    /// Roughness in green, metalness in blue.
    MetallicRoughness = 1,
    Normal = 2,
    /// Occlusion in red.
    Occlusion = 3,
    Emissive = 4,
    /// `KHR_materials_clearcoat`'s clearcoatTexture: the coat's factor in red.
    Clearcoat = 5,
    /// clearcoatRoughnessTexture: the coat's roughness in green.
    ClearcoatRoughness = 6,
    /// `KHR_materials_specular`'s specularTexture: the specular factor in alpha.
    Specular = 7,
    /// specularColorTexture: the specular colour in rgb (sRGB).
    SpecularColor = 8,
    /// `KHR_materials_volume`'s thicknessTexture: the thickness in green.
    Thickness = 9,
    /// `KHR_materials_clearcoat`'s clearcoatNormalTexture: the coat's own
    /// tangent-space normal (rgb), for the coat lobe alone.
    ClearcoatNormal = 10,
    /// `KHR_materials_anisotropy`'s anisotropyTexture: the direction in the
    /// tangent frame in red and green (-1..1 as 0..1), the strength in blue.
    Anisotropy = 11,
    /// `KHR_materials_sheen`'s sheenColorTexture: the sheen colour in rgb (sRGB).
    SheenColor = 12,
    /// sheenRoughnessTexture: the sheen roughness in alpha.
    SheenRoughness = 13,
    /// `KHR_materials_iridescence`'s iridescenceTexture: the factor in red.
    Iridescence = 14,
    /// iridescenceThicknessTexture: green mixes the film's thickness from
    /// its minimum (0) to its maximum (1).
    IridescenceThickness = 15,
}

impl MapSlot {
    pub const ALL: [MapSlot; 16] = [
        MapSlot::BaseColor,
        MapSlot::MetallicRoughness,
        MapSlot::Normal,
        MapSlot::Occlusion,
        MapSlot::Emissive,
        MapSlot::Clearcoat,
        MapSlot::ClearcoatRoughness,
        MapSlot::Specular,
        MapSlot::SpecularColor,
        MapSlot::Thickness,
        MapSlot::ClearcoatNormal,
        MapSlot::Anisotropy,
        MapSlot::SheenColor,
        MapSlot::SheenRoughness,
        MapSlot::Iridescence,
        MapSlot::IridescenceThickness,
    ];

    /// The slots of the material extensions: a material with a map in one
    /// of them packs the long layout, and the passes that read them compile
    /// their code only for a world that has one (EXTENSION_MAPS).
    pub const EXTENSIONS: [MapSlot; 11] = [
        MapSlot::Clearcoat,
        MapSlot::ClearcoatRoughness,
        MapSlot::Specular,
        MapSlot::SpecularColor,
        MapSlot::Thickness,
        MapSlot::ClearcoatNormal,
        MapSlot::Anisotropy,
        MapSlot::SheenColor,
        MapSlot::SheenRoughness,
        MapSlot::Iridescence,
        MapSlot::IridescenceThickness,
    ];

    /// The slots whose per-pixel values the G-buffer resolve writes into
    /// its sheen and film target (`sheen_film`, SHEEN_FILM) for lighting.
    pub const SHEEN_FILM: [MapSlot; 4] = [
        MapSlot::SheenColor,
        MapSlot::SheenRoughness,
        MapSlot::Iridescence,
        MapSlot::IridescenceThickness,
    ];

    /// Colour maps are stored sRGB-encoded and sampled through an sRGB format.
    pub fn srgb(self) -> bool {
        matches!(
            self,
            MapSlot::BaseColor | MapSlot::Emissive | MapSlot::SpecularColor | MapSlot::SheenColor
        )
    }
}

/// `KHR_materials_specular`'s factors, for a material with a specular map:
/// the dielectric f0 is `min(f0 x colour x colour map, 1) x factor x map`,
/// made one number (Rec. 709 luminance) as CookTorrance's reflectance is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpecularFactors {
    /// The f0 of the index of refraction (`KHR_materials_ior`) times the
    /// specular colour factor, per channel, before the colour map.
    pub f0_color: [f32; 3],
    /// The specular factor (0..=1), before the specular map.
    pub factor: f32,
}

impl Default for SpecularFactors {
    /// glTF's: ior 1.5 (f0 0.04), white, factor 1.
    fn default() -> Self {
        Self {
            f0_color: [0.04; 3],
            factor: 1.0,
        }
    }
}

/// Decoded pixels of a map: 8-bit RGBA, rows top to bottom. Shared by
/// every material and slot that uses the same image (uploaded once per world).
#[derive(Clone, Debug, PartialEq)]
pub struct MapImage {
    pub width: u32,
    pub height: u32,
    pub rgba8: Vec<u8>,
}

/// glTF's wrap modes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Wrap {
    #[default]
    Repeat = 0,
    Clamp = 1,
    Mirror = 2,
}

/// `KHR_texture_transform`: uv' = translate(offset) * rotate(rotation) * scale(scale) * uv.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UvTransform {
    pub offset: [f32; 2],
    /// Radians, counter-clockwise in UV space (glTF's convention).
    pub rotation: f32,
    pub scale: [f32; 2],
}

impl Default for UvTransform {
    fn default() -> Self {
        Self {
            offset: [0.0; 2],
            rotation: 0.0,
            scale: [1.0; 2],
        }
    }
}

impl UvTransform {
    /// Where `uv` lands (the CPU twin of `map_uv` in material_maps.wgsl).
    pub fn apply(&self, [u, v]: [f32; 2]) -> [f32; 2] {
        let (s, c) = self.rotation.sin_cos();
        let (su, sv) = (u * self.scale[0], v * self.scale[1]);
        [
            c * su + s * sv + self.offset[0],
            -s * su + c * sv + self.offset[1],
        ]
    }
}

/// One map of a material.
#[derive(Clone, Debug, PartialEq)]
pub struct MapRef {
    pub image: Arc<MapImage>,
    /// Which UV set maps it: 0 (TEXCOORD_0) or 1 (TEXCOORD_1; a mesh without
    /// a second set carries its first there). Larger values read set 0.
    pub tex_coord: u32,
    pub transform: UvTransform,
    pub wrap: [Wrap; 2],
    /// Nearest magnification (glTF NEAREST mag filter); otherwise trilinear
    /// and anisotropic.
    pub nearest: bool,
}

impl MapRef {
    /// A map of `image` with glTF's defaults: TEXCOORD_0, no transform, repeat, linear.
    pub fn new(image: Arc<MapImage>) -> Self {
        Self {
            image,
            tex_coord: 0,
            transform: UvTransform::default(),
            wrap: [Wrap::Repeat; 2],
            nearest: false,
        }
    }
}

/// How a material's alpha is used.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum AlphaMode {
    #[default]
    Opaque,
    /// Alpha below `cutoff` is not drawn, the rest is opaque.
    Mask { cutoff: f32 },
    /// Blended over what is behind (the Transparency node's job; in the
    /// G-buffer it is drawn opaque).
    Blend,
}

/// Everything of a glTF material that is not a factor of another feature.
#[derive(Clone, Debug, PartialEq)]
pub struct SurfaceMaps {
    pub maps: [Option<MapRef>; 16],
    /// Scales the normal map's x and y.
    pub normal_scale: f32,
    /// Scales the clearcoat normal map's x and y (its normalTextureInfo's scale).
    pub clearcoat_normal_scale: f32,
    /// How much of the occlusion map applies (0..=1).
    pub occlusion_strength: f32,
    pub alpha: AlphaMode,
    /// Back faces drawn and lit with flipped normals.
    pub double_sided: bool,
    /// What the specular maps scale (read only with one of them).
    pub specular: SpecularFactors,
}

impl Default for SurfaceMaps {
    fn default() -> Self {
        Self {
            maps: Default::default(),
            normal_scale: 1.0,
            clearcoat_normal_scale: 1.0,
            occlusion_strength: 1.0,
            alpha: AlphaMode::Opaque,
            double_sided: false,
            specular: SpecularFactors::default(),
        }
    }
}

/// Where a packed map lives in a world's map textures: its size-class
/// array and layer. Packed as `slot * 65536 + layer + 1` (0: no map),
/// exact in an f32.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MapLocation {
    pub array: u32,
    pub layer: u32,
}

/// How many parameter vec4s the SurfaceMaps feature packs without an
/// extension's map: the settings and the core slots.
pub const PARAM_COUNT: usize = 1 + 2 * MapSlot::EXTENSIONS[0] as usize;
/// With one: every slot, then the specular factors, then the clearcoat
/// normal map's scale.
pub const EXTENDED_PARAM_COUNT: usize = SPECULAR_FACTORS_PARAM + 2;
/// Where the extended layout keeps the specular factors (`MAP_SPECULAR_FACTORS`
/// in material_maps.wgsl); the clearcoat normal scale is the one after.
pub const SPECULAR_FACTORS_PARAM: usize = 1 + 2 * MapSlot::ALL.len();

impl SurfaceMaps {
    pub fn map(&self, slot: MapSlot) -> Option<&MapRef> {
        self.maps[slot as usize].as_ref()
    }

    pub fn set_map(&mut self, slot: MapSlot, map: Option<MapRef>) {
        self.maps[slot as usize] = map;
    }

    /// Whether a sheen or iridescence slot has a map: the G-buffer then
    /// gets its sheen and film target.
    pub fn has_sheen_film_maps(&self) -> bool {
        MapSlot::SHEEN_FILM.iter().any(|s| self.map(*s).is_some())
    }

    /// Whether a material extension's slot has a map.
    pub fn has_extension_maps(&self) -> bool {
        MapSlot::EXTENSIONS.iter().any(|s| self.map(*s).is_some())
    }

    /// The parameters the shader reads, with each map's location from `locate`:
    /// 0: (alpha mode 0/1/2 + 4 x double-sided, cutoff, normal scale, occlusion strength);
    /// per slot: (location, UV set 0/1, wrap s + 4 x wrap t + 16 x nearest, rotation),
    /// (offset u, offset v, scale u, scale v); with an extension's map every
    /// slot, then (specular f0 x colour rgb, specular factor), then
    /// (clearcoat normal scale, 0, 0, 0), else the core slots alone
    /// ([`PARAM_COUNT`]).
    pub fn pack(&self, locate: &dyn Fn(&MapRef, MapSlot) -> Option<MapLocation>) -> Vec<[f32; 4]> {
        let (mode, cutoff) = match self.alpha {
            AlphaMode::Opaque => (0.0, 0.0),
            AlphaMode::Mask { cutoff } => (1.0, cutoff),
            AlphaMode::Blend => (2.0, 0.0),
        };
        let sided = if self.double_sided { 4.0 } else { 0.0 };
        let finite = |v: f32, or: f32| if v.is_finite() { v } else { or };
        let mut params = vec![[
            mode + sided,
            finite(cutoff, 0.5),
            finite(self.normal_scale, 1.0),
            finite(self.occlusion_strength, 1.0).clamp(0.0, 1.0),
        ]];
        let extended = self.has_extension_maps();
        let slots = if extended {
            &MapSlot::ALL[..]
        } else {
            &MapSlot::ALL[..MapSlot::EXTENSIONS[0] as usize]
        };
        for &slot in slots {
            let entry = self.map(slot).and_then(|m| Some((m, locate(m, slot)?)));
            match entry {
                Some((m, at)) => {
                    let t = &m.transform;
                    let sampler =
                        m.wrap[0] as u32 + 4 * m.wrap[1] as u32 + if m.nearest { 16 } else { 0 };
                    params.push([
                        (at.array * 65536 + at.layer + 1) as f32,
                        if m.tex_coord == 1 { 1.0 } else { 0.0 },
                        sampler as f32,
                        finite(t.rotation, 0.0),
                    ]);
                    params.push([
                        finite(t.offset[0], 0.0),
                        finite(t.offset[1], 0.0),
                        finite(t.scale[0], 1.0),
                        finite(t.scale[1], 1.0),
                    ]);
                }
                None => params.extend([[0.0; 4], [0.0; 4]]),
            }
        }
        if extended {
            let s = &self.specular;
            let [r, g, b] = s.f0_color.map(|c| finite(c, 0.04).max(0.0));
            params.push([r, g, b, finite(s.factor, 1.0).clamp(0.0, 1.0)]);
            params.push([finite(self.clearcoat_normal_scale, 1.0), 0.0, 0.0, 0.0]);
        }
        params
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn texture_transform_follows_the_extension() {
        // KHR_texture_transform's example: rotate a quarter turn, then offset.
        let t = UvTransform {
            offset: [0.0, 1.0],
            rotation: std::f32::consts::FRAC_PI_2,
            scale: [1.0, 1.0],
        };
        let [u, v] = t.apply([1.0, 0.0]);
        assert!((u - 0.0).abs() < 1e-6 && (v - 0.0).abs() < 1e-6, "{u} {v}");
        let [u, v] = UvTransform::default().apply([0.25, 0.75]);
        assert_eq!((u, v), (0.25, 0.75));
    }

    #[test]
    fn packing_places_maps_and_settings() {
        let image = Arc::new(MapImage {
            width: 1,
            height: 1,
            rgba8: vec![255; 4],
        });
        let mut maps = SurfaceMaps {
            alpha: AlphaMode::Mask { cutoff: 0.3 },
            double_sided: true,
            normal_scale: 0.5,
            ..SurfaceMaps::default()
        };
        let mut normal = MapRef::new(image);
        normal.wrap = [Wrap::Clamp, Wrap::Mirror];
        normal.nearest = true;
        maps.set_map(MapSlot::Normal, Some(normal));
        let packed = maps.pack(&|_, slot| {
            (slot == MapSlot::Normal).then_some(MapLocation { array: 3, layer: 7 })
        });
        assert_eq!(packed.len(), PARAM_COUNT);
        assert_eq!(packed[0], [5.0, 0.3, 0.5, 1.0]);
        let at = 1 + 2 * MapSlot::Normal as usize;
        assert_eq!(packed[at], [(3 * 65536 + 8) as f32, 0.0, 25.0, 0.0]);
        assert_eq!(packed[at + 1], [0.0, 0.0, 1.0, 1.0]);
        // Slots without a map are zero: the shader reads "none".
        assert_eq!(packed[1], [0.0; 4]);
    }

    #[test]
    fn an_extension_map_packs_every_slot_and_the_specular_factors() {
        let image = Arc::new(MapImage {
            width: 1,
            height: 1,
            rgba8: vec![255; 4],
        });
        let mut maps = SurfaceMaps {
            specular: SpecularFactors {
                f0_color: [0.04, f32::NAN, -1.0],
                factor: 2.0,
            },
            clearcoat_normal_scale: f32::INFINITY,
            ..SurfaceMaps::default()
        };
        maps.set_map(MapSlot::Clearcoat, Some(MapRef::new(image)));
        let packed = maps.pack(&|_, slot| {
            (slot == MapSlot::Clearcoat).then_some(MapLocation { array: 1, layer: 2 })
        });
        assert_eq!(packed.len(), EXTENDED_PARAM_COUNT);
        let at = 1 + 2 * MapSlot::Clearcoat as usize;
        assert_eq!(packed[at], [(65536 + 3) as f32, 0.0, 0.0, 0.0]);
        // The specular factors after the slots, finite and in range, then
        // the coat normal's scale (finite: an infinite one reads 1).
        assert_eq!(packed[SPECULAR_FACTORS_PARAM], [0.04, 0.04, 0.0, 1.0]);
        assert_eq!(packed[EXTENDED_PARAM_COUNT - 1], [1.0, 0.0, 0.0, 0.0]);
        // Only the colour slots of the extensions (specular's, sheen's) are sRGB.
        let srgb: Vec<_> = MapSlot::EXTENSIONS.iter().map(|s| s.srgb()).collect();
        assert_eq!(
            srgb,
            [
                false, false, false, true, false, false, false, true, false, false, false
            ]
        );
        assert_eq!(
            SPECULAR_FACTORS_PARAM, 33,
            "MAP_SPECULAR_FACTORS in material_maps.wgsl"
        );
        assert_eq!(EXTENDED_PARAM_COUNT, 35);
    }
}
