//! `glTF`: loads a .gltf or .glb file into a spread of mesh instances, one
//! slice per instance: its mesh, world transform, base colour and material
//! id, ready for `DeferredBase`; and the file's materials as materials of
//! the one material world (slice i = material id i, what `MaterialManager`
//! chains and `MaterialBuffer` uploads), with their names so a patch can
//! pick one (`MaterialByName`) and change it; its `KHR_lights_punctual`
//! lights as light lists that start `AddLight` chains; its cameras as View
//! and Projection. Variant picks a `KHR_materials_variants` variant (by
//! name or index; empty: the file's default materials): only the instances'
//! material ids change, nothing is reloaded. Time and Animation pose the scene (node TRS animations,
//! skins and morph weights: skinned and morphed instances are deformed on
//! the GPU, see `gltf_deform`); the files are loaded and uploaded once and
//! kept while Filename stays.
//! A broken or unsupported file is an error on the node that names the
//! file and what is wrong.

use std::sync::Arc;

use glam::Mat4;
use spreadlight_gltf::GltfScene;
use spreadlight_gltf::MaterialData;
use spreadlight_gltf::load_gltf;
use spreadlight_graph::{
    Choice, Choices, Color, EvalContext, In, Node, NodeDef, NodeError, Out, Registry, Res,
    ResourceKind,
};
use spreadlight_render::lighting::{PointLight, SpotLight, SunLight};
use spreadlight_render::material::Material;
use spreadlight_render::material::maps::AlphaMode;
use spreadlight_render::mesh_arena::GpuMesh;

use super::gltf_deform::{Deformer, Ran};
use crate::gpu::renderer;
use crate::lighting::add_light::LightList;

fn empty<T>() -> LightList<T> {
    LightList {
        ids: Vec::new(),
        lights: Vec::new(),
    }
}

/// `named` lights appended to `list`, each ID the light's name in the file
/// (`file: name`, unique across files and lights).
fn extend<T: Clone>(list: &mut LightList<T>, named: &[(String, T)], file: &str) {
    for (name, light) in named {
        let mut id = format!("{file}: {name}");
        if list.ids.contains(&id) {
            id = format!("{id} #{}", list.ids.len());
        }
        list.ids.push(id);
        list.lights.push(light.clone());
    }
}

/// Which instances the node outputs, by their material's alpha mode.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Instances {
    All,
    Opaque,
    Blend,
}

pub static INSTANCES: Choices<Instances> = Choices::new(
    "glTF Instances",
    &["All", "Opaque", "Blend"],
    &[Instances::All, Instances::Opaque, Instances::Blend],
);

#[derive(Clone, Copy)]
struct GltfPins {
    filename: In<String>,
    first_id: In<i64>,
    time: In<f32>,
    animation: In<i64>,
    instances: In<Choice<Instances>>,
    variant: In<String>,
    mesh: Out<Res<GpuMesh>>,
    transform: Out<Mat4>,
    base_color: Out<Color>,
    material_id: Out<i64>,
    materials: Out<Res<Material>>,
    material_names: Out<String>,
    point_lights: Out<Res<LightList<PointLight>>>,
    spot_lights: Out<Res<LightList<SpotLight>>>,
    sun_lights: Out<Res<LightList<SunLight>>>,
    view: Out<Mat4>,
    projection: Out<Mat4>,
}

/// Material ids beyond this are a mistake, as in `MaterialManager`.
const MAX_FIRST_ID: i64 = 60_000;

