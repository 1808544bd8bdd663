//! `MaterialBuffer`: a spread of materials (slice i = material id i, what
//! the G-buffer stores) uploaded as one `MaterialWorld`: Emeshe's three
//! storage buffers. Nothing connected gives the default material (id 0:
//! CookTorrance, roughness 0.5, metallic 0). Worlds are not singletons:
//! each MaterialBuffer has its own.

use spreadlight_graph::{NodeDef, PinType, Registry, ResourceKind, Spread};
use spreadlight_render::TextureRef;
use spreadlight_render::material::{Material, MaterialWorld};

use super::{CATEGORY, MATERIAL, no_materials};
use crate::gpu::{renderer, resource_spread, resources};

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
        .input_spread("Materials", MATERIAL, no_materials())
        .input_spread(
            "Textures",
            PinType::Resource(ResourceKind::Texture),
            Spread::Resource(ResourceKind::Texture, Vec::new()),
        )
        .output_typed("Material World", PinType::Resource(ResourceKind::MaterialWorld))
        .evaluate(|cx| {
            let renderer = renderer(cx)?;
            let materials: Vec<Material> = resources::<Material>(cx, 0)?.iter().map(|m| Material::clone(m)).collect();
            let textures = resources::<TextureRef>(cx, 1)?;
            if textures.len() > 1 {
                return Err(cx.input_error(
                    1,
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
                return Err(cx.input_error(
                    1,
                    format!(
                        "material {id}: feature {feature} reads texture layer {layer}, but no texture array is \
                         connected: wire a FileTexture (Array) here, or set its Texture ID to -1"
                    ),
                ));
            }
            let textures = textures.first().map(|t| TextureRef::clone(t));
            let world = MaterialWorld::with_textures(&renderer, materials, textures);
            cx.set_output(0, resource_spread(ResourceKind::MaterialWorld, vec![world]));
            Ok(())
        }),
    );
}
