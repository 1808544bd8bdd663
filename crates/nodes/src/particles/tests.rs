//! The `Particles` node in a runtime: it steps every frame, keeps its state
//! across frames, is deterministic for a seed, resets on demand, and its
//! bad inputs are errors naming the pin.

use spreadlight_graph::{FrameClock, NodeDoc, NodeError, NodeId, NodeRun, Patch, Spread};
use spreadlight_render::geometry::read_mesh;

use crate::geometry::tests::Run;

fn patch(particles: NodeDoc) -> Patch {
    let mut patch = Patch::default();
    patch.add(particles);
    patch.add(NodeDoc::new(3, "Probe"));
    patch.link(2, "Mesh", 3, "Input");
    patch
}

fn fountain() -> NodeDoc {
    NodeDoc::new(2, "Particles")
        .with("Count", vec![64i64])
        .with("Rate", vec![600.0f32])
        .with("Field", Spread::Enum(vec!["Curl Noise".to_owned()]))
}

/// The particle mesh's positions after `frames` frames.
fn positions(frames: u64, doc: NodeDoc) -> Vec<[f32; 4]> {
    let mut run = Run::new(&patch(doc));
    for frame in 0..frames {
        assert_eq!(run.frame(frame, 2).0, NodeRun::Evaluated, "time-dependent");
    }
    let (vertices, _) = read_mesh(&run.renderer, &run.mesh(2)).unwrap();
    vertices.iter().map(|v| v.position_u).collect()
}

#[test]
fn the_node_is_deterministic_and_keeps_its_state_across_frames() {
    let a = positions(6, fountain());
    assert_eq!(a, positions(6, fountain()));
    assert_ne!(a, positions(6, fountain().with("Seed", vec![2i64])));
    assert_ne!(a, positions(5, fountain()), "each frame steps the system");
    assert_eq!(a.len(), 64 * 4, "four sprite corners a slot");
}

#[test]
fn reset_starts_the_system_over() {
    let mut run = Run::new(&patch(fountain()));
    for frame in 0..4 {
        run.frame(frame, 2);
    }
    let mut doc = patch(fountain().with("Reset", vec![true]));
    doc.nodes.sort_by_key(|n| n.id);
    run.runtime.load(&doc);
    run.runtime.evaluate(FrameClock::fixed(4, 60.0));
    let (vertices, _) = read_mesh(&run.renderer, &run.mesh(2)).unwrap();
    // Reset, then one step of 1/60 s at 600 a second: 10 particles born (a
    // dead slot collapses its quad to a point).
    let born = vertices
        .chunks(4)
        .filter(|quad| quad[0].position_u[..3] != quad[2].position_u[..3])
        .count();
    assert_eq!(born, 10);
}

#[test]
fn bad_counts_and_missing_meshes_are_errors_on_their_pins() {
    for (doc, pin) in [
        (fountain().with("Count", vec![0i64]), "Count"),
        (
            fountain().with("Emitter", Spread::Enum(vec!["Mesh Surface".to_owned()])),
            "Emitter Mesh",
        ),
        (
            fountain().with("Field", Spread::Enum(vec!["Texture".to_owned()])),
            "Field Texture",
        ),
    ] {
        let mut run = Run::new(&patch(doc));
        run.runtime.evaluate(FrameClock::fixed(0, 60.0));
        match run.runtime.node_error(NodeId(2)) {
            Some(NodeError::Input { pin: p, .. }) => assert_eq!(p, pin),
            other => panic!("expected an error on {pin}, got {other:?}"),
        }
    }
}
