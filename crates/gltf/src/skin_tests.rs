//! Skins and morph targets on the CPU side: what loads, the joint matrices
//! of a pose against the bar's analytic motion, and bad skins refused or
//! repaired with messages that name the file and the object.

use glam::{Mat4, Quat, Vec3};
use gltf::json;
use json::mesh::Semantic;
use json::validation::Checked::Valid;

use super::builder::bytes;
use super::skin::UNSKINNED;
use super::skinned_models::{BAR_BEND_RATE, joints, swaying_tube, two_bone_bar, two_bone_bar_doc};
use super::{GltfError, GltfScene, load_gltf_slice};

fn load(bytes: &[u8]) -> Result<GltfScene, GltfError> {
    load_gltf_slice(bytes, None)
}

/// The bar posed at `time`: the instance's deformed positions.
fn bar_at(scene: &GltfScene, time: f32) -> Vec<Vec3> {
    let world = scene.node_worlds(Some(0), time);
    let weights = scene.morph_weights(Some(0), time);
    let pose = scene.deform_pose(&scene.instances[0], &world, &weights);
    assert_eq!(pose.transform, Mat4::IDENTITY, "skinned into world space");
    scene.deformed_positions(0, &pose)
}

#[test]
fn the_bar_bends_about_its_joint_as_its_animation_says() {
    let scene = load(&two_bone_bar()).unwrap();
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    assert_eq!(scene.skins.len(), 1);
    assert_eq!(scene.skins[0].name, "skin 0 `Arm`");
    assert_eq!(scene.skins[0].joints, vec![1, 0], "Root, Tip");
    let instance = &scene.instances[0];
    assert_eq!(instance.skin, Some(0));
    assert!(scene.is_deformed(instance));
    let rest = &scene.meshes[0].positions;
    for time in [0.0f32, 0.3, 0.5, 0.9] {
        let turn = Mat4::from_translation(Vec3::X)
            * Mat4::from_quat(Quat::from_rotation_z(BAR_BEND_RATE * time))
            * Mat4::from_translation(-Vec3::X);
        for (p, r) in bar_at(&scene, time).iter().zip(rest) {
            let r = Vec3::from(*r);
            let want = if r.x > 1.0 {
                turn.transform_point3(r)
            } else if r.x < 1.0 {
                r
            } else {
                // Half and half: the midpoint of the two joints' placements.
                (r + turn.transform_point3(r)) * 0.5
            };
            assert!(
                (*p - want).length() < 1e-5,
                "t {time}: {r} -> {p}, want {want}"
            );
        }
    }
}

#[test]
fn posed_bounds_hold_every_deformed_vertex() {
    let scene = load(&swaying_tube()).unwrap();
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    // The skeleton centres the tube (its mesh at rest runs from x = 0 to
    // 2.4): the scene's bounds are where the joints put it.
    assert!(
        (scene.bounds.min.x + 1.2).abs() < 0.01 && (scene.bounds.max.x - 1.2).abs() < 0.01,
        "{:?}",
        scene.bounds
    );
    let influences = scene.deforms[0].influences.as_ref().unwrap();
    // Six joints, eight influences: the second set (JOINTS_1) carries weight.
    assert!(influences.weights.iter().any(|w| w[4] > 0.0));
    for w in &influences.weights {
        assert!((w.iter().sum::<f32>() - 1.0).abs() < 1e-5);
    }
    for time in [0.0f32, 0.4, 0.5, 1.3] {
        let world = scene.node_worlds(Some(0), time);
        let weights = scene.morph_weights(Some(0), time);
        let pose = scene.deform_pose(&scene.instances[0], &world, &weights);
        // Keys every 0.25 s of |sin(pi t)|, interpolated linearly.
        let key = |k: f32| (k * 0.25 * std::f32::consts::PI).sin().abs();
        let (k, frac) = ((time / 0.25).floor(), (time / 0.25).fract());
        let swell = key(k) + (key(k + 1.0) - key(k)) * frac;
        assert!(
            (pose.weights[0] - swell).abs() < 1e-5,
            "t {time}: {:?}",
            pose.weights
        );
        let slack = Vec3::splat(1e-4);
        for p in scene.deformed_positions(0, &pose) {
            assert!(
                p.cmpge(pose.bounds.min - slack).all() && p.cmple(pose.bounds.max + slack).all(),
                "t {time}: {p} outside {:?}",
                pose.bounds
            );
        }
    }
}

