//! Per-draw back-face culling: a double-sided material keeps the back faces
//! of its own draw only. Two quads turned away from the camera in one
//! layer, one of a double-sided material and one of a one-sided material:
//! the first shows (its back face), the second is culled, on both
//! rasterizers.

use std::sync::Arc;

use glam::{Mat4, Vec3};
use spreadlight_render::camera::CameraInput;
use spreadlight_render::gbuffer::{
    DrawBatch, GBuffer, InstanceInput, Layer, LayerFeatures, RasterChoice, RasterMode,
};
use spreadlight_render::material::maps::SurfaceMaps;
use spreadlight_render::material::{Material, MaterialWorld};
use spreadlight_render::mesh::MeshData;
use spreadlight_render::readback::render_and_read;
use spreadlight_render::renderer::test_renderer;
use spreadlight_render::{Renderer, SizeRule};

const SIZE: (u32, u32) = (64, 32);

/// A unit quad facing +Z.
fn quad() -> MeshData {
    MeshData::new(
        vec![
            [-1.0, -1.0, 0.0],
            [1.0, -1.0, 0.0],
            [1.0, 1.0, 0.0],
            [-1.0, 1.0, 0.0],
        ],
        vec![[0.0, 0.0, 1.0]; 4],
        None,
        None,
        vec![0, 1, 2, 0, 2, 3],
    )
    .expect("a quad")
}

fn material(double_sided: bool) -> Material {
    let mut m = Material::default_material();
    m.set_maps(Some(Arc::new(SurfaceMaps {
        double_sided,
        ..Default::default()
    })));
    m
}

/// Left (x = -1.2) a double-sided quad, right (x = +1.2) a one-sided one,
/// both turned half around (their backs to the camera), each its own mesh
/// and so its own draw.
fn layer(renderer: &Renderer) -> Arc<Layer> {
    let world = MaterialWorld::new(renderer, vec![material(true), material(false)]);
    let batches = [(-1.2f32, 0u32), (1.2, 1)]
        .into_iter()
        .map(|(x, material_id)| {
            let transform =
                Mat4::from_translation(Vec3::X * x) * Mat4::from_rotation_y(std::f32::consts::PI);
            DrawBatch {
                mesh: renderer
                    .meshes
                    .upload(&renderer.gpu, &quad())
                    .expect("upload"),
                instances: vec![InstanceInput {
                    transform,
                    previous_transform: transform,
                    color: [1.0; 4],
                    material_id,
                    object_id: 1,
                }],
            }
        })
        .collect();
    Arc::new(
        Layer::new(Some(1), batches, LayerFeatures::default(), None)
            .expect("layer")
            .with_materials(Some(world)),
    )
}

fn check(choice: RasterChoice, expected: RasterMode) {
    let renderer = test_renderer();
    let camera = CameraInput {
        view: glam::camera::rh::view::look_at_mat4(Vec3::Z * 4.0, Vec3::ZERO, Vec3::Y),
        projection: glam::camera::rh::proj::directx::perspective(0.9, 2.0, 0.1, 100.0),
    };
    let g = GBuffer::with_raster(
        &renderer,
        Some(2),
        vec![layer(&renderer)],
        camera,
        None,
        SizeRule::Relative(1.0),
        choice,
    );
    assert_eq!(g.raster, expected);
    assert_eq!(g.two_sided_draws(), 1, "only the double-sided draw");
    let (report, images) =
        render_and_read(&renderer, g.as_ref(), SIZE, &[&g.targets.depth]).expect("renders");
    assert!(report.errors.is_empty(), "{:?}", report.errors);
    let covered = |x0: u32, x1: u32| {
        (0..SIZE.1)
            .flat_map(|y| (x0..x1).map(move |x| (x, y)))
            .filter(|&(x, y)| images[0].pixels[(y * SIZE.0 + x) as usize][0] > 0.0)
            .count()
    };
    let half = SIZE.0 / 2;
    assert!(
        covered(0, half) > 200,
        "the double-sided quad's back shows: {}",
        covered(0, half)
    );
    assert_eq!(
        covered(half, SIZE.0),
        0,
        "the one-sided quad's back is culled"
    );
}

#[test]
fn a_double_sided_material_keeps_only_its_own_back_faces_compute_raster() {
    check(RasterChoice::Compute, RasterMode::Compute);
}

#[test]
fn a_double_sided_material_keeps_only_its_own_back_faces_hardware_raster() {
    check(RasterChoice::Hardware, RasterMode::Hardware);
}
