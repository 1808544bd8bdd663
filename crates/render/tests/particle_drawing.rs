//! Particles drawn straight from their records (procedural meshes): the
//! G-buffer they write equals what the same triangles expanded into an
//! ordinary mesh write (colour, normals, velocity, depth), and a system
//! past the old expanded path's limit costs its records only.

use std::sync::Arc;

use glam::{Mat4, Vec3};
use spreadlight_render::camera::CameraInput;
use spreadlight_render::gbuffer::{
    DrawBatch, GBuffer, InstanceInput, Layer, LayerFeatures, RasterChoice, VelocitySource,
};
use spreadlight_render::mesh::{Aabb, MeshData};
use spreadlight_render::mesh_arena::GpuMesh;
use spreadlight_render::particles::{
    DrawShape, EmitterShape, ParticleSettings, ParticleSystem, draw, read_drawn,
};
use spreadlight_render::readback::{ImageF32, render_and_read};
use spreadlight_render::renderer::test_renderer;
use spreadlight_render::{Renderer, SizeRule};

const SIZE: (u32, u32) = (48, 48);
const DT: f32 = 1.0 / 60.0;

/// From z = 5 towards the origin: the view's right is +X and its up +Y.
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

/// Colour, normals, velocity + UV and depth of `mesh` drawn with velocity
/// from geometry and geometry ids, by the given rasterizer.
fn gbuffer(renderer: &Renderer, mesh: Arc<GpuMesh>, raster: RasterChoice) -> Vec<ImageF32> {
    let layer = Layer::new(
        Some(1),
        vec![DrawBatch {
            mesh,
            instances: vec![InstanceInput {
                transform: Mat4::IDENTITY,
                previous_transform: Mat4::IDENTITY,
                color: [0.8, 0.4, 0.2, 1.0],
                material_id: 1,
                object_id: 3,
            }],
        }],
        LayerFeatures {
            texcoords: true,
            velocity: VelocitySource::Geometry,
            ids: true,
            geometry_ids: true,
            ..Default::default()
        },
        None,
    )
    .expect("layer");
    let camera = camera();
    let g = GBuffer::with_raster(
        renderer,
        None,
        vec![Arc::new(layer)],
        camera,
        Some(camera.view_projection()),
        SizeRule::Relative(1.0),
        raster,
    );
    let t = &g.targets;
    let (report, images) = render_and_read(
        renderer,
        g.as_ref(),
        SIZE,
        &[&t.color, &t.normals, &t.velocity_uv, &t.depth],
    )
    .expect("frame executes");
    assert!(report.errors.is_empty(), "{:?}", report.errors);
    images
}

/// 64 particles thrown from a box, two steps after their birth: moving, so they have velocity.
fn thrown(renderer: &Renderer) -> ParticleSystem {
    let settings = ParticleSettings {
        shape: EmitterShape::Box(Vec3::new(1.2, 1.2, 0.5)),
        rate: 1e6,
        lifetime: 10.0,
        velocity: Vec3::new(1.5, 0.5, 0.0),
        velocity_spread: 0.5,
        ..Default::default()
    };
    let mut system = ParticleSystem::new(renderer, 64, 3).expect("system");
    system.step(renderer, &settings, DT).expect("step");
    let quiet = ParticleSettings {
        rate: 0.0,
        ..settings
    };
    for _ in 0..2 {
        system.step(renderer, &quiet, DT).expect("step");
    }
    system
}

#[test]
fn drawn_from_records_the_g_buffer_is_the_expanded_meshs() {
    let renderer = test_renderer();
    let system = thrown(&renderer);
    let procedural = draw(&renderer, &system, DrawShape::Sprites, 0.12, false, 100.0).unwrap();
    // The same triangles, expanded as the old path did: an ordinary mesh
    // with previous positions and the slot as geometry id.
    let (vertices, indices) = read_drawn(&renderer, &procedural, Vec3::X, Vec3::Y).unwrap();
    let positions: Vec<[f32; 3]> = vertices
        .iter()
        .map(|v| [v.position_u[0], v.position_u[1], v.position_u[2]])
        .collect();
    let data = MeshData {
        bounds: Aabb::from_points(positions.iter().map(|p| Vec3::from(*p))),
        normals: vertices
            .iter()
            .map(|v| [v.normal_v[0], v.normal_v[1], v.normal_v[2]])
            .collect(),
        uvs: Some(
            vertices
                .iter()
                .map(|v| [v.position_u[3], v.normal_v[3]])
                .collect(),
        ),
        tangents: Some(vertices.iter().map(|v| v.tangent).collect()),
        uvs1: None,
        colors: None,
        positions,
        indices,
    };
    let previous: Vec<[f32; 4]> = vertices.iter().map(|v| v.previous_position).collect();
    let expanded = renderer
        .meshes
        .upload_with_previous(&renderer.gpu, &data, &previous)
        .expect("upload");
    for raster in [RasterChoice::Hardware, RasterChoice::Compute] {
        let a = gbuffer(&renderer, procedural.clone(), raster);
        let b = gbuffer(&renderer, expanded.clone(), raster);
        let velocity = &a[2];
        let moving = velocity.pixels.iter().filter(|p| p[0].abs() > 1e-3).count();
        assert!(
            moving > 50,
            "{raster:?}: particles cover and move: {moving}"
        );
        for (name, (x, y)) in ["color", "normals", "velocity+uv", "depth"]
            .iter()
            .zip(a.iter().zip(&b))
        {
            let differ = x
                .pixels
                .iter()
                .zip(&y.pixels)
                .filter(|(p, q)| p.iter().zip(q.iter()).any(|(s, t)| (s - t).abs() > 1e-4))
                .count();
            assert_eq!(differ, 0, "{raster:?} {name}: {differ} pixels differ");
        }
    }
}

#[test]
fn a_system_past_the_expanded_paths_limit_costs_its_records_only() {
    let renderer = test_renderer();
    let limit = renderer.gpu.device.limits().max_storage_buffer_binding_size;
    // The old path expanded every sprite into 4 arena vertices of 64 bytes
    // in one storage binding: this count did not fit.
    let count = u32::try_from(limit / (4 * 64) + 1).expect("a count");
    let (vertices_before, indices_before) = renderer.meshes.buffer_sizes();
    let system = ParticleSystem::new(&renderer, count, 1).expect("room for the records");
    let mesh = draw(&renderer, &system, DrawShape::Sprites, 0.01, true, 100.0).expect("drawn");
    let (vertices_after, indices_after) = renderer.meshes.buffer_sizes();
    let records = u64::from(count + 1) * 64;
    assert_eq!(indices_after, indices_before, "no indices");
    // The arena grew by the records, or doubled where that was more.
    assert!(vertices_after >= records);
    assert!(
        vertices_after <= (vertices_before + records).max(2 * vertices_before),
        "{vertices_after} bytes for {records} bytes of records"
    );
    assert!(u64::from(count) * 4 * 64 > limit, "past the old limit");
    assert_eq!(mesh.vertices.len() as u64, u64::from(count) + 1);
    assert_eq!(u64::from(mesh.index_count()), u64::from(count) * 6);
    assert!(mesh.is_procedural() && mesh.indices.is_empty());
}
