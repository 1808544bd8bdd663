//! The `glTF` node over generated files: its materials join the material
//! world at stable ids, a patch changes one by name, its lights start light
//! lists, many instances of one mesh stay one draw, and Variant picks a
//! `KHR_materials_variants` variant's materials (an unknown one reported).

use std::sync::Arc;

use spreadlight_gltf::models;
use spreadlight_graph::{FrameClock, NodeDoc, NodeId, Patch, Runtime, Spread};
use spreadlight_render::lighting::PointLight;
use spreadlight_render::material::{FEATURE_SURFACE_MAPS, Feature, MaterialWorld};

use crate::lighting::add_light::LightList;

/// Run `patch` one frame with a GPU (the model at `model`), expecting no errors.
fn run(patch: &Patch, dir: &std::path::Path) -> Runtime {
    let mut runtime = Runtime::new(crate::registry());
    runtime.provide(spreadlight_render::renderer::test_renderer());
    runtime.provide(Arc::new(spreadlight_graph::PatchDir(dir.to_owned())));
    let problems = runtime.load(patch);
    assert!(problems.is_empty(), "{problems:?}");
    runtime.evaluate(FrameClock::default());
    let errors: Vec<_> = runtime
        .node_errors()
        .map(|(id, e)| format!("{id}: {e}"))
        .collect();
    assert!(errors.is_empty(), "{errors:?}");
    runtime
}

fn resource<T: std::any::Any + Send + Sync>(rt: &Runtime, node: u32, pin: &str) -> Vec<Arc<T>> {
    match rt.output(NodeId(node), pin).map(|s| s.as_ref()) {
        Some(Spread::Resource(_, handles)) => handles
            .iter()
            .map(|h| h.downcast_arc::<T>().expect("type"))
            .collect(),
        other => panic!("{node}.{pin}: {other:?}"),
    }
}

#[test]
fn gltf_materials_join_the_world_and_one_is_changed_by_name() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("cube.gltf"), models::textured_cube()).unwrap();
    let mut patch = Patch::default();
    patch.add(
        NodeDoc::new(1, "glTF")
            .with("Filename", vec!["cube.gltf".to_owned()])
            .with("First Material ID", vec![3i64]),
    );
    patch.add(NodeDoc::new(2, "MaterialByName").with("Name", vec!["Painted".to_owned()]));
    patch.add(NodeDoc::new(3, "AddReflection"));
    patch.add(NodeDoc::new(4, "MaterialManager"));
    patch.add(NodeDoc::new(5, "MaterialBuffer"));
    patch.add(NodeDoc::new(6, "Probe"));
    patch.link(1, "Materials", 2, "Materials");
    patch.link(1, "Material Names", 2, "Names");
    patch.link(2, "Material", 3, "Material");
    patch.link(1, "Materials", 4, "Materials");
    patch.link(3, "Material", 4, "Material");
    patch.link(2, "Material ID", 4, "Material ID");
    patch.link(4, "Materials", 5, "Materials");
    patch.link(5, "Material World", 6, "Input");
    let rt = run(&patch, dir.path());
    // Ids 0..3 are the patch's (default materials), 3 glTF's default, 4 "Painted".
    let ids = rt.output(NodeId(1), "Material ID").unwrap();
    assert_eq!(ids.as_ref(), &Spread::Int(vec![4]));
    let world = resource::<MaterialWorld>(&rt, 5, "Material World").remove(0);
    assert_eq!(world.len(), 5);
    assert!(world.has_maps());
    let painted = world.flags(4);
    assert_ne!(painted & (1 << FEATURE_SURFACE_MAPS), 0, "maps kept");
    assert_ne!(
        painted & Feature::Reflection.flag(),
        0,
        "reflection added by name"
    );
    assert_eq!(
        world.flags(3) & Feature::Reflection.flag(),
        0,
        "others unchanged"
    );
    assert!(
        world.params(4, Feature::Emission).is_some(),
        "the emissive factor"
    );
}

#[test]
fn lights_start_light_lists_and_instances_of_one_mesh_are_one_batch() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("lights.gltf"),
        models::punctual_lights_scene(),
    )
    .unwrap();
    let mut patch = Patch::default();
    patch.add(NodeDoc::new(1, "glTF").with("Filename", vec!["lights.gltf".to_owned()]));
    patch.add(NodeDoc::new(2, "AddLight (Point)").with("ID", vec!["mine".to_owned()]));
    patch.add(NodeDoc::new(3, "Probe"));
    patch.link(1, "Point Lights", 2, "Lights");
    patch.link(2, "Lights", 3, "Input");
    let rt = run(&patch, dir.path());
    let list = resource::<LightList<PointLight>>(&rt, 2, "Lights").remove(0);
    assert_eq!(
        list.ids,
        vec!["lights.gltf: light 0".to_owned(), "mine".to_owned()]
    );
    let p = list.lights[0].position;
    assert!((p - glam::Vec3::new(-1.5, 1.5, 1.0)).length() < 1e-5, "{p}");
    assert_eq!(
        resource::<LightList<spreadlight_render::lighting::SpotLight>>(&rt, 1, "Spot Lights")[0]
            .lights
            .len(),
        1
    );

    // 2,000 nodes of one glTF mesh: one mesh handle, so DeferredBase draws them in one batch.
    std::fs::write(
        dir.path().join("grid.gltf"),
        models::bench_grid(2000, 1, 0, false),
    )
    .unwrap();
    let mut patch = Patch::default();
    patch.add(NodeDoc::new(1, "glTF").with("Filename", vec!["grid.gltf".to_owned()]));
    patch.add(NodeDoc::new(2, "Probe"));
    patch.link(1, "Mesh", 2, "Input");
    let rt = run(&patch, dir.path());
    let meshes = resource::<spreadlight_render::mesh_arena::GpuMesh>(&rt, 1, "Mesh");
    assert_eq!(meshes.len(), 2000);
    assert!(meshes.iter().all(|m| Arc::ptr_eq(m, &meshes[0])));
}

