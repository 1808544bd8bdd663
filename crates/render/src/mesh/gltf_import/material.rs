//! glTF materials to [`MaterialData`], decoding each image once.

use gltf::Document;

use super::{AlphaMode, GltfError, Importer, MaterialData, TextureData, source};

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
        Ok(MaterialData {
            name: m.name().map(str::to_owned),
            base_color: pbr.base_color_factor(),
            metallic: pbr.metallic_factor(),
            roughness: pbr.roughness_factor(),
            emissive: m.emissive_factor(),
            base_color_texture: self.texture(
                document,
                pbr.base_color_texture()
                    .map(|i| (i.texture(), i.tex_coord())),
                true,
                &what("base colour texture"),
            )?,
            metallic_roughness_texture: self.texture(
                document,
                pbr.metallic_roughness_texture()
                    .map(|i| (i.texture(), i.tex_coord())),
                false,
                &what("metallic-roughness texture"),
            )?,
            normal_scale: normal.as_ref().map_or(1.0, |t| t.scale()),
            normal_texture: self.texture(
                document,
                normal.map(|t| (t.texture(), t.tex_coord())),
                false,
                &what("normal texture"),
            )?,
            occlusion_strength: occlusion.as_ref().map_or(1.0, |t| t.strength()),
            occlusion_texture: self.texture(
                document,
                occlusion.map(|t| (t.texture(), t.tex_coord())),
                false,
                &what("occlusion texture"),
            )?,
            emissive_texture: self.texture(
                document,
                m.emissive_texture().map(|i| (i.texture(), i.tex_coord())),
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
        })
    }

    fn texture(
        &mut self,
        document: &Document,
        slot: Option<(gltf::Texture, u32)>,
        srgb: bool,
        what: &str,
    ) -> Result<Option<TextureData>, GltfError> {
        let Some((texture, tex_coord)) = slot else {
            return Ok(None);
        };
        if tex_coord != 0 {
            self.warnings.push(format!(
                "{what} uses TEXCOORD_{tex_coord}; only TEXCOORD_0 is loaded, so it is mapped with that"
            ));
        }
        let index = texture.source().index();
        if !self.images.contains_key(&index) {
            let decoded =
                source::decode_image(document, index, &self.buffers, self.base_dir, self.path)?;
            self.images.insert(index, decoded);
        }
        Ok(self.images.get(&index).map(|decoded| TextureData {
            srgb,
            ..decoded.clone()
        }))
    }
}
