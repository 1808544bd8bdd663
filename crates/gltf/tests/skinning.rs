//! GPU skinning and morph targets on a real (software) GPU: deformed
//! positions match the CPU reference, normals stay unit, previous positions
//! are the last pose's, and the G-buffer's velocity is the analytic motion
//! of a bar whose second bone turns a known angle between two frames.

use std::sync::Arc;

use glam::{Mat4, Quat, Vec2, Vec3, Vec4};
use spreadlight_gltf::GltfScene;
use spreadlight_gltf::load_gltf_slice;
use spreadlight_gltf::skinned_models::{BAR_BEND_RATE, swaying_tube, two_bone_bar};
use spreadlight_render::camera::CameraInput;
use spreadlight_render::gbuffer::{
    DrawBatch, GBuffer, InstanceInput, Layer, LayerFeatures, VelocitySource,
};
use spreadlight_render::geometry::read_mesh;
use spreadlight_render::geometry::skinning::{DeformJob, DeformSource, deform};
use spreadlight_render::mesh_arena::GpuMesh;
use spreadlight_render::readback::render_and_read;
use spreadlight_render::renderer::test_renderer;
use spreadlight_render::{Renderer, SizeRule};

const SIZE: (u32, u32) = (64, 48);

/// Instance 0 of `scene` deformed at `time` of animation 0, from `previous`.
fn deformed(
    renderer: &Renderer,
    scene: &GltfScene,
    source: &mut DeformSource,
    rest: &GpuMesh,
    time: f32,
    previous: Option<&GpuMesh>,
) -> Arc<GpuMesh> {
    let world = scene.node_worlds(Some(0), time);
    let weights = scene.morph_weights(Some(0), time);
    let pose = scene.deform_pose(&scene.instances[0], &world, &weights);
    let job = DeformJob {
        rest,
        mesh: 0,
        pose: &pose,
        previous,
    };
    deform(renderer, source, &[job]).expect("deforms").remove(0)
}

#[test]
fn gpu_skinning_and_morphing_match_the_cpu_reference() {
    let renderer = test_renderer();
    let scene = load_gltf_slice(&swaying_tube(), None).unwrap();
    let rest = renderer
        .meshes
        .upload(&renderer.gpu, &scene.meshes[0])
        .unwrap();
    let mut source = DeformSource::upload(&renderer, &scene.deforms).unwrap();
    let first = deformed(&renderer, &scene, &mut source, &rest, 0.4, None);
    let second = deformed(&renderer, &scene, &mut source, &rest, 0.55, Some(&first));
    let (a, _) = read_mesh(&renderer, &first).unwrap();
    let (b, indices) = read_mesh(&renderer, &second).unwrap();
    assert_eq!(indices, scene.meshes[0].indices, "indices are copied");
    for (time, got) in [(0.4f32, &a), (0.55, &b)] {
        let world = scene.node_worlds(Some(0), time);
        let weights = scene.morph_weights(Some(0), time);
        let pose = scene.deform_pose(&scene.instances[0], &world, &weights);
        assert!(pose.weights[0] > 0.5, "the morph target takes part");
        let want = scene.deformed_positions(0, &pose);
        let mut largest = 0.0f32;
        for (v, w) in got.iter().zip(&want) {
            let p = Vec3::from_slice(&v.position_u[..3]);
            largest = largest.max((p - *w).length());
            let n = Vec3::from_slice(&v.normal_v[..3]);
            assert!((n.length() - 1.0).abs() < 1e-4, "unit normals");
            assert!(p.cmpge(pose.bounds.min - 1e-4).all() && p.cmple(pose.bounds.max + 1e-4).all());
        }
        assert!(largest < 1e-4, "t {time}: GPU and CPU differ by {largest}");
    }
    // The rest mesh moved: the skin did something.
    let rest_p = Vec3::from(scene.meshes[0].positions.last().copied().unwrap());
    assert!((Vec3::from_slice(&a.last().unwrap().position_u[..3]) - rest_p).length() > 0.05);
    // The second pose's previous positions are the first's, UVs are kept.
    for (old, new) in a.iter().zip(&b) {
        assert_eq!(new.previous_position[..3], old.position_u[..3]);
        assert_eq!(new.position_u[3], old.position_u[3]);
    }
}