#[test]
fn five_thousand_nodes_load_and_draw_as_one_batch_per_mesh() {
    // 5,000 nodes over 5 meshes (one per material of the generated grid):
    // all instances arrive, and DeferredBase merges them into one draw per mesh.
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("nodes.gltf"),
        models::bench_grid(5000, 5, 0, false),
    )
    .unwrap();
    let mut patch = Patch::default();
    patch.add(NodeDoc::new(1, "glTF").with("Filename", vec!["nodes.gltf".to_owned()]));
    patch.add(NodeDoc::new(2, "DeferredBase"));
    patch.add(NodeDoc::new(3, "Probe"));
    for pin in ["Mesh", "Transform", "Material ID"] {
        patch.link(1, pin, 2, pin);
    }
    patch.link(1, "Base Color", 2, "Color");
    patch.link(2, "Layer", 3, "Input");
    let rt = run(&patch, dir.path());
    let meshes = resource::<spreadlight_render::mesh_arena::GpuMesh>(&rt, 1, "Mesh");
    assert_eq!(meshes.len(), 5000, "one slice per instance");
    let layer = resource::<spreadlight_render::gbuffer::Layer>(&rt, 2, "Layer").remove(0);
    assert_eq!(layer.batches.len(), 5, "one draw per mesh");
    for batch in &layer.batches {
        assert_eq!(batch.instances.len(), 1000);
    }
    // Every instance keeps its own place.
    let places: std::collections::HashSet<[u32; 3]> = layer
        .batches
        .iter()
        .flat_map(|b| &b.instances)
        .map(|i| i.transform.w_axis.truncate().to_array().map(f32::to_bits))
        .collect();
    assert_eq!(places.len(), 5000);
}

#[test]
fn variant_picks_each_instances_material_and_an_unknown_one_is_reported() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("box.gltf"), models::material_variants()).unwrap();
    // Material ids: 0 glTF's default, then Red 1, Green 2, Blue 3, White 4, Black 5.
    let frame = |variant: &str| {
        let mut patch = Patch::default();
        patch.add(
            NodeDoc::new(1, "glTF")
                .with("Filename", vec!["box.gltf".to_owned()])
                .with("Variant", vec![variant.to_owned()]),
        );
        // A sink, so the node runs.
        patch.add(NodeDoc::new(2, "Probe"));
        patch.link(1, "Material ID", 2, "Input");
        let mut runtime = Runtime::new(crate::registry());
        runtime.provide(spreadlight_render::renderer::test_renderer());
        runtime.provide(Arc::new(spreadlight_graph::PatchDir(dir.path().to_owned())));
        assert!(runtime.load(&patch).is_empty());
        runtime.evaluate(FrameClock::default());
        let errors: Vec<String> = runtime.node_errors().map(|(_, e)| e.to_string()).collect();
        let ids = match runtime.output(NodeId(1), "Material ID").map(|s| s.as_ref()) {
            Some(Spread::Int(ids)) => ids.clone(),
            other => panic!("{other:?}"),
        };
        let colours = match runtime.output(NodeId(1), "Base Color").map(|s| s.as_ref()) {
            Some(Spread::Color(c)) => c.iter().map(|c| [c.r, c.g, c.b, c.a]).collect::<Vec<_>>(),
            other => panic!("{other:?}"),
        };
        (ids, colours, errors)
    };
    // Body, then lid (Forest leaves the lid White).
    for (variant, want) in [
        ("", [1, 4]),
        ("Forest", [2, 4]),
        ("Ocean", [3, 5]),
        ("1", [3, 5]),
    ] {
        let (ids, _, errors) = frame(variant);
        assert!(errors.is_empty(), "{variant}: {errors:?}");
        assert_eq!(ids, want, "`{variant}`");
    }
    // The material colour follows: Ocean's body is blue.
    let (_, colours, _) = frame("Ocean");
    assert_eq!(colours[0], [0.05, 0.05, 0.8, 1.0]);
    // Unknown: the default materials, and the node says which file and
    // which variants it has.
    let (ids, colours, errors) = frame("Desert");
    assert_eq!(ids, [1, 4]);
    assert_eq!(colours[0], [0.8, 0.05, 0.05, 1.0]);
    assert!(
        errors.len() == 1
            && errors[0].contains("box.gltf")
            && errors[0].contains("`Desert`")
            && errors[0].contains("`Forest`, `Ocean`"),
        "{errors:?}"
    );
}
