//! `DeferredBase`: a spread of meshes drawn with a spread of transforms,
//! instanced (one draw per distinct mesh), with Emeshe's feature switches as
//! pins. A switch the geometry cannot serve is an error on this node.

use std::collections::HashMap;
use std::sync::Arc;

use glam::Mat4;
use spreadlight_graph::spread::{cycled, slice_count};
use spreadlight_graph::{
    Color, EnumDef, EvalContext, Node, NodeDef, NodeError, PinType, Registry, ResourceKind, Spread,
};
use spreadlight_render::TextureRef;
use spreadlight_render::gbuffer::{DrawBatch, InstanceInput, Layer, LayerFeatures, VelocitySource};
use spreadlight_render::material::MaterialWorld;
use spreadlight_render::mesh_arena::GpuMesh;

use crate::gpu::{resource_spread, resources};

pub static VELOCITY: EnumDef = EnumDef {
    name: "Velocity Source",
    options: &["Transforms", "Geometry", "Off"],
};

const MESH: usize = 0;
const TRANSFORM: usize = 1;
const COLOR: usize = 2;
const MATERIAL_ID: usize = 3;
const OBJECT_ID: usize = 4;
const TEXCOORDS: usize = 5;
const NORMAL_MAPPING: usize = 6;
const NORMAL_TEXTURE: usize = 7;
const TRIPLANAR: usize = 8;
const VELOCITY_PIN: usize = 9;
const IDS: usize = 10;
const COLOR_TEXTURE: usize = 11;
const MATERIAL_WORLD: usize = 12;
const GEOMETRY_IDS: usize = 13;

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
        .input_spread("Mesh", PinType::Resource(ResourceKind::Mesh), Spread::Resource(ResourceKind::Mesh, vec![]))
        .input("Transform", Mat4::IDENTITY)
        .input("Color", Color::WHITE)
        .input("Material ID", 0i64)
        .input("Object ID", 0i64)
        .input("Texture Coordinates", false)
        .input("Normal Mapping", false)
        .input_spread(
            "Normal Texture",
            PinType::Resource(ResourceKind::Texture),
            Spread::Resource(ResourceKind::Texture, vec![]),
        )
        .input("Triplanar", false)
        .input_enum("Velocity", &VELOCITY, "Transforms")
        .input("IDs", true)
        .input_spread(
            "Color Texture",
            PinType::Resource(ResourceKind::Texture),
            Spread::Resource(ResourceKind::Texture, vec![]),
        )
        .input_spread(
            "Material World",
            PinType::Resource(ResourceKind::MaterialWorld),
            Spread::Resource(ResourceKind::MaterialWorld, vec![]),
        )
        .input("Instance from GeomFX", false)
        .output_typed("Layer", PinType::Resource(ResourceKind::Layer))
        // Last frame's transforms, for per-object velocity.
        .remembers(1)
        .construct(DeferredBase::default),
    );
}

/// Keeps last frame's transforms, for velocity.
#[derive(Default)]
struct DeferredBase {
    previous: Vec<Mat4>,
}

impl Node for DeferredBase {
    fn evaluate(&mut self, cx: &mut EvalContext<'_>) -> Result<(), NodeError> {
        let meshes = resources::<GpuMesh>(cx, MESH)?;
        let transforms = cx.slices::<Mat4>(TRANSFORM)?;
        let colors = cx.slices::<Color>(COLOR)?;
        let materials = cx.slices::<i64>(MATERIAL_ID)?;
        let objects = cx.slices::<i64>(OBJECT_ID)?;
        let flag = |pin: usize| -> Result<bool, NodeError> {
            Ok(cx.slices::<bool>(pin)?.first().copied().unwrap_or(false))
        };
        let velocity = match cx.enum_slices(VELOCITY_PIN)?.first().map(String::as_str) {
            Some("Geometry") => VelocitySource::Geometry,
            Some("Off") => VelocitySource::Off,
            _ => VelocitySource::Transforms,
        };
        let features = LayerFeatures {
            texcoords: flag(TEXCOORDS)?,
            normal_map: flag(NORMAL_MAPPING)?,
            triplanar: flag(TRIPLANAR)?,
            velocity,
            ids: flag(IDS)?,
            geometry_ids: flag(GEOMETRY_IDS)?,
            // `Triplanar (Layer)` changes it on the way to MRE.
            ..LayerFeatures::default()
        };
        let first_texture = |pin: usize| -> Result<Option<TextureRef>, NodeError> {
            Ok(match cx.input(pin) {
                Spread::Resource(_, v) if !v.is_empty() => resources::<TextureRef>(cx, pin)?
                    .into_iter()
                    .next()
                    .map(|t| (*t).clone()),
                _ => None,
            })
        };
        let normal_map = first_texture(NORMAL_TEXTURE)?;
        let world = resources::<MaterialWorld>(cx, MATERIAL_WORLD)?
            .into_iter()
            .next();
        let color_map = first_texture(COLOR_TEXTURE)?;

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
            .map_err(|e| cx.input_error(COLOR_TEXTURE, e.to_string()))?
            .with_materials(world);
        cx.set_output(
            0,
            resource_spread(ResourceKind::Layer, vec![Arc::new(layer)]),
        );
        Ok(())
    }
}
