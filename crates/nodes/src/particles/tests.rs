//! The `Particles` node in a runtime: it steps every frame, keeps its state
//! across frames, is deterministic for a seed, resets on demand, and its
//! bad inputs are errors naming the pin.

use std::sync::Arc;

use glam::Vec3;
use spreadlight_graph::{
    FrameClock, NodeDoc, NodeError, NodeId, NodeRun, Patch, Runtime, Spread, format,
};
use spreadlight_render::particles::read_drawn;

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
    let (vertices, _) = read_drawn(&run.renderer, &run.mesh(2), Vec3::X, Vec3::Y).unwrap();
    vertices.iter().map(|v| v.position_u).collect()
}

#[test]
fn the_node_is_deterministic_and_keeps_its_state_across_frames() {
    let a = positions(6, fountain());
    assert_eq!(a, positions(6, fountain()));
    assert_ne!(a, positions(6, fountain().with("Seed", vec![2i64])));
    assert_ne!(a, positions(5, fountain()), "each frame steps the system");
    assert_eq!(a.len(), 64 * 6, "two triangles a slot");
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
    let (vertices, _) = read_drawn(&run.renderer, &run.mesh(2), Vec3::X, Vec3::Y).unwrap();
    // Reset, then one step of 1/60 s at 600 a second: 10 particles born (a
    // dead slot collapses its quad to a point).
    let born = vertices
        .chunks(6)
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

/// The centres and half sizes of the live particles of node `id`'s drawn
/// sprites (corners 0 and 2 of each quad are opposite), read as the drawing
/// passes make them.
fn sprites(
    runtime: &Runtime,
    renderer: &spreadlight_render::Renderer,
    id: u32,
) -> Vec<(Vec3, f32)> {
    let mesh = match runtime.output(NodeId(id), "Mesh").map(|s| s.as_ref()) {
        Some(Spread::Resource(_, handles)) if !handles.is_empty() => handles[0]
            .downcast_arc::<spreadlight_render::mesh_arena::GpuMesh>()
            .expect("a mesh"),
        other => panic!("node #{id} output {other:?}"),
    };
    let (vertices, _) = read_drawn(renderer, &mesh, Vec3::X, Vec3::Y).unwrap();
    vertices
        .chunks(6)
        .filter(|q| q[0].position_u[..3] != q[2].position_u[..3])
        .map(|q| {
            let (a, b) = (
                Vec3::from_slice(&q[0].position_u),
                Vec3::from_slice(&q[2].position_u),
            );
            ((a + b) * 0.5, (b.x - a.x).abs() * 0.5)
        })
        .collect()
}

fn centres(runtime: &Runtime, renderer: &spreadlight_render::Renderer, id: u32) -> Vec<Vec3> {
    sprites(runtime, renderer, id)
        .into_iter()
        .map(|(c, _)| c)
        .collect()
}

/// Runs `patch` for `frames` frames at 60 fps rendering its outputs at
/// `size` x `size` on the test GPU; no node may fail.
fn render_frames(
    patch: &Patch,
    frames: u64,
    size: u32,
) -> (Runtime, Arc<spreadlight_render::Renderer>) {
    let renderer = spreadlight_render::renderer::test_renderer();
    renderer.set_output_size((size, size));
    let mut runtime = Runtime::new(crate::registry());
    runtime.provide(renderer.clone());
    runtime.provide(Arc::new(crate::output::RenderedImages::default()));
    let problems = runtime.load(patch).to_vec();
    assert!(problems.is_empty(), "{problems:?}");
    for frame in 0..frames {
        runtime.evaluate(FrameClock::fixed(frame, 60.0));
        let errors: Vec<_> = runtime
            .node_errors()
            .map(|(id, e)| format!("{id}: {e}"))
            .collect();
        assert!(errors.is_empty(), "frame {frame}: {errors:?}");
    }
    (runtime, renderer)
}

/// A floor (y = 0) and a ball of radius 0.5 half sunk in it, seen from
/// above by an MRE that publishes its depth as "scene"; 200 particles a
/// second dropped from y = 2 over them (living 100 s, shrinking with age
/// so their size tells it); `collide` names the depth the particles collide
/// with ("" for none).
fn drop_onto_floor_and_ball(collide: &str) -> Patch {
    let mut p = Patch::default();
    p.add(NodeDoc::new(1, "Plane").with("Size", vec![glam::Vec2::splat(4.0)]));
    p.add(NodeDoc::new(2, "Sphere").with("Radius", vec![0.5f32]));
    p.add(NodeDoc::new(3, "DeferredBase"));
    p.add(NodeDoc::new(4, "DeferredBase"));
    p.add(NodeDoc::new(5, "Transform (Transform 3d)").with("Translate Y", vec![2.0f32]));
    p.add(
        NodeDoc::new(6, "Particles")
            .with("Count", vec![512i64])
            .with("Rate", vec![200.0f32])
            .with("Lifetime", vec![100.0f32])
            .with("Lifetime Spread", vec![0.0f32])
            .with("Emitter", Spread::Enum(vec!["Box".to_owned()]))
            .with("Emitter Size", vec![Vec3::new(1.2, 0.1, 1.2)])
            .with("Velocity", vec![Vec3::ZERO])
            .with("Velocity Spread", vec![0.0f32])
            .with("Drag", vec![0.0f32])
            .with("Bounce", vec![0.2f32])
            .with("Shrink", vec![true])
            .with("Size", vec![0.02f32])
            .with("Collide Depth", vec![collide.to_owned()]),
    );
    p.add(
        NodeDoc::new(7, "DeferredBase").with("Velocity", Spread::Enum(vec!["Geometry".to_owned()])),
    );
    p.add(NodeDoc::new(8, "Group (Layer)"));
    p.add(
        NodeDoc::new(9, "Camera")
            .with("Pitch", vec![0.2f32])
            .with("Distance", vec![6.0f32])
            .with("Aspect Ratio", vec![1.0f32]),
    );
    p.add(NodeDoc::new(10, "MRE").with("Publish Depth", vec!["scene".to_owned()]));
    p.add(
        NodeDoc::new(11, "GBufferView").with("Channel", Spread::Enum(vec!["Velocity".to_owned()])),
    );
    p.add(
        NodeDoc::new(12, "Output")
            .with("Name", vec!["scene".to_owned()])
            .with("Write", vec![false]),
    );
    p.link(1, "Mesh", 3, "Mesh");
    p.link(2, "Mesh", 4, "Mesh");
    p.link(5, "Transform Out", 6, "Emitter Transform");
    p.link(6, "Mesh", 7, "Mesh");
    p.link(3, "Layer", 8, "Layer 1");
    p.link(4, "Layer", 8, "Layer 2");
    p.link(7, "Layer", 8, "Layer 3");
    p.link(8, "Layer", 10, "Layer");
    p.link(9, "View", 10, "View");
    p.link(9, "Projection", 10, "Projection");
    p.link(10, "G-Buffer", 11, "G-Buffer");
    p.link(11, "Texture", 12, "Texture");
    p
}

#[test]
fn particles_land_on_the_floor_and_ball_an_mre_publishes() {
    // 2.5 s: a fall of 2 m takes 0.64 s; those a second old or more have landed.
    let (runtime, renderer) = render_frames(&drop_onto_floor_and_ball("scene"), 150, 96);
    let all = sprites(&runtime, &renderer, 6);
    // 149 steps of 1/60 s (the first frame's is 0) at 200 a second.
    assert_eq!(all.len(), 496, "none died");
    // Half size 0.02 shrinking to 0 over 100 s: age = 100 (1 - size / 0.02).
    let landed: Vec<Vec3> = all
        .iter()
        .filter(|(_, half)| 100.0 * (1.0 - half / 0.02) > 1.0)
        .map(|(c, _)| *c)
        .collect();
    assert!(landed.len() > 250, "{} old enough", landed.len());
    for c in &landed {
        assert!(c.is_finite(), "{c}");
        // On the surface below them, to within the depth's resolution: a
        // pixel (4 cm here) of the steep side of the ball spans several cm
        // of height, and the depth is read per pixel.
        let radial = (c.x * c.x + c.z * c.z).sqrt();
        let surface = if radial < 0.5 {
            (0.25 - radial * radial).max(0.0).sqrt()
        } else {
            0.0
        };
        assert!(
            c.y > surface - 0.1 && c.y < surface + 0.3,
            "a particle at {c} is not resting on the surface at {surface}"
        );
    }
    assert!(
        landed
            .iter()
            .any(|c| (c.x * c.x + c.z * c.z).sqrt() < 0.35 && c.y > 0.3),
        "some rest on the ball's top"
    );
    // Without the depth they fall through both.
    let (runtime, renderer) = render_frames(&drop_onto_floor_and_ball(""), 150, 32);
    let fallen = sprites(&runtime, &renderer, 6)
        .iter()
        .filter(|(c, half)| 100.0 * (1.0 - half / 0.02) > 1.0 && c.y < -1.0)
        .count();
    assert!(fallen > 250, "{fallen} fell through");
}

#[test]
fn the_particle_benchmark_collides_with_its_depth_at_a_small_count() {
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../patches/bench-particles.ron");
    let mut patch = format::load(&path).unwrap_or_else(|e| panic!("{e}"));
    for node in &mut patch.nodes {
        if node.id.0 == 1 {
            node.values.insert("Input".into(), Spread::Int(vec![2000]));
        }
    }
    // 3 s: the first particles (born at y 4 to 6) have reached the floor.
    let (runtime, renderer) = render_frames(&patch, 180, 192);
    let all = centres(&runtime, &renderer, 3);
    assert!(all.len() > 1000, "the ring is mostly full: {}", all.len());
    assert!(all.iter().all(|c| c.is_finite()));
    // Over the floor the camera sees, away from the ball (radius 2 at the
    // origin), particles stay on or above it to within the depth's
    // resolution. Depth collision is screen-space: where the floor is out
    // of view or hidden behind the ball, or where they hit the ball's far
    // side, they may fall through, so those places are left out.
    let view_projection = spreadlight_render::gbuffer::PublishedDepths::of(&renderer)
        .get("scene")
        .expect("the MRE published its depth")
        .view_projection;
    let inverse = view_projection.inverse();
    let seen: Vec<_> = all
        .iter()
        .filter(|c| {
            let floor = Vec3::new(c.x, 0.0, c.z);
            let clip = view_projection * floor.extend(1.0);
            let ndc = clip.truncate() / clip.w;
            if clip.w <= 0.0 || ndc.x.abs() > 0.9 || ndc.y.abs() > 0.9 {
                return false;
            }
            // The segment from the near plane to the floor point misses the
            // ball by a margin, and the point is not under it.
            let near = inverse.project_point3(Vec3::new(ndc.x, ndc.y, 1.0));
            let d = floor - near;
            let t = (-near.dot(d) / d.length_squared()).clamp(0.0, 1.0);
            (near + d * t).length() > 2.5 && floor.length() > 3.0
        })
        .collect();
    assert!(seen.len() > 100, "the camera sees many: {}", seen.len());
    for c in seen {
        assert!(
            c.y > -0.15,
            "a particle over the visible floor fell through it: {c}"
        );
    }
}
