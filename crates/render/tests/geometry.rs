//! GPU geometry on a real (software) GPU: previous-frame positions reach the
//! G-buffer's velocity as the analytic motion predicts, geometry ids reach
//! its object-id channel, and each geometry pass keeps its shape properties.

use crate::common;

use std::sync::Arc;

use glam::{Mat4, Vec2, Vec3};
use spreadlight_render::camera::CameraInput;
use spreadlight_render::gbuffer::{
    DrawBatch, GBuffer, InstanceInput, Layer, LayerError, LayerFeatures, VelocitySource,
};
use spreadlight_render::geometry::{SpherizeParams, read_mesh, spherize};
use spreadlight_render::mesh::primitives::{BoxParams, GridParams, box_mesh, grid};
use spreadlight_render::mesh_arena::GpuMesh;
use spreadlight_render::readback::{ImageF32, render_and_read};
use spreadlight_render::renderer::test_renderer;
use spreadlight_render::{Renderer, SizeRule};

use common::open_edges;

const SIZE: (u32, u32) = (32, 32);

fn camera() -> CameraInput {
    CameraInput {
        view: glam::camera::rh::view::look_at_mat4(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::Y),
        projection: glam::camera::rh::proj::directx::perspective(
            50f32.to_radians(),
            1.0,
            0.1,
            100.0,
        ),
    }
}

/// A 3x3 grid facing +Z (the camera) once the instance turns it.
fn facing() -> Mat4 {
    Mat4::from_rotation_x(std::f32::consts::FRAC_PI_2)
}

fn render(
    renderer: &Renderer,
    mesh: Arc<GpuMesh>,
    features: LayerFeatures,
    object_id: u32,
) -> (ImageF32, ImageF32) {
    let layer = Layer::new(
        Some(1),
        vec![DrawBatch {
            mesh,
            instances: vec![InstanceInput {
                transform: facing(),
                previous_transform: facing(),
                color: [1.0; 4],
                material_id: 1,
                object_id,
            }],
        }],
        features,
        None,
    )
    .expect("the mesh serves the switches");
    let camera = camera();
    let g = GBuffer::new(
        renderer,
        None,
        vec![Arc::new(layer)],
        camera,
        Some(camera.view_projection()),
        SizeRule::Relative(1.0),
    );
    let (report, mut images) = render_and_read(
        renderer,
        g.as_ref(),
        SIZE,
        &[&g.targets.velocity_uv, &g.targets.normals],
    )
    .expect("frame executes");
    assert!(report.errors.is_empty(), "{:?}", report.errors);
    let normals = images.pop().expect("two targets");
    (images.pop().expect("two targets"), normals)
}

fn plane() -> spreadlight_render::mesh::MeshData {
    grid(GridParams {
        size: Vec2::splat(3.0),
        resolution_x: 3,
        resolution_y: 3,
    })
}

#[test]
fn velocity_from_geometry_is_the_analytic_motion_of_a_deforming_mesh() {
    let renderer = test_renderer();
    let data = plane();
    // Every vertex moved by +0.25 along object X since last frame (the
    // instance's transform did not move at all).
    let offset = Vec3::new(0.25, 0.0, 0.0);
    let previous: Vec<[f32; 4]> = data
        .positions
        .iter()
        .map(|p| (Vec3::from(*p) - offset).extend(0.0).into())
        .collect();
    let mesh = renderer
        .meshes
        .upload_with_previous(&renderer.gpu, &data, &previous)
        .expect("upload");
    let geometry = LayerFeatures {
        velocity: VelocitySource::Geometry,
        ..Default::default()
    };
    let (velocity, _) = render(&renderer, mesh.clone(), geometry, 0);
    // The plane sits at z = 0 in world space, so a uniform offset projects to
    // the same screen motion everywhere on it.
    let vp = camera().view_projection();
    let project = |p: Vec3| {
        let c = vp * p.extend(1.0);
        (c.truncate() / c.w).truncate()
    };
    let world_offset = facing().transform_vector3(offset);
    let expected = (project(Vec3::ZERO) - project(-world_offset)) * Vec2::new(0.5, -0.5);
    assert!(expected.x > 0.02, "the test moves something visibly");
    let mut covered = 0;
    for y in 0..SIZE.1 {
        for x in 0..SIZE.0 {
            let v = velocity.pixel(x, y);
            if v == [0.0; 4] {
                continue;
            }
            covered += 1;
            assert!(
                (v[0] - expected.x).abs() < 1e-3 && (v[1] - expected.y).abs() < 1e-3,
                "pixel ({x}, {y}): velocity {v:?}, expected {expected:?}"
            );
        }
    }
    assert!(covered > 100, "the plane covers the middle of the image");

    // Velocity from transforms ignores the deformation: the instance is still.
    let (still, _) = render(&renderer, mesh, LayerFeatures::default(), 0);
    assert!(still.pixels.iter().all(|p| p[0] == 0.0 && p[1] == 0.0));

    // A mesh without previous positions cannot serve the switch: an error, as before.
    let rigid = renderer
        .meshes
        .upload(&renderer.gpu, &data)
        .expect("upload");
    let layer = Layer::new(
        None,
        vec![DrawBatch {
            mesh: rigid,
            instances: vec![],
        }],
        geometry,
        None,
    );
    assert_eq!(
        layer.err(),
        Some(LayerError::NoPreviousPositions { mesh: 0 })
    );
}