/// The bar with its WEIGHTS_0 replaced by `weights` and JOINTS_0 by `ids`.
fn bar_with(ids: Option<&[[u16; 4]]>, weights: Option<&[[f32; 4]]>) -> Vec<u8> {
    let mut doc = two_bone_bar_doc();
    if let Some(ids) = ids {
        let a = joints(&mut doc, ids);
        doc.root.meshes[0].primitives[0]
            .attributes
            .insert(Valid(Semantic::Joints(0)), a);
    }
    if let Some(weights) = weights {
        let a = doc.floats(weights);
        doc.root.meshes[0].primitives[0]
            .attributes
            .insert(Valid(Semantic::Weights(0)), a);
    }
    doc.gltf_data_uri()
}

#[test]
fn a_joint_index_beyond_the_skin_is_refused_by_name() {
    let mut ids = vec![[0u16, 1, 0, 0]; 18];
    ids[7] = [5, 1, 0, 0];
    let error = load(&bar_with(Some(&ids), None)).unwrap_err().to_string();
    for part in [
        "<memory>",
        "node 2 `Body`",
        "skin 0 `Arm`",
        "mesh 0 `Bar`, primitive 0",
        "vertex 7 uses joint 5",
        "the skin has 2 joints",
    ] {
        assert!(error.contains(part), "{part:?} missing from: {error}");
    }
}

#[test]
fn fewer_inverse_bind_matrices_than_joints_is_refused() {
    let mut doc = two_bone_bar_doc();
    let view = doc.view(&bytes(&Mat4::IDENTITY.to_cols_array()));
    let one = doc.accessor(
        Some(view),
        1,
        json::accessor::ComponentType::F32,
        json::accessor::Type::Mat4,
    );
    doc.root.skins[0].inverse_bind_matrices = Some(one);
    let error = load(&doc.gltf_data_uri()).unwrap_err().to_string();
    assert!(
        error.contains("<memory>: skin 0 `Arm`: it has 2 joints but 1 inverse bind matrices"),
        "{error}"
    );
    // No inverse bind matrices at all is valid: identities.
    let mut doc = two_bone_bar_doc();
    doc.root.skins[0].inverse_bind_matrices = None;
    let scene = load(&doc.gltf_data_uri()).unwrap();
    assert_eq!(scene.skins[0].inverse_bind, vec![Mat4::IDENTITY; 2]);
}

#[test]
fn weights_off_one_are_normalized_and_weightless_vertices_follow_the_node() {
    let mut weights = vec![[1.0f32, 0.0, 0.0, 0.0]; 18];
    weights[2] = [0.5, 0.25, 0.0, 0.0]; // sums to 0.75
    weights[3] = [0.0; 4]; // no weight
    weights[4] = [f32::NAN, 1.0, 0.0, 0.0]; // NaN counts as 0
    let scene = load(&bar_with(None, Some(&weights))).unwrap();
    let warned = |part: &str| scene.warnings.iter().any(|w| w.contains(part));
    assert!(
        warned(
            "mesh 0 `Bar`, primitive 0: 1 vertices have weights do not sum to 1; they are normalized"
        ) || warned("1 vertices have weights do not sum to 1"),
        "{:?}",
        scene.warnings
    );
    assert!(
        warned("no joint weight; they follow the mesh's node"),
        "{:?}",
        scene.warnings
    );
    assert!(
        warned("negative or non-finite weights"),
        "{:?}",
        scene.warnings
    );
    let influences = scene.deforms[0].influences.as_ref().unwrap();
    assert_eq!(influences.weights[2][..2], [2.0 / 3.0, 1.0 / 3.0]);
    assert_eq!(influences.joints[3][0], UNSKINNED);
    assert_eq!(influences.joints[4][..1], [1], "the NaN slot is dropped");
    for w in &influences.weights {
        assert!((w.iter().sum::<f32>() - 1.0).abs() < 1e-6);
    }
    // The weightless vertex stays where its node (at the origin) puts it.
    let posed = bar_at(&scene, 0.7);
    assert_eq!(posed[3], Vec3::from(scene.meshes[0].positions[3]));
}

