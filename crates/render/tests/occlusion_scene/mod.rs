//! What the occlusion tests and the blur tests share: a ball on a floor,
//! the camera that sees it, and constant textures to light it with.
#![allow(dead_code)]

use std::sync::Arc;

use glam::{Mat4, Vec3};
use spreadlight_render::camera::CameraInput;
use spreadlight_render::gbuffer::GBuffer;
use spreadlight_render::scenes::balls_on_floor;
use spreadlight_render::static_texture::StaticTexture;
use spreadlight_render::{Renderer, SizeRule};

pub const BALL: (Vec3, f32) = (Vec3::new(0.0, 1.0, 0.0), 1.0);
pub const FLOOR: f32 = 12.0;

pub fn camera(eye: Vec3, aspect: f32) -> CameraInput {
    CameraInput {
        view: glam::camera::rh::view::look_at_mat4(eye, Vec3::new(0.0, 0.6, 0.0), Vec3::Y),
        projection: glam::camera::rh::proj::directx::perspective(0.9, aspect, 0.1, 100.0),
    }
}

pub fn eye() -> Vec3 {
    Vec3::new(0.0, 2.5, 5.0)
}

pub fn gbuffer(
    renderer: &Renderer,
    eye: Vec3,
    previous: Option<Mat4>,
    size: (u32, u32),
) -> Arc<GBuffer> {
    let layer = balls_on_floor(renderer, &[BALL], FLOOR, 48).expect("upload");
    GBuffer::new(
        renderer,
        None,
        vec![layer],
        camera(eye, size.0 as f32 / size.1 as f32),
        previous,
        SizeRule::Relative(1.0),
    )
}

/// A texture of `pixels` (RGBA, row by row) at `size`.
pub fn image(
    renderer: &Renderer,
    pixels: &[[f32; 4]],
    size: (u32, u32),
    name: &str,
) -> Arc<StaticTexture> {
    StaticTexture::from_rgba32f(&renderer.gpu, size.0, size.1, pixels, name)
}

/// A texture of one colour at `size`.
pub fn constant(
    renderer: &Renderer,
    rgb: [f32; 3],
    size: (u32, u32),
    name: &str,
) -> Arc<StaticTexture> {
    let pixel = [rgb[0], rgb[1], rgb[2], 1.0];
    image(
        renderer,
        &vec![pixel; (size.0 * size.1) as usize],
        size,
        name,
    )
}
