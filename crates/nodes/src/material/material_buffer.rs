//! `MaterialBuffer`: a spread of materials (slice i = material id i, what
//! the G-buffer stores) uploaded as one `MaterialWorld`: Emeshe's three
//! storage buffers. Nothing connected gives the default material (id 0:
//! CookTorrance, roughness 0.5, metallic 0). Worlds are not singletons:
//! each MaterialBuffer has its own. It keeps its world while its inputs are
//! the same materials and texture (by identity), so an upstream node that
//! evaluates every frame with unchanged materials (an animated glTF file)
//! costs no upload.

use std::sync::Arc;

use spreadlight_graph::{
    EvalContext, In, Node, NodeDef, NodeError, Out, Registry, Res, ResourceKind,
};
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
        .with_pins_node(|p| {
            let pins = MaterialBufferPins {
                materials: material_input(p, "Materials"),
                textures: texture_input(p, "Textures"),
                out: p.output_resource::<MaterialWorld>("Material World", ResourceKind::MaterialWorld),
            };
            move || MaterialBufferNode { pins, last: None }
        }),
    );
}

#[derive(Clone, Copy)]
struct MaterialBufferPins {
    materials: In<Res<Material>>,
    textures: In<Res<TextureRef>>,
    out: Out<Res<MaterialWorld>>,
}

/// The inputs a world was made from, by identity, and the world.
struct Made {
    materials: Vec<Arc<Material>>,
    texture: Option<Arc<TextureRef>>,
    world: Arc<MaterialWorld>,
}

impl Made {
    fn is_from(&self, materials: &[Arc<Material>], texture: Option<&Arc<TextureRef>>) -> bool {
        self.materials.len() == materials.len()
            && self
                .materials
                .iter()
                .zip(materials)
                .all(|(a, b)| Arc::ptr_eq(a, b))
            && match (&self.texture, texture) {
                (None, None) => true,
                (Some(a), Some(b)) => Arc::ptr_eq(a, b),
                _ => false,
            }
    }
}

struct MaterialBufferNode {
    pins: MaterialBufferPins,
    /// The last world: an upstream node that evaluates again with the same
    /// materials (an animated glTF file keeps its materials' `Arc`s) gets
    /// it back instead of a new upload and new buffers every frame.
    last: Option<Made>,
}

impl Node for MaterialBufferNode {
    fn evaluate(&mut self, cx: &mut EvalContext<'_>) -> Result<(), NodeError> {
        let MaterialBufferPins {
            materials: materials_in,
            textures: textures_in,
            out,
        } = self.pins;
        let renderer = renderer(cx)?;
        let materials = cx.resources(materials_in)?;
        let textures = cx.resources(textures_in)?;
        if textures.len() > 1 {
            return Err(cx.error(
                textures_in,
                format!(
                    "takes one texture array, got {} textures: join them with FileTexture (Array)",
                    textures.len()
                ),
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
        let texture = textures.first();
        let kept = self
            .last
            .as_ref()
            .filter(|made| made.is_from(&materials, texture));
        if let Some(made) = kept {
            cx.put_resources(out, vec![made.world.clone()]);
            return Ok(());
        }
        let world = MaterialWorld::with_textures(
            &renderer,
            materials.iter().map(|m| Material::clone(m)).collect(),
            texture.map(|t| TextureRef::clone(t)),
        );
        cx.put_resources(out, vec![world.clone()]);
        self.last = Some(Made {
            materials,
            texture: texture.cloned(),
            world,
        });
        Ok(())
    }
}
