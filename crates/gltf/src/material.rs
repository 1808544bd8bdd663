//! glTF materials to [`MaterialData`] (decoding each image once), and
//! [`MaterialData`] to a [`Material`] of the one material world: factors
//! to CookTorrance and Emission, textures to SurfaceMaps.

use std::sync::Arc;

use gltf::Document;
use gltf::texture::{MagFilter, WrappingMode};

use super::{AlphaMode, GltfError, Importer, MaterialData, TextureData, source};
use spreadlight_render::material::maps::{
    MapRef, MapSlot, SpecularFactors, SurfaceMaps, UvTransform, Wrap,
};
use spreadlight_render::material::{Feature, Material, transmission_params};

/// A texture use as glTF states it: the texture, its texCoord, and its
/// `KHR_texture_transform` extension object if any.
pub(super) struct Slot<'a> {
    pub(super) texture: gltf::Texture<'a>,
    pub(super) tex_coord: u32,
    /// `KHR_texture_transform`, and the texCoord it overrides with.
    pub(super) transform: Option<(UvTransform, Option<u32>)>,
}

impl Importer<'_> {
    pub(super) fn material(
        &mut self,
        document: &Document,
        m: &gltf::Material,
    ) -> Result<MaterialData, GltfError> {
        let pbr = m.pbr_metallic_roughness();
        let what = |slot: &str| match m.index() {
            Some(i) => format!("material {i}, {slot}"),
            None => format!("default material, {slot}"),
        };
        let normal = m.normal_texture();
        let occlusion = m.occlusion_texture();
        let normal_slot = normal.as_ref().map(|t| Slot {
            texture: t.texture(),
            tex_coord: t.tex_coord(),
            transform: t
                .extension_value("KHR_texture_transform")
                .map(parse_transform),
        });
        let occlusion_slot = occlusion.as_ref().map(|t| Slot {
            texture: t.texture(),
            tex_coord: t.tex_coord(),
            transform: t
                .extension_value("KHR_texture_transform")
                .map(parse_transform),
        });
        let mut data = MaterialData {
            name: m.name().map(str::to_owned),
            base_color: pbr.base_color_factor(),
            metallic: pbr.metallic_factor(),
            roughness: pbr.roughness_factor(),
            emissive: m.emissive_factor(),
            emissive_strength: m.emissive_strength().unwrap_or(1.0),
            base_color_texture: self.texture(
                document,
                pbr.base_color_texture().map(info_slot),
                true,
                &what("base colour texture"),
            )?,
            metallic_roughness_texture: self.texture(
                document,
                pbr.metallic_roughness_texture().map(info_slot),
                false,
                &what("metallic-roughness texture"),
            )?,
            normal_scale: normal.as_ref().map_or(1.0, |t| t.scale()),
            normal_texture: self.texture(document, normal_slot, false, &what("normal texture"))?,
            occlusion_strength: occlusion.as_ref().map_or(1.0, |t| t.strength()),
            occlusion_texture: self.texture(
                document,
                occlusion_slot,
                false,
                &what("occlusion texture"),
            )?,
            emissive_texture: self.texture(
                document,
                m.emissive_texture().map(info_slot),
                true,
                &what("emissive texture"),
            )?,
            double_sided: m.double_sided(),
            alpha_mode: match m.alpha_mode() {
                gltf::material::AlphaMode::Opaque => AlphaMode::Opaque,
                gltf::material::AlphaMode::Mask => AlphaMode::Mask {
                    cutoff: m.alpha_cutoff().unwrap_or(0.5),
                },
                gltf::material::AlphaMode::Blend => AlphaMode::Blend,
            },
            ..MaterialData::default()
        };
        // KHR_materials_*: unlit, ior, specular, clearcoat, transmission,
        // spec-gloss (converted), emissive strength checked.
        self.material_extensions(document, m, &mut data)?;
        Ok(data)
    }

    pub(super) fn texture(
        &mut self,
        document: &Document,
        slot: Option<Slot>,
        srgb: bool,
        what: &str,
    ) -> Result<Option<TextureData>, GltfError> {
        let Some(slot) = slot else {
            return Ok(None);
        };
        // glTF allows a texture without `source` when an extension (a
        // compressed or WebP image) supplies it; without one read here the
        // material is drawn without that texture, as other viewers do.
        let Some(source_image) = slot.texture.source() else {
            self.warn(format!(
                "{what}: texture {} has no image this loader reads (no `source`); drawn without it",
                slot.texture.index()
            ));
            return Ok(None);
        };
        let index = source_image.index();
        let (transform, tex_coord) = match slot.transform {
            Some((t, over)) => (finite_transform(t), over.unwrap_or(slot.tex_coord)),
            None => (UvTransform::default(), slot.tex_coord),
        };
        // Meshes carry two UV sets (TEXCOORD_0 and TEXCOORD_1).
        let tex_coord = if tex_coord > 1 {
            self.warn(format!(
                "{what} uses TEXCOORD_{tex_coord}; meshes carry TEXCOORD_0 and TEXCOORD_1, so it is mapped with TEXCOORD_0"
            ));
            0
        } else {
            tex_coord
        };
        let image = match self.images.get(&index) {
            Some(image) => image.clone(),
            None => {
                let decoded = Arc::new(source::decode_image(
                    document,
                    index,
                    &self.buffers,
                    self.base_dir,
                    self.path,
                )?);
                self.images.insert(index, decoded.clone());
                decoded
            }
        };
        let sampler = slot.texture.sampler();
        let wrap = |mode| match mode {
            WrappingMode::ClampToEdge => Wrap::Clamp,
            WrappingMode::MirroredRepeat => Wrap::Mirror,
            WrappingMode::Repeat => Wrap::Repeat,
        };
        Ok(Some(TextureData {
            image,
            srgb,
            tex_coord,
            transform,
            wrap: [wrap(sampler.wrap_s()), wrap(sampler.wrap_t())],
            nearest: sampler.mag_filter() == Some(MagFilter::Nearest),
        }))
    }
}