#[test]
fn geometry_ids_add_to_the_object_id_only_when_asked() {
    let renderer = test_renderer();
    let data = plane();
    let with_ids: Vec<[f32; 4]> = data
        .positions
        .iter()
        .map(|p| [p[0], p[1], p[2], 5.0])
        .collect();
    let mesh = renderer
        .meshes
        .upload_with_previous(&renderer.gpu, &data, &with_ids)
        .expect("upload");
    let object_id_at_centre = |geometry_ids: bool| {
        let features = LayerFeatures {
            ids: true,
            geometry_ids,
            ..Default::default()
        };
        let (_, normals) = render(&renderer, mesh.clone(), features, 7);
        normals.pixel(SIZE.0 / 2, SIZE.1 / 2)[3]
    };
    assert_eq!(object_id_at_centre(false), 7.0);
    assert_eq!(object_id_at_centre(true), 12.0);
}

fn length(v: [f32; 4]) -> f32 {
    Vec3::new(v[0], v[1], v[2]).length()
}

#[test]
fn spherize_at_one_lies_on_the_sphere_and_at_zero_is_the_mesh() {
    let renderer = test_renderer();
    let data = box_mesh(BoxParams {
        size: Vec3::ONE,
        segments: 3,
    });
    let input = renderer
        .meshes
        .upload(&renderer.gpu, &data)
        .expect("upload");
    let params = |amount| SpherizeParams {
        center: Vec3::ZERO,
        radius: 2.0,
        amount,
    };
    let round = spherize(&renderer, &input, None, params(1.0)).expect("spherize");
    let (vertices, indices) = read_mesh(&renderer, &round).expect("readback");
    assert_eq!(indices, data.indices, "spherize keeps the topology");
    assert_eq!(vertices.len(), data.positions.len());
    for (i, v) in vertices.iter().enumerate() {
        let p = Vec3::from_slice(&v.position_u);
        assert!((p.length() - 2.0).abs() < 1e-5, "vertex {i} at {p}");
        let n = Vec3::from_slice(&v.normal_v);
        assert!((n - p / 2.0).length() < 1e-4, "normal {n} at {p}");
        let t = Vec3::from_slice(&v.tangent);
        assert!((t.length() - 1.0).abs() < 1e-4 && t.dot(n).abs() < 1e-4);
        // UVs are kept, and a fresh output has no motion.
        let uvs = data.uvs.as_ref().unwrap()[i];
        assert_eq!([v.position_u[3], v.normal_v[3]], uvs);
        assert_eq!(&v.previous_position[..3], &v.position_u[..3]);
    }
    let same = spherize(&renderer, &input, None, params(0.0)).expect("spherize");
    let (vertices, _) = read_mesh(&renderer, &same).expect("readback");
    for (v, (p, n)) in vertices
        .iter()
        .zip(data.positions.iter().zip(&data.normals))
    {
        assert!((Vec3::from_slice(&v.position_u) - Vec3::from(*p)).length() < 1e-6);
        assert!((Vec3::from_slice(&v.normal_v) - Vec3::from(*n)).length() < 1e-5);
    }
    assert!(length(vertices[0].tangent) > 0.99);
}

