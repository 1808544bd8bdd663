//! The material nodes: building materials on the CPU through `testing::eval`,
//! and `MaterialBuffer`'s upload through a runtime that has a renderer.

use std::sync::Arc;

use glam::Vec4;
use spreadlight_graph::{
    Color, FrameClock, NodeDoc, NodeError, NodeId, Patch, Resource, ResourceKind, Runtime, Spread,
};
use spreadlight_render::material::{Feature, Material, MaterialWorld};

use crate::testing::{eval, eval_err, floats, ints};

/// The materials on output 0 of node `name` with `values` on its pins.
fn materials(name: &str, values: &[(&str, Spread)]) -> Vec<Arc<Material>> {
    let out = eval(name, values).unwrap_or_else(|e| panic!("`{name}` failed: {e}"));
    match &out[0] {
        Spread::Resource(ResourceKind::Material, handles) => handles
            .iter()
            .map(|h| h.downcast_arc::<Material>().expect("a Material"))
            .collect(),
        other => panic!("`{name}` output {other:?}"),
    }
}

fn material_spread(materials: &[Arc<Material>]) -> Spread {
    Spread::Resource(
        ResourceKind::Material,
        materials.iter().cloned().map(Resource::from_arc).collect(),
    )
}

#[test]
fn helpers_make_new_materials_one_per_slice() {
    let out = materials(
        "AddCookTorrance",
        &[("Roughness", floats(&[0.1, 0.9, 2.0]))],
    );
    assert_eq!(out.len(), 3);
    let rough: Vec<f32> = out
        .iter()
        .map(|m| m.params(Feature::CookTorrance).unwrap()[0][0])
        .collect();
    assert_eq!(rough, [0.1, 0.9, 1.0], "roughness is clamped to 0..1");
    assert_eq!(
        out[0].params(Feature::CookTorrance),
        Some(&[[0.1, 0.0, 0.04, 0.0]][..])
    );
    assert!(out.iter().all(|m| m.flags() == 1));

    let sss = materials(
        "AddFakeSSS",
        &[(
            "Color",
            Spread::Color(vec![Color {
                r: 0.5,
                g: -1.0,
                b: 0.25,
                a: 0.3,
            }]),
        )],
    );
    assert_eq!(
        sss[0].params(Feature::FakeSss),
        Some(&[[0.5, 0.0, 0.25, 1.0]][..])
    );
    for (name, feature) in [
        ("AddReflection", Feature::Reflection),
        ("AddMatCap", Feature::MatCap),
        ("AddAmbientOcclusion", Feature::AmbientOcclusion),
    ] {
        let m = materials(name, &[("Strength", floats(&[-2.0, 3.0]))]);
        assert_eq!(m.len(), 2);
        assert_eq!(m[0].params(feature), Some(&[[0.0; 4]][..]), "{name}");
        // Reflection and AO weigh an input 0..1; a matcap may be brighter.
        let top = if name == "AddMatCap" { 3.0 } else { 1.0 };
        assert_eq!(
            m[1].params(feature),
            Some(&[[top, 0.0, 0.0, 0.0]][..]),
            "{name}"
        );
        assert_eq!(m[1].flags(), feature.flag());
    }
}

#[test]
fn helpers_chain_and_replace_their_feature() {
    let base = materials("AddCookTorrance", &[("Roughness", floats(&[0.2, 0.4]))]);
    // Spreading: 2 materials, 3 strengths -> 3 materials, the first wraps around.
    let lit = materials(
        "AddEmission",
        &[
            ("Material", material_spread(&base)),
            ("Strength", floats(&[1.0, 2.0, 3.0])),
        ],
    );
    assert_eq!(lit.len(), 3);
    assert_eq!(lit[2].params(Feature::CookTorrance).unwrap()[0][0], 0.2);
    assert_eq!(
        lit[2].params(Feature::Emission),
        Some(&[[1.0, 1.0, 1.0, 3.0]][..])
    );
    assert_eq!(lit[0].flags(), 0b11);
    let again = materials(
        "AddCookTorrance",
        &[
            ("Material", material_spread(&lit)),
            ("Metallic", floats(&[1.0])),
        ],
    );
    assert_eq!(again.len(), 3, "the material pin counts when connected");
    assert_eq!(
        again[1].params(Feature::CookTorrance),
        Some(&[[0.5, 1.0, 0.04, 0.0]][..]),
        "replaced, not merged"
    );
    assert_eq!(
        again[1].params(Feature::Emission),
        lit[1].params(Feature::Emission)
    );
    // The inputs are untouched: materials are values.
    assert_eq!(base[0].flags(), 1);
    assert!(materials("AddEmission", &[("Strength", floats(&[]))]).is_empty());
}

