//! What the reflection and SSR tests share: a ball (material 0) over a
//! floor (material 1) at 64x48, the camera that sees it, a reflective
//! material, and the world position under a pixel.
#![allow(dead_code)]

use std::sync::Arc;

use glam::{Vec3, Vec4};
use spreadlight_render::SizeRule;
use spreadlight_render::camera::{CameraInput, reverse_z};
use spreadlight_render::gbuffer::GBuffer;
use spreadlight_render::material::{Feature, Material};
use spreadlight_render::renderer::Renderer;
use spreadlight_render::scenes::{balls_on_floor, with_materials};

pub const SIZE: (u32, u32) = (64, 48);
pub const EYE: Vec3 = Vec3::new(0.0, 1.5, 4.0);

pub fn camera(eye: Vec3, target: Vec3) -> CameraInput {
    CameraInput {
        view: glam::camera::rh::view::look_at_mat4(eye, target, Vec3::Y),
        projection: glam::camera::rh::proj::directx::perspective(
            1.0,
            SIZE.0 as f32 / SIZE.1 as f32,
            0.1,
            100.0,
        ),
    }
}

/// A ball (material 0) over a floor (material 1) seen from `eye`.
pub fn gbuffer_from(renderer: &Renderer, eye: Vec3, target: Vec3) -> Arc<GBuffer> {
    let layer =
        balls_on_floor(renderer, &[(Vec3::new(0.0, 0.6, 0.0), 0.6)], 8.0, 32).expect("upload");
    GBuffer::new(
        renderer,
        None,
        vec![with_materials(&layer, 0, 1)],
        camera(eye, target),
        None,
        SizeRule::Relative(1.0),
    )
}

pub fn gbuffer(renderer: &Renderer) -> Arc<GBuffer> {
    gbuffer_from(renderer, EYE, Vec3::new(0.0, 0.3, 0.0))
}

pub fn reflective(roughness: f32, metallic: f32) -> Material {
    Material::new()
        .with(Feature::CookTorrance, &[[roughness, metallic, 0.04, 0.0]])
        .and_then(|m| m.with(Feature::Reflection, &[[1.0, 0.0, 0.0, 0.0]]))
        .expect("valid")
}

/// The world position of pixel (x, y) at reversed-Z depth `d`.
pub fn world_position(g: &GBuffer, x: u32, y: u32, d: f32) -> Vec3 {
    let inverse = (reverse_z(g.camera.projection) * g.camera.view).inverse();
    let ndc = Vec4::new(
        (x as f32 + 0.5) / SIZE.0 as f32 * 2.0 - 1.0,
        1.0 - (y as f32 + 0.5) / SIZE.1 as f32 * 2.0,
        d,
        1.0,
    );
    let h = inverse * ndc;
    h.truncate() / h.w
}
