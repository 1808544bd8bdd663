//! The light nodes: `AddLight` chains on the CPU through `testing::eval`,
//! and the buffers' uploads through a runtime that has a renderer.

use std::sync::Arc;

use glam::{Mat4, Vec3};
use spreadlight_graph::{
    FrameClock, NodeDoc, NodeError, NodeId, Patch, Resource, ResourceKind, Runtime, Spread,
};
use spreadlight_render::lighting::{LightBuffer, LightKind, PointLight};

use super::add_light::LightList;
use crate::testing::{eval, eval_err, floats};

fn points(values: &[(&str, Spread)]) -> Arc<LightList<PointLight>> {
    let out = eval("AddLight (Point)", values).unwrap_or_else(|e| panic!("AddLight failed: {e}"));
    match &out[0] {
        Spread::Resource(ResourceKind::PointLights, handles) if handles.len() == 1 => {
            handles[0].downcast_arc().expect("a list of point lights")
        }
        other => panic!("AddLight output {other:?}"),
    }
}

fn upstream(list: &Arc<LightList<PointLight>>) -> Spread {
    Spread::Resource(
        ResourceKind::PointLights,
        vec![Resource::from_arc(list.clone())],
    )
}

#[test]
fn add_light_chains_keep_order_and_name_every_light() {
    let first = points(&[("Intensity", floats(&[1.0, 2.0, 3.0]))]);
    assert_eq!(first.ids, ["point0", "point1", "point2"]);
    let second = points(&[
        ("Lights", upstream(&first)),
        ("ID", Spread::String(vec!["key".into(), "fill".into()])),
        ("Intensity", floats(&[7.0, 8.0])),
    ]);
    assert_eq!(second.ids, ["point0", "point1", "point2", "key", "fill"]);
    let intensities: Vec<f32> = second.lights.iter().map(|l| l.intensity).collect();
    assert_eq!(intensities, [1.0, 2.0, 3.0, 7.0, 8.0]);
}

#[test]
fn a_light_id_given_twice_is_an_error_naming_it() {
    let first = points(&[("Intensity", floats(&[1.0, 2.0]))]);
    // The same default ID again down the chain.
    let e = eval_err(
        "AddLight (Point)",
        &[
            ("Lights", upstream(&first)),
            ("Intensity", floats(&[3.0, 4.0])),
        ],
        "ID",
    );
    assert!(
        e.to_string().contains("`point0` is already in the lights"),
        "{e}"
    );
    let e = eval_err(
        "AddLight (Point)",
        &[("ID", Spread::String(vec!["a".into(), "a".into()]))],
        "ID",
    );
    assert!(e.to_string().contains("`a` is given twice"), "{e}");
}

#[test]
fn a_light_cutoff_or_merge_that_is_nan_infinite_or_negative_is_an_error_on_its_pin() {
    for (pin, says) in [
        ("Light Cutoff", "light cutoff"),
        ("Light Merge", "light merge"),
    ] {
        for bad in [f32::NAN, f32::INFINITY, -1.0] {
            let e = eval_err("CookTorrance", &[(pin, floats(&[bad]))], pin);
            assert!(e.to_string().contains(says), "{pin} {bad}: {e}");
        }
    }
}

#[test]
fn a_nan_on_a_light_pin_is_an_error_on_the_node_never_a_light() {
    let e = eval_err(
        "AddLight (Point)",
        &[("Range", floats(&[1.0, f32::NAN]))],
        "Range",
    );
    assert!(e.to_string().contains("slice 1"), "{e}");
    eval_err(
        "AddLight (Sun)",
        &[("Illuminance", floats(&[f32::INFINITY]))],
        "Illuminance",
    );
    eval_err(
        "AddLight (Spot)",
        &[(
            "View",
            Spread::Mat4(vec![Mat4::from_scale(Vec3::splat(f32::NAN))]),
        )],
        "View",
    );
}

#[test]
fn light_buffers_without_a_renderer_say_how_to_get_one() {
    for name in ["PointLightBuffer", "SpotLightBuffer", "SunLightBuffer"] {
        match eval(name, &[]) {
            Err(NodeError::Other(message)) => assert!(message.contains("renderer"), "{message}"),
            other => panic!("{name}: {other:?}"),
        }
    }
}

/// Runs `patch` for a frame with a GPU and returns node `id`'s output `pin`.
fn run(patch: &Patch, id: u32, pin: &str) -> (Runtime, Option<Arc<Spread>>) {
    let mut runtime = Runtime::new(crate::registry());
    runtime.provide(spreadlight_render::renderer::test_renderer());
    let problems = runtime.load(patch);
    assert!(problems.is_empty(), "{problems:?}");
    runtime.evaluate(FrameClock::default());
    let out = runtime.output(NodeId(id), pin).cloned();
    (runtime, out)
}

#[test]
fn buffers_upload_what_their_add_light_chains_gathered() {
    let mut patch = Patch::default();
    patch.add(NodeDoc::new(1, "AddLight (Spot)").with("Intensity", vec![10.0f32, 20.0]));
    patch.add(NodeDoc::new(2, "AddLight (Spot)").with("ID", vec!["extra".to_owned()]));
    patch.add(NodeDoc::new(3, "SpotLightBuffer"));
    patch.add(NodeDoc::new(4, "Probe"));
    patch.add(NodeDoc::new(5, "Probe"));
    patch.link(1, "Lights", 2, "Lights");
    patch.link(2, "Lights", 3, "Lights");
    patch.link(3, "Lights", 4, "Input");
    patch.link(3, "Count", 5, "Input");
    let (runtime, out) = run(&patch, 3, "Lights");
    let errors: Vec<_> = runtime.node_errors().collect();
    assert!(errors.is_empty(), "{errors:?}");
    let buffer = match out.as_deref() {
        Some(Spread::Resource(ResourceKind::LightWorld, h)) => {
            h[0].downcast_arc::<LightBuffer>().expect("a LightBuffer")
        }
        other => panic!("{other:?}"),
    };
    assert_eq!((buffer.kind, buffer.count()), (LightKind::Spot, 3));
    assert_eq!(
        runtime
            .output(NodeId(3), "Count")
            .map(|s| s.as_ref().clone()),
        Some(Spread::Int(vec![3]))
    );
}