#[test]
fn nan_on_a_pin_is_an_error_naming_pin_and_slice() {
    let e = eval_err(
        "AddEmission",
        &[("Strength", floats(&[1.0, f32::NAN]))],
        "Strength",
    );
    assert!(e.to_string().contains("slice 1"), "{e}");
    let red = Spread::Color(vec![Color {
        r: f32::INFINITY,
        g: 0.0,
        b: 0.0,
        a: 1.0,
    }]);
    let e = eval_err("AddFakeSSS", &[("Color", red)], "Color");
    assert!(e.to_string().contains("slice 0"), "{e}");
    let nan = Spread::Vec4(vec![Vec4::ONE, Vec4::new(0.0, f32::NAN, 0.0, 0.0)]);
    let e = eval_err("FeatureManager", &[("Parameters", nan)], "Parameters");
    assert!(e.to_string().contains("slice 1"), "{e}");
}

#[test]
fn feature_manager_sets_built_in_and_custom_features() {
    let params = Spread::Vec4(vec![Vec4::new(0.3, 0.7, 0.5, 9.0)]);
    let ct = materials("FeatureManager", &[("Parameters", params)]);
    assert_eq!(ct.len(), 1);
    assert_eq!(
        ct[0].params(Feature::CookTorrance),
        Some(&[[0.3, 0.7, 0.5, 0.0]][..])
    );

    // Custom feature 20, two vec4s per material: four parameters make two materials.
    let four = Spread::Vec4((0..4).map(|i| Vec4::splat(i as f32 - 1.0)).collect());
    let custom = materials(
        "FeatureManager",
        &[
            ("Feature ID", ints(&[20])),
            ("Parameters", four),
            ("Bin Size", ints(&[2])),
        ],
    );
    assert_eq!(custom.len(), 2);
    assert_eq!(
        custom[0].params(Feature::Custom(20)),
        Some(&[[-1.0; 4], [0.0; 4]][..])
    );
    assert_eq!(
        custom[1].params(Feature::Custom(20)),
        Some(&[[1.0; 4], [2.0; 4]][..])
    );
    assert_eq!(custom[1].flags(), 1 << 20);

    let flag_only = materials(
        "FeatureManager",
        &[("Feature ID", ints(&[16, 31])), ("Bin Size", ints(&[0]))],
    );
    assert_eq!(flag_only.len(), 2);
    assert_eq!(flag_only[1].params(Feature::Custom(31)), Some(&[][..]));
    assert_eq!(flag_only[1].flags(), 1 << 31);
}

#[test]
fn feature_manager_refuses_unknown_ids_and_wrong_bin_sizes() {
    for id in [6, 13, 15, 32, -1] {
        let e = eval_err(
            "FeatureManager",
            &[("Feature ID", ints(&[1, id]))],
            "Feature ID",
        );
        assert!(e.to_string().contains("slice 1"), "{e}");
    }
    let e = eval_err("FeatureManager", &[("Bin Size", ints(&[2]))], "Bin Size");
    assert!(e.to_string().contains("CookTorrance"), "{e}");
    eval_err("FeatureManager", &[("Bin Size", ints(&[-1]))], "Bin Size");
}

#[test]
fn material_buffer_without_a_renderer_says_how_to_get_one() {
    match eval("MaterialBuffer", &[]) {
        Err(NodeError::Other(message)) => assert!(message.contains("renderer"), "{message}"),
        other => panic!("{other:?}"),
    }
}

/// The world a `MaterialBuffer` (node 9, probed) uploads in a runtime with a
/// GPU, fed by `upstream` nodes: `chain` lists nodes whose Material output
/// feeds the next one's Material input, the last feeding Materials.
fn world(upstream: Vec<NodeDoc>, chain: &[u32]) -> Arc<MaterialWorld> {
    let mut patch = Patch::default();
    for node in upstream {
        patch.add(node);
    }
    patch.add(NodeDoc::new(9, "MaterialBuffer"));
    patch.add(NodeDoc::new(10, "Probe"));
    for pair in chain.windows(2) {
        patch.link(pair[0], "Material", pair[1], "Material");
    }
    if let Some(&last) = chain.last() {
        patch.link(last, "Material", 9, "Materials");
    }
    patch.link(9, "Material World", 10, "Input");
    let mut runtime = Runtime::new(crate::registry());
    runtime.provide(spreadlight_render::renderer::test_renderer());
    let problems = runtime.load(&patch);
    assert!(problems.is_empty(), "{problems:?}");
    runtime.evaluate(FrameClock::default());
    let errors: Vec<_> = runtime.node_errors().collect();
    assert!(errors.is_empty(), "{errors:?}");
    match runtime
        .output(NodeId(9), "Material World")
        .map(|s| s.as_ref())
    {
        Some(Spread::Resource(ResourceKind::MaterialWorld, handles)) if handles.len() == 1 => {
            handles[0]
                .downcast_arc::<MaterialWorld>()
                .expect("a MaterialWorld")
        }
        other => panic!("MaterialBuffer output {other:?}"),
    }
}