#[test]
fn a_rerun_with_new_pins_keeps_last_frames_positions_as_previous() {
    let renderer = test_renderer();
    let data = box_mesh(BoxParams::default());
    let input = renderer
        .meshes
        .upload(&renderer.gpu, &data)
        .expect("upload");
    let at = |amount| SpherizeParams {
        center: Vec3::ZERO,
        radius: 1.0,
        amount,
    };
    let frame0 = spherize(&renderer, &input, None, at(0.0)).unwrap();
    let frame1 = spherize(&renderer, &input, Some(&frame0), at(0.5)).unwrap();
    let frame2 = spherize(&renderer, &input, Some(&frame1), at(0.5)).unwrap();
    let (v0, _) = read_mesh(&renderer, &frame0).unwrap();
    let (v1, _) = read_mesh(&renderer, &frame1).unwrap();
    let (v2, _) = read_mesh(&renderer, &frame2).unwrap();
    let mut moved = 0;
    for i in 0..v1.len() {
        assert_eq!(v1[i].previous_position[..3], v0[i].position_u[..3]);
        moved += usize::from(v1[i].position_u[..3] != v0[i].position_u[..3]);
        // The pins stood still: the next run settles to zero motion.
        assert_eq!(v2[i].previous_position[..3], v2[i].position_u[..3]);
    }
    assert!(moved > 0, "amount 0 to 0.5 moves the box's corners");
    assert!(frame1.has_previous_positions);
}

#[test]
fn extrude_adds_seven_triangles_a_face_and_a_closed_mesh_stays_closed() {
    use spreadlight_render::geometry::extrude;
    let renderer = test_renderer();
    let data = box_mesh(BoxParams {
        size: Vec3::ONE,
        segments: 2,
    });
    let input = renderer
        .meshes
        .upload(&renderer.gpu, &data)
        .expect("upload");
    let (v_in, i_in) = read_mesh(&renderer, &input).unwrap();
    assert_eq!(open_edges(&v_in, &i_in), 0, "the box is closed");
    let out = extrude(&renderer, &input, None, &[0.1, 0.3], None).expect("extrude");
    let (vertices, indices) = read_mesh(&renderer, &out).unwrap();
    let faces = data.indices.len() / 3;
    assert_eq!(
        indices.len() / 3,
        faces * 7,
        "cap + 3 walls of 2 triangles a face"
    );
    assert_eq!(vertices.len(), faces * 15);
    assert_eq!(open_edges(&vertices, &indices), 0, "still closed");
    // Face 1's cap is 0.3 out along its normal (amounts cycle).
    for (f, amount) in [(0usize, 0.1f32), (1, 0.3)] {
        let corner = |k: usize| Vec3::from(data.positions[data.indices[f * 3 + k] as usize]);
        let n = (corner(1) - corner(0))
            .cross(corner(2) - corner(0))
            .normalize();
        for k in 0..3 {
            let cap = Vec3::from_slice(&vertices[f * 15 + k].position_u);
            assert!(
                (cap - corner(k) - n * amount).length() < 1e-5,
                "face {f} cap {k}"
            );
            assert!((Vec3::from_slice(&vertices[f * 15 + k].normal_v) - n).length() < 1e-5);
        }
    }
    for v in &vertices {
        let n = Vec3::from_slice(&v.normal_v);
        let t = Vec3::from_slice(&v.tangent);
        assert!((n.length() - 1.0).abs() < 1e-4 && (t.length() - 1.0).abs() < 1e-4);
    }
}