pub fn register(r: &mut Registry) {
    r.add(
        NodeDef::new(
            "glTF",
            "Geometry",
            "Loads a glTF 2.0 file (.gltf or .glb): one output slice per mesh instance of the default scene, with its \
             world transform, material base colour and Material ID. Materials: the file's materials as materials of the \
             material world, at stable ids: First Material ID for glTF's default material, then one per file material in \
             file order (ids below First hold the default material, so patch materials placed there by a MaterialManager \
             coexist). Their textures, alpha modes and sidedness are surface maps, read by DeferredBase when its Material \
             World pin has them. Material Names: each id's name (empty where none). Point, Spot and Sun Lights: the \
             file's KHR_lights_punctual lights (candela, lux), to wire into an AddLight chain's Lights or a light buffer. \
             View and Projection: one slice per camera of the scene. Time (seconds) and Animation (index; -1: none) pose \
             the nodes with the file's animations, looping: node TRS channels, skins (up to 8 joint influences per \
             vertex, JOINTS_0/1) and morph target weights. Skinned and morphed instances are deformed on the GPU (one \
             compute dispatch per file and pose change) into meshes that carry last frame's positions, for DeferredBase's \
             Velocity Geometry; skinned instances come out in world space with an identity Transform. Instances: All, Opaque (OPAQUE and MASK materials, for the \
             G-buffer) or Blend (BLEND materials, for a DeferredBase layer drawn by Transparency: Base Color's alpha is \
             their opacity). Variant: a KHR_materials_variants variant of the file, by name or index (empty: the file's \
             default materials; one slice per file, cycling); each instance gets its primitive's material for it (the same material ids: the \
             Materials output holds every material of the file); an unknown one is reported on the node, naming the \
             file and its variants, and the default materials are shown. A relative Filename is relative to the \
             patch's folder.",
        )
        .with_pins_node(|p| {
            let pins = GltfPins {
                filename: p.input("Filename", String::new()),
                first_id: p.input("First Material ID", 0i64),
                time: p.input("Time", 0.0f32),
                animation: p.input("Animation", 0i64),
                instances: p.input_choice("Instances", &INSTANCES, Instances::All),
                variant: p.input("Variant", String::new()),
                mesh: super::mesh_output(p, "Mesh"),
                transform: p.output::<Mat4>("Transform"),
                base_color: p.output::<Color>("Base Color"),
                material_id: p.output::<i64>("Material ID"),
                materials: p.output_resource::<Material>("Materials", ResourceKind::Material),
                material_names: p.output::<String>("Material Names"),
                point_lights: p.output_resource::<LightList<PointLight>>("Point Lights", ResourceKind::PointLights),
                spot_lights: p.output_resource::<LightList<SpotLight>>("Spot Lights", ResourceKind::SpotLights),
                sun_lights: p.output_resource::<LightList<SunLight>>("Sun Lights", ResourceKind::SunLights),
                view: p.output::<Mat4>("View"),
                projection: p.output::<Mat4>("Projection"),
            };
            move || GltfNode {
                pins,
                loaded: Vec::new(),
                from: Vec::new(),
                materials: None,
            }
        }),
    );
}

/// A loaded file: the scene, its meshes on the GPU (at rest), and what
/// deforms its skinned and morphed instances.
struct Loaded {
    file: String,
    scene: GltfScene,
    meshes: Vec<Arc<GpuMesh>>,
    deformer: Option<Deformer>,
}

/// Keeps the loaded files while Filename is unchanged, so posing at a new
/// Time does not read or upload anything.
struct GltfNode {
    pins: GltfPins,
    loaded: Vec<Loaded>,
    /// The Filename slices `loaded` was made from (resolved).
    from: Vec<std::path::PathBuf>,
    /// The Materials and Material Names outputs for `loaded` at a First
    /// Material ID, kept while both are unchanged: an animated file then
    /// gives the same materials every frame, which MaterialBuffer reuses.
    materials: Option<Materials>,
}

/// The materials of the loaded files from First Material ID on, and their names.
struct Materials {
    first: i64,
    list: Vec<Arc<Material>>,
    names: Vec<String>,
}

impl Materials {
    /// Ids below `first` hold one shared default; then each file's default
    /// material and its materials, file after file.
    fn of(loaded: &[Loaded], first: i64) -> Materials {
        let default = Arc::new(Material::default_material());
        let mut list = vec![default; first as usize];
        let mut names = vec![String::new(); first as usize];
        for file in loaded {
            list.push(Arc::new(MaterialData::default().to_material()));
            names.push(String::new());
            for m in &file.scene.materials {
                list.push(Arc::new(m.to_material()));
                names.push(m.name.clone().unwrap_or_default());
            }
        }
        Materials { first, list, names }
    }
}

impl GltfNode {
    fn load(&mut self, cx: &EvalContext<'_>) -> Result<(), NodeError> {
        let files: Vec<String> = cx
            .get(self.pins.filename)?
            .iter()
            .filter(|f| !f.is_empty())
            .cloned()
            .collect();
        let paths: Vec<_> = files.iter().map(|f| cx.resolve_path(f)).collect();
        if paths == self.from && !self.loaded.is_empty() {
            return Ok(());
        }
        let renderer = renderer(cx)?;
        let mut loaded = Vec::new();
        for (file, path) in files.iter().zip(&paths) {
            let scene = load_gltf(path).map_err(|e| cx.error(self.pins.filename, e.to_string()))?;
            let meshes = scene
                .meshes
                .iter()
                .map(|m| renderer.meshes.upload(&renderer.gpu, m))
                .collect::<Result<_, _>>()
                .map_err(|e| NodeError::Other(format!("{file}: {e}")))?;
            let deformer = Deformer::new(&renderer, &scene)
                .map_err(|e| NodeError::Other(format!("{file}: {e}")))?;
            loaded.push(Loaded {
                file: file.clone(),
                scene,
                meshes,
                deformer,
            });
        }
        self.loaded = loaded;
        self.from = paths;
        self.materials = None;
        Ok(())
    }
}

