//! The ratified `KHR_materials_*` extensions that fit the G-buffer, read
//! from their raw JSON objects (the gltf crate's `extension_value`), so that
//! a malformed or out-of-range value is a warning naming the material and
//! the rest of the file loads: a factor outside its range is clamped into
//! it, a value that is not a number keeps the extension's default, and no
//! NaN or infinity reaches a material.
//!
//! - `KHR_materials_unlit`: [`MaterialData::unlit`] (the Unlit feature).
//! - `KHR_materials_ior`, `KHR_materials_specular`: the dielectric f0
//!   ([`MaterialData::reflectance`], CookTorrance's reflectance).
//! - `KHR_materials_clearcoat`: factor and roughness (the Clearcoat feature).
//! - `KHR_materials_anisotropy`: strength and rotation (the Anisotropy
//!   feature), its map a surface map (the G-buffer's anisotropy target).
//! - `KHR_materials_iridescence`: factor, film ior, thickness minimum and
//!   maximum (the Iridescence feature) and its two maps.
//! - `KHR_materials_sheen`: colour and roughness factors (the Sheen
//!   feature) and its two maps (the colour map sRGB
//!   are drawn).
//! - `KHR_materials_transmission`: drawn BLEND with opacity
//!   alpha x (1 - transmission), what shows through refracted by lit
//!   transparency (the material's Transmission feature, with
//!   `KHR_materials_ior` and `KHR_materials_volume`); its
//!   transmissionTexture is baked into the base colour map's alpha
//!   ([`super::transmission`]), so it is sampled per texel.
//! - `KHR_materials_volume`: thickness, its map, attenuation colour and
//!   distance read and checked ([`super::volume`]), drawn by lit
//!   transparency (the thickness map sampled per fragment).
//! - `KHR_materials_dispersion`: the dispersion, carried by the
//!   Transmission feature; lit transparency refracts red, green and blue
//!   by their own index (it changes nothing without transmission and volume).
//! - `KHR_materials_pbrSpecularGlossiness`: converted to metal-rough
//!   ([`super::spec_gloss`]), maps included.
//! - `KHR_materials_emissive_strength` (typed by the gltf crate): checked.
//!
//! The clearcoat, clearcoat roughness, clearcoat normal, specular,
//! specular colour and thickness maps are surface maps of their own slots
//! ([`MaterialData::to_material`]), sampled where their factor is read: the
//! coat (its normal too) and the reflectance in the G-buffer resolve and in
//! lit transparency, the thickness in lit transparency.

use gltf::Document;
use gltf::json::Value;

use super::material::{Slot, parse_transform};
use super::spec_gloss::{self, SpecGloss};
use super::{AlphaMode, GltfError, Importer, MaterialData, TextureData};