#[test]
fn material_buffer_uploads_one_world_with_material_id_per_slice() {
    let default = world(Vec::new(), &[]);
    assert_eq!(default.len(), 1);
    assert_eq!(
        default.params(0, Feature::CookTorrance),
        Some(&[[0.5, 0.0, 0.04, 0.0]][..])
    );
    assert_eq!(default.union_flags(), 1);

    let nodes = || {
        vec![
            NodeDoc::new(1, "AddCookTorrance").with("Roughness", vec![0.25f32, 0.75]),
            NodeDoc::new(2, "AddEmission").with("Strength", vec![0.0f32, 4.0]),
        ]
    };
    // Emission alone: new materials with only that feature.
    let emissive = world(nodes(), &[2]);
    assert_eq!(emissive.len(), 2);
    assert_eq!(emissive.flags(1), Feature::Emission.flag());
    assert_eq!(
        emissive.params(1, Feature::Emission),
        Some(&[[1.0, 1.0, 1.0, 4.0]][..])
    );
    assert_eq!(emissive.union_flags(), Feature::Emission.flag());

    let chained = world(nodes(), &[1, 2]);
    assert_eq!(chained.len(), 2);
    assert_eq!(chained.flags(1), 0b11);
    assert_eq!(
        chained.params(1, Feature::CookTorrance).unwrap()[0][0],
        0.75
    );
    assert_eq!(chained.params(1, Feature::Emission).unwrap()[0][3], 4.0);
    assert_eq!(
        chained.flags(7),
        chained.flags(0),
        "ids out of range read material 0"
    );
    assert_eq!(chained.union_flags(), 0b11);
}

#[test]
fn texture_ids_pick_a_layer_per_material_and_negative_means_none() {
    let out = materials(
        "AddEmission",
        &[
            ("Strength", floats(&[1.0, 2.0, 3.0])),
            ("Texture ID", ints(&[2, -1])),
        ],
    );
    let layers: Vec<_> = out.iter().map(|m| m.texture(Feature::Emission)).collect();
    assert_eq!(layers, [Some(2), None, Some(2)]);
    let out = materials(
        "FeatureManager",
        &[
            ("Feature ID", ints(&[1])),
            ("Parameters", Spread::Vec4(vec![Vec4::ONE])),
            ("Texture ID", ints(&[0])),
        ],
    );
    assert_eq!(out[0].texture(Feature::Emission), Some(0));
}

#[test]
fn material_managers_place_materials_at_their_ids_and_later_ones_win() {
    let shiny = materials("AddCookTorrance", &[("Roughness", floats(&[0.1, 0.2]))]);
    let placed = materials(
        "MaterialManager",
        &[
            ("Material", material_spread(&shiny)),
            ("Material ID", ints(&[3, 1])),
        ],
    );
    assert_eq!(placed.len(), 4);
    let rough = |m: &Material| m.params(Feature::CookTorrance).unwrap()[0][0];
    assert_eq!(
        placed.iter().map(|m| rough(m)).collect::<Vec<_>>(),
        [0.5, 0.2, 0.5, 0.1]
    );
    // A second manager replaces id 1 and keeps the rest.
    let glow = materials("AddEmission", &[]);
    let chained = materials(
        "MaterialManager",
        &[
            ("Materials", material_spread(&placed)),
            ("Material", material_spread(&glow)),
            ("Material ID", ints(&[1])),
        ],
    );
    assert_eq!(chained.len(), 4);
    assert_eq!(chained[1].flags(), Feature::Emission.flag());
    assert!(Arc::ptr_eq(&chained[3], &placed[3]));
    let e = eval_err(
        "MaterialManager",
        &[("Material ID", ints(&[2, 2]))],
        "Material ID",
    );
    assert!(e.to_string().contains("id 2 is given twice"), "{e}");
    eval_err(
        "MaterialManager",
        &[("Material ID", ints(&[-1]))],
        "Material ID",
    );
}