fn info_slot(i: gltf::texture::Info<'_>) -> Slot<'_> {
    // gltf reads the extension of texture infos itself (typed, not in the map).
    let transform = i.texture_transform().map(|t| {
        let uv = UvTransform {
            offset: t.offset(),
            rotation: t.rotation(),
            scale: t.scale(),
        };
        (uv, t.tex_coord())
    });
    Slot {
        texture: i.texture(),
        tex_coord: i.tex_coord(),
        transform,
    }
}

/// `KHR_texture_transform` from its extension object (offset, rotation,
/// scale, texCoord override); absent or malformed fields keep their defaults.
pub(super) fn parse_transform(v: &gltf::json::Value) -> (UvTransform, Option<u32>) {
    let d = UvTransform::default();
    let pair = |key: &str, default: [f32; 2]| {
        v.get(key)
            .and_then(|p| Some([p.get(0)?.as_f64()? as f32, p.get(1)?.as_f64()? as f32]))
            .unwrap_or(default)
    };
    let t = UvTransform {
        offset: pair("offset", d.offset),
        scale: pair("scale", d.scale),
        rotation: v
            .get("rotation")
            .and_then(|r| r.as_f64())
            .map_or(0.0, |r| r as f32),
    };
    let tex_coord = v
        .get("texCoord")
        .and_then(|c| c.as_u64())
        .and_then(|c| u32::try_from(c).ok());
    (t, tex_coord)
}

/// Non-finite parts of a transform replaced by the identity's.
fn finite_transform(t: UvTransform) -> UvTransform {
    let d = UvTransform::default();
    let pair = |p: [f32; 2], or: [f32; 2]| {
        if p.iter().all(|c| c.is_finite()) {
            p
        } else {
            or
        }
    };
    UvTransform {
        offset: pair(t.offset, d.offset),
        scale: pair(t.scale, d.scale),
        rotation: if t.rotation.is_finite() {
            t.rotation
        } else {
            0.0
        },
    }
}

impl TextureData {
    fn map(&self) -> MapRef {
        MapRef {
            image: self.image.clone(),
            tex_coord: self.tex_coord,
            transform: self.transform,
            wrap: self.wrap,
            nearest: self.nearest,
        }
    }
}

impl MaterialData {
    /// This material in the material world: CookTorrance with its roughness
    /// and metallic factors and the dielectric f0 of `KHR_materials_ior` and
    /// `KHR_materials_specular` ([`MaterialData::reflectance`]; 0.04, glTF's,
    /// without them), Emission when it emits (colour,
    /// `KHR_materials_emissive_strength`), Clearcoat when it has a coat
    /// (`KHR_materials_clearcoat`), Iridescence when it has a film
    /// (`KHR_materials_iridescence`), Sheen when its sheen colour is not
    /// black (`KHR_materials_sheen`), Unlit (`KHR_materials_unlit`),
    /// Transmission when it transmits (`KHR_materials_transmission`, its
    /// refraction by `KHR_materials_ior`, its thickness and absorption by
    /// `KHR_materials_volume`), Anisotropy when its highlight stretches
    /// (`KHR_materials_anisotropy`), and
    /// SurfaceMaps for its textures (the extensions' clearcoat, clearcoat
    /// roughness, specular, specular colour and thickness maps included),
    /// alpha mode and sidedness. The base
    /// colour factor is the instance colour (the glTF node's Base Color).
    pub fn to_material(&self) -> Material {
        let mut material = Material::new();
        let finite = |v: f32| if v.is_finite() { v } else { 0.0 };
        // Clamped into range by `set`; finite, so it cannot fail.
        let _ = material.set(
            Feature::CookTorrance,
            &[[
                finite(self.roughness),
                finite(self.metallic),
                self.reflectance(),
                0.0,
            ]],
        );
        if finite(self.clearcoat) > 0.0 {
            let _ = material.set(
                Feature::Clearcoat,
                &[[
                    finite(self.clearcoat),
                    finite(self.clearcoat_roughness),
                    0.0,
                    0.0,
                ]],
            );
        }
        if finite(self.iridescence) > 0.0 {
            let _ = material.set(
                Feature::Iridescence,
                &[[
                    finite(self.iridescence),
                    if self.iridescence_ior.is_finite() {
                        self.iridescence_ior.max(1.0)
                    } else {
                        1.3
                    },
                    finite(self.iridescence_thickness_minimum),
                    finite(self.iridescence_thickness_maximum),
                ]],
            );
        }
        let sheen = self.sheen_color.map(finite);
        let sheened = sheen.iter().any(|&c| c > 0.0);
        let filmed = finite(self.iridescence) > 0.0;
        if sheened {
            let [r, g, b] = sheen;
            let _ = material.set(Feature::Sheen, &[[r, g, b, finite(self.sheen_roughness)]]);
        }
        if self.unlit {
            let _ = material.set(Feature::Unlit, &[[1.0, 0.0, 0.0, 0.0]]);
        }
        let anisotropic = finite(self.anisotropy_strength) > 0.0;
        if anisotropic {
            let _ = material.set(
                Feature::Anisotropy,
                &[[
                    finite(self.anisotropy_strength),
                    finite(self.anisotropy_rotation),
                    0.0,
                    0.0,
                ]],
            );
        }
        if finite(self.transmission) > 0.0 {
            // The factor and map are in the base colour's alpha already
            // (1 - transmission), so all of what shows through refracts.
            let _ = material.set(
                Feature::Transmission,
                &transmission_params(
                    1.0,
                    self.ior,
                    self.thickness,
                    self.attenuation_color,
                    self.attenuation_distance,
                    self.dispersion,
                ),
            );
        }
        let [r, g, b] = self.emissive.map(finite);
        let strength = finite(self.emissive_strength);
        if (r > 0.0 || g > 0.0 || b > 0.0) && strength > 0.0 {
            let _ = material.set(Feature::Emission, &[[r, g, b, strength]]);
        }
        let mut maps = SurfaceMaps {
            normal_scale: self.normal_scale,
            clearcoat_normal_scale: self.clearcoat_normal_scale,
            occlusion_strength: self.occlusion_strength,
            alpha: self.alpha_mode,
            double_sided: self.double_sided,
            ..SurfaceMaps::default()
        };
        for (slot, texture) in [
            (MapSlot::BaseColor, &self.base_color_texture),
            (MapSlot::MetallicRoughness, &self.metallic_roughness_texture),
            (MapSlot::Normal, &self.normal_texture),
            (MapSlot::Occlusion, &self.occlusion_texture),
            (MapSlot::Emissive, &self.emissive_texture),
        ] {
            maps.set_map(slot, texture.as_ref().map(TextureData::map));
        }
        // The extensions' maps scale their factors: a map under a zero
        // factor (no coat, nothing transmitted) changes nothing, and is left out.
        let coated = finite(self.clearcoat) > 0.0;
        let transmits = finite(self.transmission) > 0.0;
        for (slot, texture, used) in [
            (MapSlot::Clearcoat, &self.clearcoat_texture, coated),
            (
                MapSlot::ClearcoatRoughness,
                &self.clearcoat_roughness_texture,
                coated,
            ),
            (
                MapSlot::ClearcoatNormal,
                &self.clearcoat_normal_texture,
                coated,
            ),
            (MapSlot::Specular, &self.specular_texture, true),
            (MapSlot::SpecularColor, &self.specular_color_texture, true),
            (MapSlot::Thickness, &self.thickness_texture, transmits),
            (MapSlot::Anisotropy, &self.anisotropy_texture, anisotropic),
            (MapSlot::SheenColor, &self.sheen_color_texture, sheened),
            (
                MapSlot::SheenRoughness,
                &self.sheen_roughness_texture,
                sheened,
            ),
            (MapSlot::Iridescence, &self.iridescence_texture, filmed),
            (
                MapSlot::IridescenceThickness,
                &self.iridescence_thickness_texture,
                filmed,
            ),
        ] {
            maps.set_map(
                slot,
                texture.as_ref().filter(|_| used).map(TextureData::map),
            );
        }
        let f0 = self.dielectric_f0();
        maps.specular = SpecularFactors {
            f0_color: self.specular_color.map(|c| f0 * finite(c).max(0.0)),
            factor: finite(self.specular).clamp(0.0, 1.0),
        };
        material.set_maps(Some(Arc::new(maps)));
        material
    }
}
