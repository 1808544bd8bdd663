//! The `glTF` node's skinned instances in a runtime with a renderer: a
//! moving Time deforms every frame (one skinning dispatch) with last frame's
//! positions as previous positions; a still pose settles once and then
//! reruns nothing.

use glam::{Mat4, Quat, Vec3};
use spreadlight_gltf::skinned_models::{BAR_BEND_RATE, coloured_two_bone_bar, two_bone_bar};
use spreadlight_graph::{NodeDoc, NodeRun, Patch};
use spreadlight_render::geometry::{GeometryStats, read_extras, read_mesh};
use spreadlight_render::mesh_arena::GpuVertexExtra;

use super::tests::Run;

/// glTF (#2) of the bar at `time` into a Probe, its Time from node #4 when `timed`.
fn bar_at(dir: &std::path::Path, time: f32, timed: bool) -> Patch {
    std::fs::write(dir.join("bar.gltf"), two_bone_bar()).unwrap();
    let mut patch = Patch::default();
    patch.add(
        NodeDoc::new(2, "glTF")
            .with("Filename", vec![dir.join("bar.gltf").display().to_string()])
            .with("Time", vec![time]),
    );
    patch.add(NodeDoc::new(3, "Probe"));
    patch.link(2, "Mesh", 3, "Input");
    if timed {
        patch.add(NodeDoc::new(4, "Time (Animation)"));
        patch.link(4, "Time", 2, "Time");
    }
    patch
}

fn bar_patch(dir: &std::path::Path, timed: bool) -> Patch {
    bar_at(dir, 0.25, timed)
}

fn skinning(run: &Run) -> u64 {
    GeometryStats::of(&run.renderer).skinning_dispatches()
}

#[test]
fn a_still_pose_deforms_once_and_then_reruns_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let mut run = Run::new(&bar_patch(dir.path(), false));
    assert_eq!(run.frame(0, 2), (NodeRun::Evaluated, 1));
    assert_eq!(skinning(&run), 1, "the dispatch is skinning's");
    // The first pose moved from nothing: no settling run is needed.
    for frame in 1..4 {
        assert_eq!(run.frame(frame, 2), (NodeRun::Reused, 0), "frame {frame}");
    }
    let (vertices, indices) = read_mesh(&run.renderer, &run.mesh(2)).unwrap();
    assert_eq!(indices.len(), 8 * 6, "the bar's indices are copied");
    assert!(
        vertices
            .iter()
            .all(|v| v.previous_position[..3] == v.position_u[..3])
    );
    // The tip end (rest (2, +-0.1)) turned by a quarter of the bend rate's second.
    let turn = Mat4::from_translation(Vec3::X)
        * Mat4::from_quat(Quat::from_rotation_z(BAR_BEND_RATE * 0.25))
        * Mat4::from_translation(-Vec3::X);
    let want = turn.transform_point3(Vec3::new(2.0, 0.1, 0.0));
    let got = Vec3::from_slice(&vertices[17].position_u[..3]);
    assert!((got - want).length() < 1e-5, "{got} vs {want}");
}

#[test]
fn a_moving_time_deforms_every_frame_from_last_frames_positions() {
    let dir = tempfile::tempdir().unwrap();
    let mut run = Run::new(&bar_patch(dir.path(), true));
    run.frame(0, 2);
    let (before, _) = read_mesh(&run.renderer, &run.mesh(2)).unwrap();
    for frame in 1..3 {
        let skinned = skinning(&run);
        assert_eq!(
            run.frame(frame, 2),
            (NodeRun::Evaluated, 1),
            "frame {frame}"
        );
        assert_eq!(skinning(&run), skinned + 1);
    }
    let (last, _) = read_mesh(&run.renderer, &run.mesh(2)).unwrap();
    let moved = last
        .iter()
        .filter(|v| v.previous_position[..3] != v.position_u[..3])
        .count();
    assert!(moved >= 8, "the tip half moves: {moved}");
    assert_ne!(before[17].position_u, last[17].position_u);
    // The previous positions are frame 1's: the analytic pose at 1/60 s.
    let turn = |t: f32| {
        Mat4::from_translation(Vec3::X)
            * Mat4::from_quat(Quat::from_rotation_z(BAR_BEND_RATE * t))
            * Mat4::from_translation(-Vec3::X)
    };
    let rest = Vec3::new(2.0, 0.1, 0.0);
    let previous = Vec3::from_slice(&last[17].previous_position[..3]);
    let now = Vec3::from_slice(&last[17].position_u[..3]);
    assert!(
        (previous - turn(1.0 / 60.0).transform_point3(rest)).length() < 1e-5,
        "{previous}"
    );
    assert!(
        (now - turn(2.0 / 60.0).transform_point3(rest)).length() < 1e-5,
        "{now}"
    );
}

