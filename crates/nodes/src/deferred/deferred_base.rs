//! `DeferredBase`: a spread of meshes drawn with a spread of transforms,
//! instanced (one draw per distinct mesh), with Emeshe's feature switches as
//! pins. A switch the geometry cannot serve is an error on this node.

use std::collections::HashMap;
use std::sync::Arc;

use glam::Mat4;
use spreadlight_graph::spread::{cycled, slice_count};
use spreadlight_graph::{
    Choice, Choices, Color, EvalContext, In, Node, NodeDef, NodeError, Out, Registry, Res,
    ResourceKind, Spread,
};
use spreadlight_render::TextureRef;
use spreadlight_render::gbuffer::{DrawBatch, InstanceInput, Layer, LayerFeatures, VelocitySource};
use spreadlight_render::material::MaterialWorld;
use spreadlight_render::mesh_arena::GpuMesh;

use crate::post::{optional_texture, texture_input};

pub static VELOCITY: Choices<VelocitySource> = Choices::new(
    "Velocity Source",
    &["Transforms", "Geometry", "Off"],
    &[
        VelocitySource::Transforms,
        VelocitySource::Geometry,
        VelocitySource::Off,
    ],
);

#[derive(Clone, Copy)]
struct Pins {
    mesh: In<Res<GpuMesh>>,
    transform: In<Mat4>,
    color: In<Color>,
    material_id: In<i64>,
    object_id: In<i64>,
    texcoords: In<bool>,
    normal_mapping: In<bool>,
    normal_texture: In<Res<TextureRef>>,
    triplanar: In<bool>,
    velocity: In<Choice<VelocitySource>>,
    ids: In<bool>,
    color_texture: In<Res<TextureRef>>,
    material_world: In<Res<MaterialWorld>>,
    geometry_ids: In<bool>,
    out: Out<Res<Layer>>,
}

pub fn register(r: &mut Registry) {
    r.add(
        NodeDef::new(
            "DeferredBase",
            super::CATEGORY,
            "Draws a spread of meshes with a spread of transforms into a layer for MRE. Slice i uses mesh i and \
             transform i (wrapping); instances of one mesh are one draw. The switches choose what the G-buffer \
             receives; each is a shader feature compiled only when used. Color Texture scales Color (albedo) at the \
             surface's UV (needs Texture Coordinates or Triplanar). Color's alpha is opacity for Transparency only: \
             the G-buffer keeps the material id there. Normal Mapping reads the mesh's UVs unless Triplanar is on. \
             Triplanar projects world position on three planes and blends the Color and Normal Textures' three samples by \
             the normal's components (Triplanar (Layer) sets how sharply), so there is no seam; the G-buffer's UV (what \
             material textures read) is the plane the surface faces most. \
             Material World: the MaterialBuffer the Material IDs index, needed where materials have surface maps (glTF \
             textures, alpha modes, double-sided): the G-buffer samples them per pixel, trilinear and anisotropic. \
             Velocity Geometry reads the meshes' previous positions (GPU geometry and particles make them); Instance \
             from GeomFX adds each triangle's geometry id (a particle's index, say) to its Object ID.",
        )
        // Last frame's transforms, for per-object velocity.
        .remembers(1)
        .with_pins_node(|p| {
            let pins = Pins {
                mesh: p.input_resource::<GpuMesh>("Mesh", ResourceKind::Mesh),
                transform: p.input("Transform", Mat4::IDENTITY),
                color: p.input("Color", Color::WHITE),
                material_id: p.input("Material ID", 0i64),
                object_id: p.input("Object ID", 0i64),
                texcoords: p.input("Texture Coordinates", false),
                normal_mapping: p.input("Normal Mapping", false),
                normal_texture: texture_input(p, "Normal Texture"),
                triplanar: p.input("Triplanar", false),
                velocity: p.input_choice("Velocity", &VELOCITY, VelocitySource::Transforms),
                ids: p.input("IDs", true),
                color_texture: texture_input(p, "Color Texture"),
                material_world: p.input_resource::<MaterialWorld>("Material World", ResourceKind::MaterialWorld),
                geometry_ids: p.input("Instance from GeomFX", false),
                out: p.output_resource::<Layer>("Layer", ResourceKind::Layer),
            };
            move || DeferredBase {
                pins,
                previous: Vec::new(),
            }
        }),
    );
}

