//! GPU geometry nodes in a runtime with a renderer: unchanged inputs rerun
//! nothing (counted by the runtime and by the renderer's dispatch counter),
//! animated pins rerun every frame and carry last frame's positions.

use std::sync::Arc;

use spreadlight_graph::{FrameClock, NodeDoc, NodeId, NodeRun, Patch, Runtime, Spread};
use spreadlight_render::Renderer;
use spreadlight_render::geometry::{GeometryStats, read_extras, read_mesh};
use spreadlight_render::mesh_arena::{GpuMesh, GpuVertexExtra};

pub(crate) struct Run {
    pub runtime: Runtime,
    pub renderer: Arc<Renderer>,
}

impl Run {
    pub fn new(patch: &Patch) -> Self {
        let renderer = spreadlight_render::renderer::test_renderer();
        let mut runtime = Runtime::new(crate::registry());
        runtime.provide(renderer.clone());
        let problems = runtime.load(patch);
        assert!(problems.is_empty(), "{problems:?}");
        Run { runtime, renderer }
    }

    /// Evaluates frame `frame` at 60 fps; returns how node `id` ran and the dispatches it cost.
    pub fn frame(&mut self, frame: u64, id: u32) -> (NodeRun, u64) {
        let before = GeometryStats::of(&self.renderer).dispatches();
        let stats = self.runtime.evaluate(FrameClock::fixed(frame, 60.0));
        let run = stats.node(NodeId(id)).expect("node ran").run;
        let errors: Vec<_> = self.runtime.node_errors().collect();
        assert!(errors.is_empty(), "frame {frame}: {errors:?}");
        (run, GeometryStats::of(&self.renderer).dispatches() - before)
    }

    /// Node `id`'s first output mesh.
    pub fn mesh(&self, id: u32) -> Arc<GpuMesh> {
        match self.runtime.output(NodeId(id), "Mesh").map(|s| s.as_ref()) {
            Some(Spread::Resource(_, handles)) if !handles.is_empty() => {
                handles[0].downcast_arc::<GpuMesh>().expect("a mesh")
            }
            other => panic!("node #{id} output {other:?}"),
        }
    }
}

pub(crate) fn box_into(node: NodeDoc) -> Patch {
    let mut patch = Patch::default();
    patch.add(NodeDoc::new(1, "Box"));
    patch.add(node);
    patch.add(NodeDoc::new(3, "Probe"));
    patch.link(1, "Mesh", 2, "Mesh");
    patch.link(2, "Mesh", 3, "Input");
    patch
}

#[test]
fn an_unchanged_geometry_node_reruns_nothing() {
    let mut run = Run::new(&box_into(
        NodeDoc::new(2, "Spherize").with("Amount", vec![0.5f32]),
    ));
    // Frame 0 makes the mesh; frame 1 settles its velocity; then nothing.
    assert_eq!(run.frame(0, 2), (NodeRun::Evaluated, 1));
    assert_eq!(run.frame(1, 2), (NodeRun::Evaluated, 1));
    for frame in 2..5 {
        assert_eq!(run.frame(frame, 2), (NodeRun::Reused, 0), "frame {frame}");
    }
    let (vertices, _) = read_mesh(&run.renderer, &run.mesh(2)).unwrap();
    assert!(
        vertices
            .iter()
            .all(|v| v.previous_position[..3] == v.position_u[..3]),
        "settled: no motion left"
    );
}

/// A mesh a pass makes gets, from the pass, the extras an uploaded mesh
/// without the streams gets (mesh_arena.rs): its first UV set as the second,
/// and white. Nothing uploads them, and the arena's range may hold what a
/// freed mesh left there.
#[test]
fn a_made_mesh_gets_its_first_uv_set_and_white_as_extras() {
    for node in [
        NodeDoc::new(2, "Spherize").with("Amount", vec![0.5f32]),
        NodeDoc::new(2, "Tessellate"),
    ] {
        let name = node.type_name.clone();
        let mut run = Run::new(&box_into(node));
        run.frame(0, 2);
        let mesh = run.mesh(2);
        let (vertices, _) = read_mesh(&run.renderer, &mesh).unwrap();
        let extras = read_extras(&run.renderer, &mesh).unwrap();
        assert_eq!(extras.len(), vertices.len(), "{name}");
        assert!(
            vertices.iter().any(|v| v.position_u[3] != 0.0),
            "{name}: the box has UVs"
        );
        for (i, (v, extra)) in vertices.iter().zip(&extras).enumerate() {
            let uv = [v.position_u[3], v.normal_v[3]];
            assert_eq!(
                *extra,
                GpuVertexExtra::new(uv, [1.0; 4]),
                "{name}, vertex {i}"
            );
        }
    }
}