impl Node for GltfNode {
    fn evaluate(&mut self, cx: &mut EvalContext<'_>) -> Result<(), NodeError> {
        let pins = self.pins;
        let first = cx.first(pins.first_id, 0)?;
        if !(0..=MAX_FIRST_ID).contains(&first) {
            return Err(cx.error(
                pins.first_id,
                format!("{first} is outside 0..={MAX_FIRST_ID}"),
            ));
        }
        let time = cx.first(pins.time, 0.0)?;
        let animation = cx.first(pins.animation, -1)?;
        let which = cx.choice(pins.instances)?;
        // One variant per file, the slices cycling with Filename's.
        let variants: Vec<String> = cx.get(pins.variant)?.to_vec();
        self.load(cx)?;
        let (mut meshes, mut transforms, mut colors, mut ids) =
            (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        if self.materials.as_ref().is_none_or(|m| m.first != first) {
            self.materials = Some(Materials::of(&self.loaded, first));
        }
        // Each file's materials start at the ids after the files before it.
        let mut base = first;
        let (mut points, mut spots, mut suns) = (empty(), empty(), empty());
        let (mut views, mut projections) = (Vec::new(), Vec::new());
        let mut settle = false;
        for (f, loaded) in self.loaded.iter_mut().enumerate() {
            let Loaded {
                file,
                scene,
                meshes: uploaded,
                deformer,
            } = loaded;
            // This file's default material, then its materials.
            let file_base = base;
            base += 1 + scene.materials.len() as i64;
            // Instances, lights and cameras follow their (animated) nodes.
            let animation = usize::try_from(animation).ok();
            let world = scene.node_worlds(animation, time);
            if let Some(d) = deformer.as_mut() {
                let weights = scene.morph_weights(animation, time);
                let renderer = renderer(cx)?;
                match d
                    .pose(&renderer, scene, uploaded, &world, &weights)
                    .map_err(|e| NodeError::Other(format!("{file}: {e}")))?
                {
                    Ran::Deformed { settle: true } => settle = true,
                    Ran::Deformed { settle: false } | Ran::Nothing => {}
                }
            }
            // An unknown variant is shown on the node; the file keeps its
            // default materials and the rest of the patch runs.
            let variant = variants.get(f % variants.len().max(1));
            let chosen = scene
                .variant(variant.map_or("", |v| v))
                .unwrap_or_else(|e| {
                    cx.report(NodeError::Other(format!("{file}: {e}")));
                    None
                });
            let (lights, cameras) = scene.posed_content(&world);
            extend(&mut points, &lights.points, file);
            extend(&mut spots, &lights.spots, file);
            extend(&mut suns, &lights.suns, file);
            for camera in &cameras {
                views.push(camera.view);
                projections.push(camera.projection);
            }
            for (k, instance) in scene.instances.iter().enumerate() {
                let index = instance.material_in(chosen);
                let material = index.and_then(|m| scene.materials.get(m));
                let blend = material.is_some_and(|m| m.alpha_mode == AlphaMode::Blend);
                match which {
                    Instances::Opaque if blend => continue,
                    Instances::Blend if !blend => continue,
                    _ => {}
                }
                match deformer.as_ref().and_then(|d| d.mesh(k)) {
                    Some((mesh, transform)) => {
                        meshes.push(mesh.clone());
                        transforms.push(transform);
                    }
                    None => {
                        meshes.push(uploaded[instance.mesh].clone());
                        transforms.push(
                            world
                                .get(instance.node)
                                .copied()
                                .unwrap_or(instance.transform),
                        );
                    }
                }
                let c = material.map_or([1.0; 4], |m| m.base_color);
                colors.push(Color::rgba(c[0], c[1], c[2], c[3]));
                ids.push(file_base + index.map_or(0, |m| m as i64 + 1));
            }
        }
        cx.put_resources(pins.mesh, meshes);
        cx.put(pins.transform, transforms);
        cx.put(pins.base_color, colors);
        cx.put(pins.material_id, ids);
        let materials = self.materials.as_ref().expect("made above");
        cx.put_resources(pins.materials, materials.list.clone());
        cx.put(pins.material_names, materials.names.clone());
        cx.put_resources(pins.point_lights, vec![Arc::new(points)]);
        cx.put_resources(pins.spot_lights, vec![Arc::new(spots)]);
        cx.put_resources(pins.sun_lights, vec![Arc::new(suns)]);
        cx.put(pins.view, views);
        cx.put(pins.projection, projections);
        if settle {
            cx.reevaluate_next_frame();
        }
        Ok(())
    }
}