#[test]
fn a_pose_change_settles_in_one_more_frame() {
    let dir = tempfile::tempdir().unwrap();
    let mut run = Run::new(&bar_patch(dir.path(), false));
    run.frame(0, 2);
    // The same patch with another Time: the node keeps its state.
    let problems = run.runtime.load(&bar_at(dir.path(), 0.5, false));
    assert!(problems.is_empty(), "{problems:?}");
    assert_eq!(run.frame(1, 2), (NodeRun::Evaluated, 1), "the new pose");
    assert_eq!(run.frame(2, 2), (NodeRun::Evaluated, 1), "its settling run");
    assert_eq!(run.frame(3, 2), (NodeRun::Reused, 0));
    let (vertices, _) = read_mesh(&run.renderer, &run.mesh(2)).unwrap();
    assert!(
        vertices
            .iter()
            .all(|v| v.previous_position[..3] == v.position_u[..3])
    );
}

/// The skinning kernel copies each rest vertex's extras beside the deformed
/// vertex: a skinned mesh keeps its COLOR_0 and TEXCOORD_1, frame after
/// frame, and says so (the G-buffer reads its extras only then). Nothing
/// uploads them each frame.
#[test]
fn a_skinned_mesh_keeps_its_vertex_colours_and_second_uv_set() {
    let dir = tempfile::tempdir().unwrap();
    let patch = bar_patch(dir.path(), true);
    let (file, colours, uvs) = coloured_two_bone_bar();
    std::fs::write(dir.path().join("bar.gltf"), file).unwrap();
    let mut run = Run::new(&patch);
    for frame in 0..3 {
        assert_eq!(
            run.frame(frame, 2),
            (NodeRun::Evaluated, 1),
            "frame {frame}"
        );
        let mesh = run.mesh(2);
        assert!(mesh.has_colors && mesh.has_uvs1, "frame {frame}");
        let extras = read_extras(&run.renderer, &mesh).unwrap();
        assert_eq!(extras.len(), colours.len());
        for (i, extra) in extras.iter().enumerate() {
            assert_eq!(
                *extra,
                GpuVertexExtra::new(uvs[i], colours[i]),
                "frame {frame}, vertex {i}"
            );
        }
    }
}

/// An animated file evaluates every frame with the same materials: a
/// MaterialBuffer behind it gives back the world it made, not a new upload
/// every frame; a new First Material ID makes a new one.
#[test]
fn a_material_buffer_behind_an_animated_file_keeps_its_world() {
    use spreadlight_graph::{NodeId, Spread};
    use spreadlight_render::material::MaterialWorld;
    use std::sync::Arc;

    let dir = tempfile::tempdir().unwrap();
    let mut patch = bar_patch(dir.path(), true);
    patch.add(NodeDoc::new(6, "MaterialBuffer"));
    patch.add(NodeDoc::new(7, "Probe"));
    patch.link(2, "Materials", 6, "Materials");
    patch.link(6, "Material World", 7, "Input");
    let mut run = Run::new(&patch);
    let world = |run: &Run| match run
        .runtime
        .output(NodeId(6), "Material World")
        .map(|s| s.as_ref())
    {
        Some(Spread::Resource(_, handles)) => handles[0]
            .downcast_arc::<MaterialWorld>()
            .expect("a material world"),
        other => panic!("{other:?}"),
    };
    run.frame(0, 2);
    let first = world(&run);
    for frame in 1..4 {
        assert_eq!(
            run.frame(frame, 2).0,
            NodeRun::Evaluated,
            "the file poses each frame"
        );
        assert!(Arc::ptr_eq(&first, &world(&run)), "frame {frame}");
    }
    let mut moved = patch.clone();
    moved.nodes[0] = moved.nodes[0].clone().with("First Material ID", vec![3i64]);
    let problems = run.runtime.load(&moved);
    assert!(problems.is_empty(), "{problems:?}");
    run.frame(4, 2);
    assert!(!Arc::ptr_eq(&first, &world(&run)), "new ids, a new world");
}