#[test]
fn a_morph_target_of_the_wrong_length_is_refused() {
    let mut doc = two_bone_bar_doc();
    let short = doc.positions(&[[0.0, 1.0, 0.0]; 5]);
    doc.root.meshes[0].primitives[0].targets = Some(vec![json::mesh::MorphTarget {
        positions: Some(short),
        normals: None,
        tangents: None,
    }]);
    let error = load(&doc.gltf_data_uri()).unwrap_err().to_string();
    assert!(
        error.contains("<memory>: mesh 0 `Bar`, primitive 0: morph target 0 POSITION: 5 elements but POSITION has 18"),
        "{error}"
    );
}

#[test]
fn mesh_weights_set_the_rest_morph_and_node_weights_override_them() {
    let mut doc = two_bone_bar_doc();
    let up = doc.positions(&[[0.0, 1.0, 0.0]; 18]);
    doc.root.meshes[0].primitives[0].targets = Some(vec![json::mesh::MorphTarget {
        positions: Some(up),
        normals: None,
        tangents: None,
    }]);
    doc.root.meshes[0].weights = Some(vec![0.25]);
    let scene = load(&doc.gltf_data_uri()).unwrap();
    assert_eq!(scene.instances[0].weights, vec![0.25]);
    let rest = bar_at(&scene, 0.0);
    assert!((rest[0] - Vec3::new(0.0, -0.1 + 0.25, 0.0)).length() < 1e-6);
    let mut doc = two_bone_bar_doc();
    let up = doc.positions(&[[0.0, 1.0, 0.0]; 18]);
    doc.root.meshes[0].primitives[0].targets = Some(vec![json::mesh::MorphTarget {
        positions: Some(up),
        normals: None,
        tangents: None,
    }]);
    doc.root.meshes[0].weights = Some(vec![0.25]);
    doc.root.nodes[2].weights = Some(vec![0.5, 7.0]);
    let scene = load(&doc.gltf_data_uri()).unwrap();
    assert_eq!(
        scene.instances[0].weights,
        vec![0.5],
        "fitted to one target"
    );
    assert!(
        scene
            .warnings
            .iter()
            .any(|w| w.contains("2 morph weights for 1 morph targets"))
    );
}

#[test]
fn the_skinning_benchmark_model_is_what_the_generator_makes() {
    // patches/assets/bench-skinning.gltf is a committed output of `bench_herd`.
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../patches/assets/bench-skinning.gltf");
    let made = super::skinned_models::bench_herd();
    if std::env::var_os("SPREADLIGHT_BLESS").is_some() {
        std::fs::write(&path, &made).unwrap();
    }
    let committed = std::fs::read(&path).unwrap();
    assert!(
        committed == made,
        "bench-skinning.gltf is stale: regenerate with SPREADLIGHT_BLESS=1"
    );
    let scene = load(&made).unwrap();
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    assert_eq!(scene.meshes.len(), 1, "one mesh, shared");
    assert_eq!(scene.meshes[0].positions.len(), 3232);
    assert_eq!(scene.instances.len(), 100);
    assert_eq!(scene.skins.len(), 100, "a skeleton each");
    assert!(scene.skins.iter().all(|s| s.joints.len() == 20));
    assert!(scene.instances.iter().all(|i| scene.is_deformed(i)));
}
