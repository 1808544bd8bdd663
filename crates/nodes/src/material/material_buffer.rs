//! `MaterialBuffer`: a spread of materials (slice i = material id i, what
//! the G-buffer stores) uploaded as one `MaterialWorld`: Emeshe's three
//! storage buffers. Nothing connected gives the default material (id 0:
//! CookTorrance, roughness 0.5, metallic 0). Worlds are not singletons:
//! each MaterialBuffer has its own.

use spreadlight_graph::{NodeDef, Registry, ResourceKind};
use spreadlight_render::TextureRef;
use spreadlight_render::material::{Material, MaterialWorld};

use super::{CATEGORY, material_input};
use crate::gpu::renderer;
use crate::post::texture_input;

pub fn register(r: &mut Registry) {
    r.add(
        NodeDef::new(
            "MaterialBuffer",
            CATEGORY,
            "Uploads materials for shading: slice i becomes material id i (the G-buffer's material id; ids \
             beyond the last read material 0). Nothing connected: one default material (CookTorrance, \
             roughness 0.5, metallic 0). Shading passes compile only the features some material has. \
             Textures: a texture array (FileTexture (Array)) whose layers the features' Texture IDs pick, \
             mapped by the G-buffer's UV; no texture code is compiled unless some material reads one.",
        )
        .with_pins(|p| {
            let materials_in = material_input(p, "Materials");
            let textures_in = texture_input(p, "Textures");
            let out = p.output_resource::<MaterialWorld>("Material World", ResourceKind::MaterialWorld);
            move |cx| {
            let renderer = renderer(cx)?;
            let materials: Vec<Material> = cx.resources(materials_in)?.iter().map(|m| Material::clone(m)).collect();
            let textures = cx.resources(textures_in)?;
            if textures.len() > 1 {
                return Err(cx.error(
                    textures_in,
                    format!("takes one texture array, got {} textures: join them with FileTexture (Array)", textures.len()),
                ));
            }
            // A Texture ID with no array to index would be read as "no
            // texture" without a word: say which material and feature asks.
            if textures.is_empty()
                && let Some((id, feature, layer)) = materials.iter().enumerate().find_map(|(id, m)| {
                    m.features().find_map(|(f, _)| {
                        let param = (0..f.parameters().len()).find_map(|p| m.param_texture(f, p));
                        m.texture(f).or(param).map(|layer| (id, f, layer))
                    })
                })
            {
                return Err(cx.error(
                    textures_in,
                    format!(
                        "material {id}: feature {feature} reads texture layer {layer}, but no texture array is \
                         connected: wire a FileTexture (Array) here, or set its Texture ID to -1"
                    ),
                ));
            }
            let textures = textures.first().map(|t| TextureRef::clone(t));
            let world = MaterialWorld::with_textures(&renderer, materials, textures);
            cx.put_resources(out, vec![world]);
            Ok(())
            }
        }),
    );
}
