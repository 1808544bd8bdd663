//! The nodes of the second geometry batch in a runtime: Tessellate,
//! Displace and Extrude with a texture, Decimate and Spline run once for
//! unchanged inputs and refuse bad input on the pin at fault.

use glam::Vec3;
use spreadlight_graph::{FrameClock, NodeDoc, NodeError, NodeId, NodeRun, Patch, Spread};

use super::tests::{Run, box_into};
use crate::testing::eval;

fn tiles() -> String {
    concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../patches/assets/tiles.png"
    )
    .to_owned()
}

/// `patch` with a FileTexture of tiles.png (linear) as node 5, into `pin` of node 2.
fn with_texture(mut patch: Patch) -> Patch {
    patch.add(
        NodeDoc::new(5, "FileTexture")
            .with("Filename", vec![tiles()])
            .with("sRGB", vec![false]),
    );
    patch.link(5, "Texture", 2, "Texture");
    patch
}

#[test]
fn tessellate_runs_its_three_passes_once_then_nothing() {
    let mut run = Run::new(&box_into(
        NodeDoc::new(2, "Tessellate").with("Max Area", vec![0.02f32]),
    ));
    assert_eq!(
        run.frame(0, 2),
        (NodeRun::Evaluated, 3),
        "count, sums, write"
    );
    assert_eq!(run.frame(1, 2), (NodeRun::Evaluated, 3), "settles velocity");
    assert_eq!(run.frame(2, 2), (NodeRun::Reused, 0));
    // A unit box's faces are 0.5 each: at 0.02 every one splits.
    assert!(run.mesh(2).indices.len() >= 12 * 25 * 3);

    let mut run = Run::new(&box_into(
        NodeDoc::new(2, "Tessellate").with("Max Area", vec![0.0f32]),
    ));
    run.runtime.evaluate(FrameClock::fixed(0, 60.0));
    assert!(
        matches!(run.runtime.node_error(NodeId(2)), Some(NodeError::Input { pin, .. }) if pin == "Max Area")
    );
}

#[test]
fn displace_and_extrude_read_a_file_texture() {
    let mut run = Run::new(&with_texture(box_into(NodeDoc::new(2, "Displace"))));
    assert_eq!(
        run.frame(0, 2),
        (NodeRun::Evaluated, 3),
        "move, accumulate, normals"
    );
    run.frame(1, 2);
    assert_eq!(run.frame(2, 2), (NodeRun::Reused, 0));
    assert_eq!(run.mesh(2).indices.len(), 36);

    let mut run = Run::new(&with_texture(box_into(NodeDoc::new(2, "Extrude"))));
    assert_eq!(run.frame(0, 2), (NodeRun::Evaluated, 1));
    assert_eq!(run.mesh(2).indices.len(), 12 * 7 * 3);

    // No texture: Displace says which pin wants one.
    let mut run = Run::new(&box_into(NodeDoc::new(2, "Displace")));
    run.runtime.evaluate(FrameClock::fixed(0, 60.0));
    assert!(
        matches!(run.runtime.node_error(NodeId(2)), Some(NodeError::Input { pin, .. }) if pin == "Texture")
    );
}

#[test]
fn decimate_keeps_about_its_ratio_on_the_cpu() {
    let mut patch = Patch::default();
    patch.add(NodeDoc::new(1, "Sphere"));
    patch.add(NodeDoc::new(2, "Decimate").with("Ratio", vec![0.5f32]));
    patch.add(NodeDoc::new(3, "Probe"));
    patch.link(1, "Mesh", 2, "Mesh");
    patch.link(2, "Mesh", 3, "Input");
    let mut run = Run::new(&patch);
    assert_eq!(run.frame(0, 2), (NodeRun::Evaluated, 0), "no GPU pass");
    assert_eq!(run.frame(1, 2), (NodeRun::Reused, 0));
    let sphere = match run.runtime.output(NodeId(1), "Mesh").map(|s| s.as_ref()) {
        Some(Spread::Resource(_, h)) => h[0]
            .downcast_arc::<spreadlight_render::mesh_arena::GpuMesh>()
            .unwrap(),
        other => panic!("{other:?}"),
    };
    let ratio = run.mesh(2).indices.len() as f32 / sphere.indices.len() as f32;
    assert!((ratio - 0.5).abs() < 0.05, "kept {ratio}");
}

#[test]
fn the_spline_node_passes_through_its_points_or_anchors() {
    let points: Vec<Vec3> = (0..7)
        .map(|i| Vec3::new(i as f32, (i * i % 3) as f32, 0.5 * i as f32))
        .collect();
    let outputs = |curve: &str| {
        eval(
            "Spline",
            &[
                ("Points", Spread::Vec3(points.clone())),
                ("Segments", Spread::Int(vec![4])),
                ("Curve", Spread::Enum(vec![curve.to_owned()])),
            ],
        )
    };
    let Spread::Vec3(out) = &outputs("Bezier").unwrap()[0] else {
        panic!("points")
    };
    assert_eq!(out.len(), 2 * 4 + 1);
    for (k, anchor) in [(0, 0), (4, 3), (8, 6)] {
        assert!((out[k] - points[anchor]).length() < 1e-5, "anchor {anchor}");
    }
    let all = outputs("Catmull-Rom").unwrap();
    let (Spread::Vec3(out), Spread::Vec3(tangents)) = (&all[0], &all[1]) else {
        panic!("points and tangents")
    };
    assert_eq!(out.len(), 6 * 4 + 1);
    for (k, p) in points.iter().enumerate() {
        assert!((out[k * 4] - *p).length() < 1e-5, "point {k}");
    }
    assert!(tangents.iter().all(|t| (t.length() - 1.0).abs() < 1e-5));
    let six = eval(
        "Spline",
        &[
            ("Points", Spread::Vec3(points[..6].to_vec())),
            ("Curve", Spread::Enum(vec!["Bezier".to_owned()])),
        ],
    );
    assert!(matches!(six, Err(NodeError::Input { pin, .. }) if pin == "Points"));
}
