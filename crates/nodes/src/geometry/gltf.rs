//! `glTF`: loads a .gltf or .glb file into a spread of mesh instances, one
//! slice per instance: its mesh, world transform and base colour, ready for
//! `DeferredBase`. A broken or unsupported file is an error on the node that
//! names the file and what is wrong.

use std::sync::Arc;

use glam::Mat4;
use spreadlight_graph::{Color, NodeDef, NodeError, PinType, Registry, ResourceKind};
use spreadlight_render::mesh::gltf_import::load_gltf;
use spreadlight_render::mesh_arena::GpuMesh;

use crate::gpu::{renderer, resource_spread};

pub fn register(r: &mut Registry) {
    r.add(
        NodeDef::new(
            "glTF",
            "Geometry",
            "Loads a glTF 2.0 file (.gltf or .glb): one output slice per mesh instance of the default scene, with its \
             world transform and material base colour. A relative Filename is relative to the patch's folder. Missing normals are generated, missing tangents too (MikkTSpace).",
        )
        .input("Filename", String::new())
        .output_typed("Mesh", PinType::Resource(ResourceKind::Mesh))
        .output::<Mat4>("Transform")
        .output::<Color>("Base Color")
        .output::<i64>("Material ID")
        .evaluate(|cx| {
            let files = cx.slices::<String>(0)?.to_vec();
            let renderer = renderer(cx)?;
            let (mut meshes, mut transforms, mut colors, mut materials) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
            for file in files.iter().filter(|f| !f.is_empty()) {
                let scene = load_gltf(&cx.resolve_path(file)).map_err(|e| cx.input_error(0, e.to_string()))?;
                let uploaded: Vec<Arc<GpuMesh>> = scene
                    .meshes
                    .iter()
                    .map(|m| renderer.meshes.upload(&renderer.gpu, m))
                    .collect::<Result<_, _>>()
                    .map_err(|e| NodeError::Other(format!("{file}: {e}")))?;
                for instance in &scene.instances {
                    meshes.push(uploaded[instance.mesh].clone());
                    transforms.push(instance.transform);
                    let material = instance.material.and_then(|m| scene.materials.get(m));
                    let c = material.map_or([1.0; 4], |m| m.base_color);
                    colors.push(Color::rgba(c[0], c[1], c[2], c[3]));
                    materials.push(instance.material.map_or(0, |m| m as i64 + 1));
                }
            }
            cx.set_output(0, resource_spread(ResourceKind::Mesh, meshes));
            cx.set(1, transforms);
            cx.set(2, colors);
            cx.set(3, materials);
            Ok(())
        }),
    );
}