/// Keeps last frame's transforms, for velocity.
struct DeferredBase {
    pins: Pins,
    previous: Vec<Mat4>,
}

impl Node for DeferredBase {
    fn evaluate(&mut self, cx: &mut EvalContext<'_>) -> Result<(), NodeError> {
        let pins = self.pins;
        let meshes = cx.resources(pins.mesh)?;
        let transforms = cx.get(pins.transform)?;
        let colors = cx.get(pins.color)?;
        let materials = cx.get(pins.material_id)?;
        let objects = cx.get(pins.object_id)?;
        let flag = |pin: In<bool>| cx.first(pin, false);
        let velocity = cx.choice(pins.velocity)?;
        let features = LayerFeatures {
            texcoords: flag(pins.texcoords)?,
            normal_map: flag(pins.normal_mapping)?,
            triplanar: flag(pins.triplanar)?,
            velocity,
            ids: flag(pins.ids)?,
            geometry_ids: flag(pins.geometry_ids)?,
            // `Triplanar (Layer)` changes it on the way to MRE.
            ..LayerFeatures::default()
        };
        let first_texture = |pin: In<Res<TextureRef>>| -> Result<Option<TextureRef>, NodeError> {
            Ok(match cx.spread(pin) {
                Spread::Resource(_, v) if !v.is_empty() => optional_texture(cx, pin)?,
                _ => None,
            })
        };
        let normal_map = first_texture(pins.normal_texture)?;
        let world = cx.first_resource(pins.material_world)?;
        let color_map = first_texture(pins.color_texture)?;

        let n = slice_count([
            meshes.len(),
            transforms.len(),
            colors.len(),
            materials.len(),
            objects.len(),
        ]);
        let mut batches: Vec<DrawBatch> = Vec::new();
        let mut batch_of: HashMap<*const GpuMesh, usize> = HashMap::new();
        let mut moved = false;
        let slices = cycled(&meshes, n)
            .zip(cycled(transforms, n))
            .zip(cycled(colors, n))
            .zip(cycled(materials, n))
            .zip(cycled(objects, n));
        for (i, ((((mesh, transform), color), material), object)) in slices.enumerate() {
            let previous = match (velocity, self.previous.get(i)) {
                (VelocitySource::Off, _) | (_, None) => *transform,
                (_, Some(p)) => *p,
            };
            moved |= previous != *transform;
            let ids = |v: i64| {
                if features.ids {
                    v.clamp(0, 2048) as u32
                } else {
                    0
                }
            };
            let instance = InstanceInput {
                transform: *transform,
                previous_transform: previous,
                color: [color.r, color.g, color.b, color.a],
                material_id: ids(*material),
                object_id: ids(*object),
            };
            let key = Arc::as_ptr(mesh);
            let b = *batch_of.entry(key).or_insert_with(|| {
                batches.push(DrawBatch {
                    mesh: mesh.clone(),
                    instances: Vec::new(),
                });
                batches.len() - 1
            });
            batches[b].instances.push(instance);
        }
        self.previous = cycled(transforms, n).copied().collect();
        if moved {
            // Velocity is last frame's motion: next frame must see it settle to zero.
            cx.reevaluate_next_frame();
        }
        let layer = Layer::new(Some(cx.node_id.0), batches, features, normal_map)
            .map_err(|e| NodeError::Other(e.to_string()))?
            .with_color_map(color_map)
            .map_err(|e| cx.error(pins.color_texture, e.to_string()))?
            .with_materials(world);
        cx.put_resources(pins.out, vec![Arc::new(layer)]);
        Ok(())
    }
}