impl Importer<'_> {
    /// Reads `m`'s material extensions into `data` (already holding the core material).
    pub(super) fn material_extensions(
        &mut self,
        document: &Document,
        m: &gltf::Material,
        data: &mut MaterialData,
    ) -> Result<(), GltfError> {
        let who = match (m.index(), m.name()) {
            (Some(i), Some(name)) => format!("material {i} `{name}`"),
            (Some(i), None) => format!("material {i}"),
            (None, _) => return Ok(()),
        };
        let strength = data.emissive_strength;
        if !(strength.is_finite() && strength >= 0.0) {
            self.warn(format!(
                "{who}: KHR_materials_emissive_strength emissiveStrength is {strength}, not a finite number >= 0: 1 used"
            ));
            data.emissive_strength = 1.0;
        }
        if m.extension_value("KHR_materials_unlit").is_some() {
            data.unlit = true;
        }
        if let Some(ext) = m.extension_value("KHR_materials_ior") {
            data.ior = self.ior(&who, ext);
        }
        if let Some(ext) = m.extension_value("KHR_materials_specular") {
            let name = "KHR_materials_specular";
            data.specular = self.factor(&who, name, ext, "specularFactor", 1.0, 0.0, 1.0);
            data.specular_color =
                self.color(&who, name, ext, "specularColorFactor", [1.0; 3], f32::MAX);
            data.specular_texture =
                self.extension_texture(document, &who, name, ext, "specularTexture", false)?;
            data.specular_color_texture =
                self.extension_texture(document, &who, name, ext, "specularColorTexture", true)?;
        }
        if let Some(ext) = m.extension_value("KHR_materials_clearcoat") {
            let name = "KHR_materials_clearcoat";
            data.clearcoat = self.factor(&who, name, ext, "clearcoatFactor", 0.0, 0.0, 1.0);
            data.clearcoat_roughness =
                self.factor(&who, name, ext, "clearcoatRoughnessFactor", 0.0, 0.0, 1.0);
            data.clearcoat_texture =
                self.extension_texture(document, &who, name, ext, "clearcoatTexture", false)?;
            data.clearcoat_roughness_texture = self.extension_texture(
                document,
                &who,
                name,
                ext,
                "clearcoatRoughnessTexture",
                false,
            )?;
            data.clearcoat_normal_texture =
                self.extension_texture(document, &who, name, ext, "clearcoatNormalTexture", false)?;
            // normalTextureInfo's scale: any finite number (a negative one
            // turns the map's x and y around, as glTF allows).
            if let Some(info) = ext.get("clearcoatNormalTexture") {
                data.clearcoat_normal_scale =
                    self.factor(&who, name, info, "scale", 1.0, f32::MIN, f32::MAX);
            }
        }
        if let Some(ext) = m.extension_value("KHR_materials_anisotropy") {
            let name = "KHR_materials_anisotropy";
            data.anisotropy_strength =
                self.factor(&who, name, ext, "anisotropyStrength", 0.0, 0.0, 1.0);
            // Any finite angle turns the direction (radians).
            data.anisotropy_rotation = self.factor(
                &who,
                name,
                ext,
                "anisotropyRotation",
                0.0,
                f32::MIN,
                f32::MAX,
            );
            data.anisotropy_texture =
                self.extension_texture(document, &who, name, ext, "anisotropyTexture", false)?;
        }
        if let Some(ext) = m.extension_value("KHR_materials_iridescence") {
            self.iridescence(document, &who, ext, data)?;
        }
        if let Some(ext) = m.extension_value("KHR_materials_sheen") {
            let name = "KHR_materials_sheen";
            data.sheen_color = self.color(&who, name, ext, "sheenColorFactor", [0.0; 3], 1.0);
            data.sheen_roughness =
                self.factor(&who, name, ext, "sheenRoughnessFactor", 0.0, 0.0, 1.0);
            data.sheen_color_texture =
                self.extension_texture(document, &who, name, ext, "sheenColorTexture", true)?;
            data.sheen_roughness_texture =
                self.extension_texture(document, &who, name, ext, "sheenRoughnessTexture", false)?;
        }
        // Spec-gloss replaces the base colour map; transmission's map is
        // baked into whichever base colour map results.
        if let Some(ext) = m.extension_value("KHR_materials_pbrSpecularGlossiness") {
            self.spec_gloss(document, &who, ext, data)?;
        }
        if let Some(ext) = m.extension_value("KHR_materials_transmission") {
            self.transmission(document, &who, ext, data)?;
        }
        if let Some(ext) = m.extension_value("KHR_materials_volume") {
            self.volume(document, &who, ext, data)?;
        }
        if let Some(ext) = m.extension_value("KHR_materials_dispersion") {
            // Any finite number >= 0 (no upper bound in the extension).
            data.dispersion = self.factor(
                &who,
                "KHR_materials_dispersion",
                ext,
                "dispersion",
                0.0,
                0.0,
                f32::MAX,
            );
        }
        Ok(())
    }

    /// `KHR_materials_transmission`: the factor, and its map baked into
    /// the base colour map's alpha; drawn BLEND, what shows through
    /// refracted (the Transmission feature, [`MaterialData::to_material`]).
    fn transmission(
        &mut self,
        document: &Document,
        who: &str,
        ext: &Value,
        data: &mut MaterialData,
    ) -> Result<(), GltfError> {
        let name = "KHR_materials_transmission";
        data.transmission = self.factor(who, name, ext, "transmissionFactor", 0.0, 0.0, 1.0);
        data.transmission_texture =
            self.extension_texture(document, who, name, ext, "transmissionTexture", false)?;
        if data.transmission <= 0.0 {
            return Ok(());
        }
        // What the surface lets through is its coverage's complement; lit
        // transparency refracts it (the Transmission feature).
        data.alpha_mode = AlphaMode::Blend;
        let Some(map) = data.transmission_texture.clone() else {
            data.base_color[3] *= 1.0 - data.transmission;
            self.warn(format!(
                "{who}: {name} {} is drawn as BLEND with opacity {} (alpha x (1 - transmission)), what shows through refracted in screen space (the opaque scene only)",
                data.transmission, data.base_color[3]
            ));
            return Ok(());
        };
        let base = data.base_color_texture.take();
        if let Some(b) = &base
            && (b.tex_coord, b.transform, b.wrap) != (map.tex_coord, map.transform, map.wrap)
        {
            self.warn(format!(
                "{who}: {name}: transmissionTexture is mapped differently from baseColorTexture; it is baked on the base colour's mapping"
            ));
        }
        let image = super::transmission::bake_opacity(
            base.as_ref().map(|b| b.image.as_ref()),
            &map.image,
            data.transmission,
        );
        // The baked map keeps the base colour's sampling, else the
        // transmission map's (with white colour, so only alpha changes).
        let sampling = base.unwrap_or(TextureData { srgb: true, ..map });
        data.base_color_texture = Some(TextureData { image, ..sampling });
        self.warn(format!(
            "{who}: {name} {} with transmissionTexture is drawn as BLEND with opacity alpha x (1 - transmission x map), what shows through refracted in screen space (the opaque scene only)",
            data.transmission
        ));
        Ok(())
    }

    /// `KHR_materials_iridescence`: the factor (0..1), the film's index
    /// (>= 1; else 1.3), the thickness range (nm, >= 0, the minimum at
    /// most the maximum), all warned when out of range; the maps read.
    fn iridescence(
        &mut self,
        document: &Document,
        who: &str,
        ext: &Value,
        data: &mut MaterialData,
    ) -> Result<(), GltfError> {
        let name = "KHR_materials_iridescence";
        data.iridescence = self.factor(who, name, ext, "iridescenceFactor", 0.0, 0.0, 1.0);
        data.iridescence_ior = match ext.get("iridescenceIor") {
            None => 1.3,
            Some(v) => match v.as_f64().map(|v| v as f32) {
                Some(ior) if ior.is_finite() && ior >= 1.0 => ior,
                _ => {
                    self.warn(format!(
                        "{who}: {name} iridescenceIor is {v}, not a finite number >= 1: 1.3 used"
                    ));
                    1.3
                }
            },
        };
        let lo = self.factor(
            who,
            name,
            ext,
            "iridescenceThicknessMinimum",
            100.0,
            0.0,
            f32::MAX,
        );
        let hi = self.factor(
            who,
            name,
            ext,
            "iridescenceThicknessMaximum",
            400.0,
            0.0,
            f32::MAX,
        );
        if lo > hi {
            self.warn(format!(
                "{who}: {name} iridescenceThicknessMinimum {lo} is above the maximum {hi}: kept as given (a thickness map runs from one to the other)"
            ));
        }
        data.iridescence_thickness_minimum = lo;
        data.iridescence_thickness_maximum = hi;
        data.iridescence_texture =
            self.extension_texture(document, who, name, ext, "iridescenceTexture", false)?;
        data.iridescence_thickness_texture = self.extension_texture(
            document,
            who,
            name,
            ext,
            "iridescenceThicknessTexture",
            false,
        )?;
        Ok(())
    }

    /// `KHR_materials_ior`'s ior: 1 or more, or 0 (f0 = 1); else 1.5, warned.
    fn ior(&mut self, who: &str, ext: &Value) -> f32 {
        let Some(v) = ext.get("ior") else {
            return 1.5;
        };
        match v.as_f64().map(|v| v as f32) {
            Some(ior) if ior.is_finite() && (ior >= 1.0 || ior == 0.0) => ior,
            _ => {
                self.warn(format!(
                    "{who}: KHR_materials_ior ior is {v}, not 0 or a finite number >= 1: 1.5 used"
                ));
                1.5
            }
        }
    }

    /// Number `key` of extension object `ext`: `default` when absent,
    /// clamped into `lo..=hi` when outside, `default` when not a finite
    /// number (both warned, naming the material).
    #[allow(clippy::too_many_arguments)]
    pub(super) fn factor(
        &mut self,
        who: &str,
        extension: &str,
        ext: &Value,
        key: &str,
        default: f32,
        lo: f32,
        hi: f32,
    ) -> f32 {
        let Some(v) = ext.get(key) else {
            return default;
        };
        match v.as_f64().map(|v| v as f32) {
            Some(x) if x.is_finite() && (lo..=hi).contains(&x) => x,
            Some(x) if x.is_finite() => {
                let clamped = x.clamp(lo, hi);
                self.warn(format!(
                    "{who}: {extension} {key} is {x}, outside {lo}..={hi}: {clamped} used"
                ));
                clamped
            }
            _ => {
                self.warn(format!(
                    "{who}: {extension} {key} is {v}, not a finite number: {default} used"
                ));
                default
            }
        }
    }

    /// An array of N numbers in 0..=`hi`; `default` when absent or malformed.
    pub(super) fn color<const N: usize>(
        &mut self,
        who: &str,
        extension: &str,
        ext: &Value,
        key: &str,
        default: [f32; N],
        hi: f32,
    ) -> [f32; N] {
        let Some(v) = ext.get(key) else {
            return default;
        };
        let numbers: Option<Vec<f32>> = v.as_array().and_then(|a| {
            a.iter()
                .map(|c| c.as_f64().map(|c| c as f32).filter(|c| c.is_finite()))
                .collect()
        });
        match numbers.and_then(|n| <[f32; N]>::try_from(n).ok()) {
            Some(c) => {
                let clamped = c.map(|c| c.clamp(0.0, hi));
                if clamped != c {
                    self.warn(format!(
                        "{who}: {extension} {key} {c:?} has components outside 0..={hi}: {clamped:?} used"
                    ));
                }
                clamped
            }
            None => {
                self.warn(format!(
                    "{who}: {extension} {key} is {v}, not {N} finite numbers: {default:?} used"
                ));
                default
            }
        }
    }

    /// The texture an extension's texture info names, decoded as the core
    /// slots are; one that names no texture of the file is warned and left out.
    pub(super) fn extension_texture(
        &mut self,
        document: &Document,
        who: &str,
        extension: &str,
        ext: &Value,
        key: &str,
        srgb: bool,
    ) -> Result<Option<TextureData>, GltfError> {
        let Some(info) = ext.get(key) else {
            return Ok(None);
        };
        let texture = info
            .get("index")
            .and_then(Value::as_u64)
            .and_then(|i| usize::try_from(i).ok())
            .and_then(|i| document.textures().nth(i));
        let Some(texture) = texture else {
            self.warn(format!(
                "{who}: {extension} {key} names no texture of the file ({info}); drawn without it"
            ));
            return Ok(None);
        };
        let slot = Slot {
            texture,
            tex_coord: info
                .get("texCoord")
                .and_then(Value::as_u64)
                .and_then(|c| u32::try_from(c).ok())
                .unwrap_or(0),
            transform: info
                .get("extensions")
                .and_then(|e| e.get("KHR_texture_transform"))
                .map(parse_transform),
        };
        self.texture(
            document,
            Some(slot),
            srgb,
            &format!("{who}, {extension} {key}"),
        )
    }

    /// `KHR_materials_pbrSpecularGlossiness` in place of the core
    /// metallic-roughness (the extension says a reader of it uses it):
    /// factors and maps converted (`spec_gloss`).
    fn spec_gloss(
        &mut self,
        document: &Document,
        who: &str,
        ext: &Value,
        data: &mut MaterialData,
    ) -> Result<(), GltfError> {
        let name = "KHR_materials_pbrSpecularGlossiness";
        let factors = SpecGloss {
            diffuse: self.color(who, name, ext, "diffuseFactor", [1.0; 4], 1.0),
            specular: self.color(who, name, ext, "specularFactor", [1.0; 3], 1.0),
            glossiness: self.factor(who, name, ext, "glossinessFactor", 1.0, 0.0, 1.0),
        };
        let diffuse = self.extension_texture(document, who, name, ext, "diffuseTexture", true)?;
        let specular_glossiness =
            self.extension_texture(document, who, name, ext, "specularGlossinessTexture", true)?;
        data.from_spec_gloss = true;
        if diffuse.is_none() && specular_glossiness.is_none() {
            let mr = spec_gloss::convert(factors);
            data.base_color = mr.base_color;
            data.metallic = mr.metallic;
            data.roughness = mr.roughness;
            data.base_color_texture = None;
            data.metallic_roughness_texture = None;
            return Ok(());
        }
        if let (Some(d), Some(s)) = (&diffuse, &specular_glossiness)
            && (d.tex_coord, d.transform, d.wrap) != (s.tex_coord, s.transform, s.wrap)
        {
            self.warn(format!(
                "{who}: {name}: diffuseTexture and specularGlossinessTexture are mapped differently; both are converted on diffuseTexture's mapping"
            ));
        }
        let (base, metal_rough) = spec_gloss::convert_maps(
            factors,
            diffuse.as_ref().map(|t| t.image.as_ref()),
            specular_glossiness.as_ref().map(|t| t.image.as_ref()),
        );
        // The maps carry the factors; the converted maps use the first map's sampling.
        let Some(sampling) = diffuse.or(specular_glossiness) else {
            return Ok(());
        };
        data.base_color = [1.0; 4];
        data.metallic = 1.0;
        data.roughness = 1.0;
        data.base_color_texture = Some(TextureData {
            image: base,
            srgb: true,
            ..sampling.clone()
        });
        data.metallic_roughness_texture = Some(TextureData {
            image: metal_rough,
            srgb: false,
            ..sampling
        });
        Ok(())
    }
}

