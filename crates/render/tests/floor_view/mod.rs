//! A camera over a 20x20 floor at y = 0, and per pixel the floor point it
//! sees: tests that shade the floor compare each pixel with the CPU
//! reference at that point (`surface_lighting.rs`, `light_loop_reference.rs`).
// Each test file uses a part of it.
#![allow(dead_code)]

use std::sync::Arc;

use glam::{Vec3, Vec4Swizzles};
use spreadlight_render::Renderer;
use spreadlight_render::camera::CameraInput;
use spreadlight_render::mesh::primitives::{GridParams, grid};
use spreadlight_render::mesh_arena::GpuMesh;

pub const SIZE: (u32, u32) = (96, 54);
pub const EYE: Vec3 = Vec3::new(0.0, 4.0, 6.0);

pub fn camera() -> CameraInput {
    CameraInput {
        view: glam::camera::rh::view::look_at_mat4(EYE, Vec3::ZERO, Vec3::Y),
        projection: glam::camera::rh::proj::directx::perspective(
            1.0,
            SIZE.0 as f32 / SIZE.1 as f32,
            0.1,
            100.0,
        ),
    }
}

/// Per pixel, the floor point the pixel sees and the unit vector to the eye
/// (None where it sees past the floor's edge).
pub fn floor_points() -> Vec<Option<(Vec3, Vec3)>> {
    let c = camera();
    let inverse = (c.projection * c.view).inverse();
    (0..SIZE.1)
        .flat_map(|y| (0..SIZE.0).map(move |x| (x, y)))
        .map(|(x, y)| {
            let ndc_x = (x as f32 + 0.5) / SIZE.0 as f32 * 2.0 - 1.0;
            let ndc_y = 1.0 - (y as f32 + 0.5) / SIZE.1 as f32 * 2.0;
            let h = inverse * glam::Vec4::new(ndc_x, ndc_y, 0.5, 1.0);
            let ray = (h.xyz() / h.w - EYE).normalize();
            if ray.y >= -1e-3 {
                return None;
            }
            let p = EYE + ray * (-EYE.y / ray.y);
            (p.x.abs() < 9.5 && p.z.abs() < 9.5).then_some((p, -ray))
        })
        .collect()
}

/// The 20x20 floor, one quad, uploaded.
pub fn floor_mesh(renderer: &Renderer) -> Arc<GpuMesh> {
    renderer
        .meshes
        .upload(
            &renderer.gpu,
            &grid(GridParams {
                size: glam::Vec2::splat(20.0),
                resolution_x: 1,
                resolution_y: 1,
            }),
        )
        .expect("upload")
}