/// A box spherized (#2) by an LFO's Amount: it runs every frame.
fn spherize_by_lfo() -> Patch {
    let mut patch = box_into(NodeDoc::new(2, "Spherize"));
    patch.add(NodeDoc::new(4, "LFO").with("Period", vec![0.5f32]));
    patch.link(4, "Output", 2, "Amount");
    patch
}

/// With timing on (bench), a dispatch does not wait for its timestamps as
/// its node evaluates: they are read when the times are taken, once each,
/// and the next frame's dispatch times itself with the timer read before.
#[test]
fn timed_dispatches_are_read_when_their_times_are_taken() {
    let mut run = Run::new(&spherize_by_lfo());
    let stats = GeometryStats::of(&run.renderer);
    stats.set_timing(true);
    for frame in 0..3 {
        assert_eq!(run.frame(frame, 2), (NodeRun::Evaluated, 1));
        let gpu = &run.renderer.gpu;
        let ms = stats.take_gpu_ms(gpu).unwrap();
        if gpu.has_timestamps() {
            assert!(ms > 0.0, "frame {frame}: {ms}");
        } else {
            assert_eq!(ms, 0.0, "nothing is timed without timestamps");
        }
        assert_eq!(stats.take_gpu_ms(gpu).unwrap(), 0.0, "read once");
    }
}

#[test]
fn an_animated_pin_reruns_every_frame_with_last_frames_positions() {
    let mut run = Run::new(&spherize_by_lfo());
    run.frame(0, 2);
    let (before, _) = read_mesh(&run.renderer, &run.mesh(2)).unwrap();
    assert_eq!(run.frame(1, 2), (NodeRun::Evaluated, 1));
    let (now, _) = read_mesh(&run.renderer, &run.mesh(2)).unwrap();
    let mut moved = 0;
    for (b, n) in before.iter().zip(&now) {
        assert_eq!(n.previous_position[..3], b.position_u[..3]);
        moved += usize::from(n.position_u != b.position_u);
    }
    assert!(moved > 0);
}

#[test]
fn extrude_reruns_only_when_its_amounts_change() {
    let patch = box_into(NodeDoc::new(2, "Extrude").with("Amount", vec![0.1f32, 0.2]));
    let mut run = Run::new(&patch);
    assert_eq!(run.frame(0, 2), (NodeRun::Evaluated, 1));
    assert_eq!(run.frame(1, 2), (NodeRun::Evaluated, 1));
    assert_eq!(run.frame(2, 2), (NodeRun::Reused, 0));
    let mesh = run.mesh(2);
    assert_eq!(
        mesh.indices.len(),
        12 * 7 * 3,
        "a box's 12 faces, 7 triangles each"
    );
}

#[test]
fn tube_and_ribbon_run_once_and_refuse_too_few_points() {
    for name in ["Tube", "Ribbon"] {
        let mut patch = Patch::default();
        patch.add(NodeDoc::new(2, name));
        patch.add(NodeDoc::new(3, "Probe"));
        patch.link(2, "Mesh", 3, "Input");
        let mut run = Run::new(&patch);
        assert_eq!(run.frame(0, 2), (NodeRun::Evaluated, 1));
        run.frame(1, 2);
        assert_eq!(run.frame(2, 2), (NodeRun::Reused, 0), "{name}");
        assert!(run.mesh(2).has_uvs);

        let mut patch = Patch::default();
        patch.add(NodeDoc::new(2, name).with("Points", vec![glam::Vec3::ZERO]));
        patch.add(NodeDoc::new(3, "Probe"));
        patch.link(2, "Mesh", 3, "Input");
        let mut run = Run::new(&patch);
        run.runtime.evaluate(FrameClock::fixed(0, 60.0));
        assert!(
            matches!(run.runtime.node_error(NodeId(2)), Some(spreadlight_graph::NodeError::Input { pin, .. }) if pin == "Points"),
            "{name}"
        );
    }
}

#[test]
fn pn_triangles_and_subdivide_make_level_squared_triangles_once() {
    for name in ["PN Triangles", "Subdivide"] {
        let mut run = Run::new(&box_into(NodeDoc::new(2, name).with("Level", vec![4i64])));
        assert_eq!(run.frame(0, 2), (NodeRun::Evaluated, 1));
        run.frame(1, 2);
        assert_eq!(run.frame(2, 2), (NodeRun::Reused, 0), "{name}");
        assert_eq!(run.mesh(2).indices.len(), 12 * 16 * 3, "{name}");
    }
}