impl MaterialData {
    /// The f0 of the index of refraction alone, ((ior - 1) / (ior + 1))²
    /// (`KHR_materials_ior`: 0.04 at 1.5, 1 for ior 0); what the specular
    /// colour and factor, and their maps, scale.
    pub fn dielectric_f0(&self) -> f32 {
        let ior = if self.ior.is_finite() { self.ior } else { 1.5 };
        // glTF's default (1.5) gives the 0.04 every material had, bit for bit.
        if ior == 0.0 {
            1.0
        } else if ior == 1.5 {
            0.04
        } else {
            let r = (ior - 1.0) / (ior + 1.0);
            r * r
        }
    }

    /// The f0 of the dielectric part (CookTorrance's reflectance):
    /// ((ior - 1) / (ior + 1))² (`KHR_materials_ior`; 0.04 at 1.5, 1 for
    /// ior 0) times the specular colour, capped at 1, times the specular
    /// factor (`KHR_materials_specular`). The material world's reflectance
    /// is one number: a coloured specular gives its luminance (Rec. 709),
    /// and the extension's f90 (the specular factor at grazing) stays 1.
    pub fn reflectance(&self) -> f32 {
        let finite = |v: f32, or: f32| if v.is_finite() { v } else { or };
        let f0 = self.dielectric_f0();
        let [r, g, b] = self
            .specular_color
            .map(|c| (f0 * finite(c, 1.0).max(0.0)).min(1.0));
        let grey = if r == g && g == b {
            r
        } else {
            0.2126 * r + 0.7152 * g + 0.0722 * b
        };
        (grey * finite(self.specular, 1.0)).clamp(0.0, 1.0)
    }
}