#[test]
fn a_tube_passes_through_its_points_with_their_radii() {
    use spreadlight_render::geometry::{Curve, Sweep, spline};
    let renderer = test_renderer();
    let points = [
        Vec3::ZERO,
        Vec3::new(1.0, 0.5, 0.0),
        Vec3::new(2.0, 0.0, 1.0),
        Vec3::new(2.5, 1.0, 2.0),
    ];
    let radii = [0.1, 0.2, 0.15, 0.3];
    let (segments, sides) = (5usize, 8usize);
    let tube = spline(
        &renderer,
        &points,
        &radii,
        Curve::CatmullRom,
        segments as u32,
        Sweep::Tube {
            sides: sides as u32,
        },
        None,
    )
    .expect("tube");
    let (vertices, indices) = read_mesh(&renderer, &tube).unwrap();
    let rings = 3 * segments + 1;
    assert_eq!(vertices.len(), rings * (sides + 1));
    assert_eq!(indices.len(), (rings - 1) * sides * 6);
    for (k, (p, r)) in points.iter().zip(radii).enumerate() {
        let ring = &vertices[k * segments * (sides + 1)..][..sides];
        let centre = ring
            .iter()
            .map(|v| Vec3::from_slice(&v.position_u))
            .sum::<Vec3>()
            / sides as f32;
        assert!(
            (centre - *p).length() < 1e-5,
            "point {k}: ring centred at {centre}"
        );
        for v in ring {
            let offset = Vec3::from_slice(&v.position_u) - *p;
            assert!((offset.length() - r).abs() < 1e-5, "radius at point {k}");
            let n = Vec3::from_slice(&v.normal_v);
            assert!((n - offset / r).length() < 1e-4, "radial normals");
            assert!(n.dot(Vec3::from_slice(&v.tangent)).abs() < 1e-4);
        }
    }
    // Outward winding: each triangle's geometric normal agrees with its vertices' normals.
    for t in indices.chunks(3) {
        let p = |i: u32| Vec3::from_slice(&vertices[i as usize].position_u);
        let face = (p(t[1]) - p(t[0])).cross(p(t[2]) - p(t[0]));
        let n = Vec3::from_slice(&vertices[t[0] as usize].normal_v);
        assert!(face.dot(n) >= 0.0, "triangle {t:?} faces inwards");
    }
    let ribbon = spline(
        &renderer,
        &points,
        &radii,
        Curve::CatmullRom,
        4,
        Sweep::Ribbon,
        None,
    )
    .expect("ribbon");
    let (vertices, _) = read_mesh(&renderer, &ribbon).unwrap();
    for (k, p) in points.iter().enumerate() {
        let pair = &vertices[k * 4 * 2..][..2];
        let mid =
            (Vec3::from_slice(&pair[0].position_u) + Vec3::from_slice(&pair[1].position_u)) / 2.0;
        assert!((mid - *p).length() < 1e-5, "ribbon through point {k}");
    }
}

#[test]
fn pn_triangles_bound_the_error_to_the_sphere_and_stay_closed() {
    use spreadlight_render::geometry::pn_triangles;
    let renderer = test_renderer();
    let ico = renderer
        .meshes
        .upload(
            &renderer.gpu,
            &spreadlight_render::geometry::analytic::icosahedron(),
        )
        .expect("upload");
    let (v0, i0) = read_mesh(&renderer, &ico).unwrap();
    assert_eq!(open_edges(&v0, &i0), 0);
    // Largest distance from the unit sphere over vertices and triangle centroids.
    let error = |curved: bool, level: u32| {
        let mesh = pn_triangles(&renderer, &ico, None, level, curved).expect("tessellate");
        let (v, i) = read_mesh(&renderer, &mesh).unwrap();
        assert_eq!(
            i.len(),
            20 * 3 * (level * level) as usize,
            "level² triangles a face"
        );
        assert_eq!(
            open_edges(&v, &i),
            0,
            "no cracks (curved {curved}, level {level})"
        );
        let p = |k: u32| Vec3::from_slice(&v[k as usize].position_u);
        i.chunks(3)
            .map(|t| (p(t[0]) + p(t[1]) + p(t[2])) / 3.0)
            .chain(v.iter().map(|x| Vec3::from_slice(&x.position_u)))
            .map(|q| (q.length() - 1.0).abs())
            .fold(0.0f32, f32::max)
    };
    let flat = [1, 2, 4, 8].map(|l| error(false, l));
    let curved = [1, 2, 4, 8].map(|l| error(true, l));
    // Flat subdivision never leaves the icosahedron: its error does not vanish.
    assert!(flat.iter().all(|e| *e > 0.05), "{flat:?}");
    // PN's error falls with the level towards its cubic patch's own error:
    // within 6.5% of the radius from level 8 on, a third of flat's.
    for w in curved.windows(2) {
        assert!(w[1] < w[0], "{curved:?}");
    }
    assert!(curved[3] < 0.065, "{curved:?}");
    assert!(curved[3] < flat[3] / 3.0, "{curved:?} vs {flat:?}");
}
