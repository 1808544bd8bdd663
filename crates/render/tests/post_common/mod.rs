//! What the post tests share: a scene of balls against the sky (depth 0,
//! infinitely far), moving or not, seen through a chosen camera; images
//! made from a function; rendering one named texture.
#![allow(dead_code)]

use std::sync::Arc;

use glam::{Mat4, Vec3};
use spreadlight_render::camera::CameraInput;
use spreadlight_render::frame_graph::FrameReport;
use spreadlight_render::gbuffer::{DrawBatch, GBuffer, InstanceInput, Layer};
use spreadlight_render::mesh::primitives::{SphereParams, sphere};
use spreadlight_render::readback::{ImageF32, render_and_read};
use spreadlight_render::recipe::Recipe;
use spreadlight_render::static_texture::StaticTexture;
use spreadlight_render::{Renderer, SizeRule};

/// A ball: centre now, centre last frame, radius.
#[derive(Clone, Copy, Debug)]
pub struct Ball {
    pub center: Vec3,
    pub previous: Vec3,
    pub radius: f32,
}

impl Ball {
    pub fn still(center: Vec3, radius: f32) -> Self {
        Ball {
            center,
            previous: center,
            radius,
        }
    }
}

pub fn look(eye: Vec3, target: Vec3, fov: f32, aspect: f32) -> CameraInput {
    CameraInput {
        view: glam::camera::rh::view::look_at_mat4(eye, target, Vec3::Y),
        projection: glam::camera::rh::proj::directx::perspective(fov, aspect, 0.1, 100.0),
    }
}

pub fn balls(renderer: &Renderer, balls: &[Ball]) -> Arc<Layer> {
    let mesh = renderer
        .meshes
        .upload(
            &renderer.gpu,
            &sphere(SphereParams {
                radius: 1.0,
                sectors: 32,
                stacks: 16,
            }),
        )
        .expect("upload");
    let at = |c: Vec3, r: f32| Mat4::from_translation(c) * Mat4::from_scale(Vec3::splat(r));
    let instances = balls
        .iter()
        .map(|b| InstanceInput {
            transform: at(b.center, b.radius),
            previous_transform: at(b.previous, b.radius),
            color: [0.8, 0.8, 0.8, 1.0],
            material_id: 0,
            object_id: 0,
        })
        .collect();
    Arc::new(Layer::plain(vec![DrawBatch { mesh, instances }]))
}

pub fn gbuffer(
    renderer: &Renderer,
    layer: Arc<Layer>,
    camera: CameraInput,
    previous: Option<Mat4>,
) -> Arc<GBuffer> {
    GBuffer::new(
        renderer,
        None,
        vec![layer],
        camera,
        previous,
        SizeRule::Relative(1.0),
    )
}

pub fn image(
    renderer: &Renderer,
    (w, h): (u32, u32),
    f: impl Fn(u32, u32) -> [f32; 4],
) -> Arc<StaticTexture> {
    let pixels: Vec<[f32; 4]> = (0..w * h).map(|i| f(i % w, i / w)).collect();
    StaticTexture::from_rgba32f(&renderer.gpu, w, h, &pixels, "test image")
}

/// Render `name` from `recipe`; no pass may fail and every pixel must be finite.
pub fn render(
    renderer: &Renderer,
    recipe: &dyn Recipe,
    name: &str,
    size: (u32, u32),
) -> (FrameReport, ImageF32) {
    let (report, images) = render_and_read(renderer, recipe, size, &[name]).expect("renders");
    assert!(report.errors.is_empty(), "{:?}", report.errors);
    let image = images.into_iter().next().expect("one image");
    assert!(
        image.all_finite(),
        "{name}: a NaN or infinity reached the target"
    );
    (report, image)
}

/// The largest and smallest channel value of an image.
pub fn range(image: &ImageF32) -> (f32, f32) {
    image
        .pixels
        .iter()
        .flat_map(|p| p.iter().copied())
        .fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        })
}

/// A checkerboard of 1-pixel cells: all high frequency, what any blur flattens.
pub fn checker(x: u32, y: u32, a: [f32; 4], b: [f32; 4]) -> [f32; 4] {
    if (x + y).is_multiple_of(2) { a } else { b }
}

/// How many of the frame's passes are of a step that begins with `what`
/// ("down" counts glare's "down 1", "down 2", ...).
pub fn passes_named(report: &FrameReport, what: &str) -> usize {
    report
        .passes
        .iter()
        .filter(|p| p.step.as_deref().is_some_and(|s| s.starts_with(what)))
        .count()
}