#[test]
fn a_spot_that_cannot_be_a_light_is_an_error_naming_its_id() {
    let mut patch = Patch::default();
    patch.add(
        NodeDoc::new(1, "AddLight (Spot)")
            .with("ID", vec!["gobo".to_owned()])
            .with("Projection", vec![Mat4::ZERO]),
    );
    patch.add(NodeDoc::new(2, "SpotLightBuffer"));
    patch.add(NodeDoc::new(3, "Probe"));
    patch.link(1, "Lights", 2, "Lights");
    patch.link(2, "Lights", 3, "Input");
    let (runtime, _) = run(&patch, 2, "Lights");
    let errors: Vec<String> = runtime
        .node_errors()
        .map(|(id, e)| format!("#{}: {e}", id.0))
        .collect();
    assert_eq!(errors.len(), 1, "{errors:?}");
    assert!(
        errors[0].starts_with("#2") && errors[0].contains("light `gobo`: spot 0: the projection"),
        "{errors:?}"
    );
}

#[test]
fn shadow_map_settings_out_of_range_are_errors_naming_the_pin() {
    // Settings are checked before anything needs a G-buffer or a renderer's GPU work.
    let renderer_error = |name: &str, values: &[(&str, Spread)], pin: &str| {
        let mut patch = Patch::default();
        let mut node = NodeDoc::new(1, name);
        for (p, v) in values {
            node = node.with(p, v.clone());
        }
        patch.add(node);
        patch.add(NodeDoc::new(2, "Probe"));
        patch.link(1, "Shadows", 2, "Input");
        let (runtime, _) = run(&patch, 1, "Shadows");
        let errors: Vec<String> = runtime.node_errors().map(|(_, e)| e.to_string()).collect();
        assert_eq!(errors.len(), 1, "{errors:?}");
        assert!(errors[0].contains(&format!("input `{pin}`")), "{errors:?}");
        errors[0].clone()
    };
    let e = renderer_error(
        "ShadowMap (Spot)",
        &[("Resolution", Spread::Int(vec![8]))],
        "Resolution",
    );
    assert!(e.contains("16..="), "{e}");
    let e = renderer_error(
        "ShadowMap (Point)",
        &[("PCF Kernel", Spread::Int(vec![4]))],
        "PCF Kernel",
    );
    assert!(e.contains("odd"), "{e}");
    // Nothing wrong with the settings, but no view to render shadows for.
    renderer_error("ShadowMap (Sun)", &[], "G-Buffer");
}

#[test]
fn two_lights_on_one_shadow_slice_are_named() {
    let mut patch = Patch::default();
    patch.add(
        NodeDoc::new(1, "AddLight (Point)")
            .with("Shadow Slice", vec![2i64])
            .with("Intensity", vec![1.0f32, 2.0]),
    );
    patch.add(NodeDoc::new(2, "ShadowMap (Point)"));
    patch.add(NodeDoc::new(3, "Probe"));
    patch.add(NodeDoc::new(4, "Sphere"));
    patch.add(NodeDoc::new(5, "DeferredBase"));
    patch.add(NodeDoc::new(6, "MRE"));
    patch.link(1, "Lights", 2, "Lights");
    patch.link(4, "Mesh", 5, "Mesh");
    patch.link(5, "Layer", 6, "Layer");
    patch.link(5, "Layer", 2, "Layer");
    patch.link(6, "G-Buffer", 2, "G-Buffer");
    patch.link(2, "Shadows", 3, "Input");
    let (runtime, _) = run(&patch, 2, "Shadows");
    let errors: Vec<String> = runtime
        .node_errors()
        .map(|(id, e)| format!("#{}: {e}", id.0))
        .collect();
    assert_eq!(
        errors,
        ["#2: input `Lights`: shadow slice 2 is given to lights `point0`, `point1`"]
    );
}

#[test]
fn ao_pins_out_of_range_are_errors_naming_the_pin() {
    let error = |name: &str, values: &[(&str, Spread)]| {
        let mut patch = Patch::default();
        let mut node = NodeDoc::new(1, name);
        for (p, v) in values {
            node = node.with(p, v.clone());
        }
        patch.add(node);
        patch.add(NodeDoc::new(2, "Probe"));
        patch.link(1, "Texture", 2, "Input");
        let (runtime, _) = run(&patch, 1, "Texture");
        let errors: Vec<String> = runtime.node_errors().map(|(_, e)| e.to_string()).collect();
        assert_eq!(errors.len(), 1, "{errors:?}");
        errors[0].clone()
    };
    let e = error("SSAO", &[]);
    assert!(e.contains("input `G-Buffer`"), "{e}");
    for name in ["SSAO", "HBAO"] {
        let e = error(name, &[("Radius", Spread::Float(vec![-1.0]))]);
        assert!(e.contains("input `Radius`"), "{e}");
        let e = error(name, &[("Temporal Blend", Spread::Float(vec![1.0]))]);
        assert!(e.contains("input `Temporal Blend`"), "{e}");
    }
}