fn camera() -> CameraInput {
    CameraInput {
        view: glam::camera::rh::view::look_at_mat4(
            Vec3::new(1.0, 0.4, 1.8),
            Vec3::new(1.0, 0.4, 0.0),
            Vec3::Y,
        ),
        projection: glam::camera::rh::proj::directx::perspective(
            55f32.to_radians(),
            SIZE.0 as f32 / SIZE.1 as f32,
            0.1,
            100.0,
        ),
    }
}

/// The bar's tip bone turns about (1, 0, 0) by BAR_BEND_RATE * t.
fn bend(t: f32) -> Mat4 {
    Mat4::from_translation(Vec3::X)
        * Mat4::from_quat(Quat::from_rotation_z(BAR_BEND_RATE * t))
        * Mat4::from_translation(-Vec3::X)
}

#[test]
fn velocity_is_the_analytic_motion_of_a_bending_bar() {
    let renderer = test_renderer();
    let scene = load_gltf_slice(&two_bone_bar(), None).unwrap();
    let rest = renderer
        .meshes
        .upload(&renderer.gpu, &scene.meshes[0])
        .unwrap();
    let mut source = DeformSource::upload(&renderer, &scene.deforms).unwrap();
    let (t0, t1) = (0.2f32, 0.35f32);
    let before = deformed(&renderer, &scene, &mut source, &rest, t0, None);
    let now = deformed(&renderer, &scene, &mut source, &rest, t1, Some(&before));
    let layer = Layer::new(
        Some(1),
        vec![DrawBatch {
            mesh: now,
            instances: vec![InstanceInput {
                transform: Mat4::IDENTITY,
                previous_transform: Mat4::IDENTITY,
                color: [1.0; 4],
                material_id: 1,
                object_id: 0,
            }],
        }],
        LayerFeatures {
            velocity: VelocitySource::Geometry,
            ..Default::default()
        },
        None,
    )
    .expect("a skinned mesh serves Velocity: Geometry");
    let camera = camera();
    let g = GBuffer::new(
        &renderer,
        None,
        vec![Arc::new(layer)],
        camera,
        Some(camera.view_projection()),
        SizeRule::Relative(1.0),
    );
    let (report, images) =
        render_and_read(&renderer, g.as_ref(), SIZE, &[&g.targets.velocity_uv]).expect("frame");
    assert!(report.errors.is_empty(), "{:?}", report.errors);
    let velocity = &images[0];

    let vp = camera.view_projection();
    let inverse = vp.inverse();
    let project = |p: Vec3| {
        let c = vp * p.extend(1.0);
        (c.truncate() / c.w).truncate()
    };
    // The pixel centre's ray meets the bar's plane (z = 0) at a world point.
    let on_plane = |x: u32, y: u32| {
        let ndc = Vec2::new(
            (x as f32 + 0.5) / SIZE.0 as f32 * 2.0 - 1.0,
            1.0 - (y as f32 + 0.5) / SIZE.1 as f32 * 2.0,
        );
        let unproject = |z: f32| {
            let p: Vec4 = inverse * ndc.extend(z).extend(1.0);
            p.truncate() / p.w
        };
        let (a, b) = (unproject(0.0), unproject(1.0));
        a + (b - a) * (-a.z / (b.z - a.z))
    };
    let (mut tip, mut root) = (0, 0);
    for y in 0..SIZE.1 {
        for x in 0..SIZE.0 {
            let v = velocity.pixel(x, y);
            let p = on_plane(x, y);
            // Where this point of the tip bone sits in the rest pose.
            let r = bend(t1).inverse().transform_point3(p);
            let inside = |q: Vec3, from: f32, to: f32| q.x > from && q.x < to && q.y.abs() < 0.07;
            let expected = if inside(r, 1.3, 1.95) {
                tip += 1;
                let earlier = bend(t0).transform_point3(r);
                (project(p) - project(earlier)) * Vec2::new(0.5, -0.5)
            } else if inside(p, 0.05, 0.7) {
                root += 1;
                Vec2::ZERO
            } else {
                continue;
            };
            assert!(
                (v[0] - expected.x).abs() < 1e-3 && (v[1] - expected.y).abs() < 1e-3,
                "pixel ({x}, {y}) at {p}: velocity {v:?}, expected {expected}"
            );
        }
    }
    assert!(
        tip > 30 && root > 30,
        "pixels checked: tip {tip}, root {root}"
    );
}