#[test]
fn add_matcap_keeps_mode_mapping_and_its_image_layer() {
    use spreadlight_render::material::{MatCapMapping, MatCapMode, matcap_params};
    let out = materials(
        "AddMatCap",
        &[
            ("Strength", floats(&[0.5, 2.0])),
            (
                "Mode",
                Spread::Enum(vec!["Multiply".to_owned(), "Add".to_owned()]),
            ),
            ("Mapping", Spread::Enum(vec!["Reflected".to_owned()])),
            ("MatCap Texture ID", ints(&[3, -1])),
        ],
    );
    assert_eq!(out.len(), 2);
    assert_eq!(
        out[0].params(Feature::MatCap),
        Some(
            &[matcap_params(
                0.5,
                MatCapMode::Multiply,
                MatCapMapping::Reflected
            )][..]
        )
    );
    assert_eq!(
        out[1].params(Feature::MatCap),
        Some(&[[2.0, 1.0, 1.0, 0.0]][..])
    );
    assert_eq!(out[0].texture(Feature::MatCap), Some(3));
    assert_eq!(
        out[1].texture(Feature::MatCap),
        None,
        "-1: the built-in matcap"
    );
    for bad in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
        let e = eval_err(
            "AddMatCap",
            &[("Strength", floats(&[1.0, bad]))],
            "Strength",
        );
        assert!(e.to_string().contains("slice 1"), "{e}");
    }
}

#[test]
fn feature_manager_refuses_a_texture_on_features_that_read_none() {
    for id in [3, 5] {
        let e = eval_err(
            "FeatureManager",
            &[
                ("Feature ID", ints(&[id])),
                ("Parameters", Spread::Vec4(vec![Vec4::ONE])),
                ("Texture ID", ints(&[0])),
            ],
            "Texture ID",
        );
        assert!(e.to_string().contains("reads no texture"), "{e}");
    }
    let matcap = materials(
        "FeatureManager",
        &[
            ("Feature ID", ints(&[4])),
            ("Parameters", Spread::Vec4(vec![Vec4::ONE])),
            ("Texture ID", ints(&[1])),
        ],
    );
    assert_eq!(matcap[0].texture(Feature::MatCap), Some(1));
}

#[test]
fn parameter_texture_maps_one_parameter_and_refuses_what_it_cannot_map() {
    let ct = materials("AddCookTorrance", &[("Roughness", floats(&[0.2, 0.4]))]);
    let mapped = materials(
        "ParameterTexture",
        &[
            ("Material", material_spread(&ct)),
            ("Parameter", Spread::Enum(vec!["Metallic".into()])),
            ("Texture ID", ints(&[2, -1])),
        ],
    );
    assert_eq!(mapped.len(), 2);
    assert_eq!(mapped[0].param_texture(Feature::CookTorrance, 1), Some(2));
    assert_eq!(mapped[0].param_texture(Feature::CookTorrance, 0), None);
    assert_eq!(mapped[1].param_texture(Feature::CookTorrance, 1), None);
    assert_eq!(
        mapped[0].texture(Feature::CookTorrance),
        None,
        "the feature's own Texture ID untouched"
    );
    // Reflection's strength is not mapped by shading: refused, naming the pin.
    let e = eval_err(
        "ParameterTexture",
        &[
            ("Material", material_spread(&ct)),
            ("Feature ID", ints(&[3])),
        ],
        "Feature ID",
    );
    assert!(e.to_string().contains("CookTorrance"), "{e}");
    // CookTorrance has no Color.
    let e = eval_err(
        "ParameterTexture",
        &[
            ("Material", material_spread(&ct)),
            ("Parameter", Spread::Enum(vec!["Color".into()])),
        ],
        "Parameter",
    );
    assert!(
        e.to_string().contains("Roughness, Metallic, Reflectance"),
        "{e}"
    );
    // A material without the feature: set it first.
    let emissive = materials("AddEmission", &[]);
    let e = eval_err(
        "ParameterTexture",
        &[("Material", material_spread(&emissive))],
        "Material",
    );
    assert!(e.to_string().contains("CookTorrance"), "{e}");
}

#[test]
fn a_texture_id_without_a_texture_array_is_an_error_naming_material_and_feature() {
    let mut patch = Patch::default();
    patch.add(NodeDoc::new(1, "AddCookTorrance"));
    patch.add(
        NodeDoc::new(2, "AddEmission")
            .with("Strength", vec![1.0f32, 2.0])
            .with("Texture ID", vec![-1i64, 3]),
    );
    patch.add(NodeDoc::new(9, "MaterialBuffer"));
    patch.add(NodeDoc::new(10, "Probe"));
    patch.link(1, "Material", 2, "Material");
    patch.link(2, "Material", 9, "Materials");
    patch.link(9, "Material World", 10, "Input");
    let mut runtime = Runtime::new(crate::registry());
    runtime.provide(spreadlight_render::renderer::test_renderer());
    assert!(runtime.load(&patch).is_empty());
    runtime.evaluate(FrameClock::default());
    let errors: Vec<String> = runtime.node_errors().map(|(_, e)| e.to_string()).collect();
    assert!(
        errors.iter().any(|e| e.contains("Textures")
            && e.contains("material 1")
            && e.contains("Emission")
            && e.contains("layer 3")),
        "{errors:?}"
    );
}
