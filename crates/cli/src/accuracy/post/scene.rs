//! The scene every post effect is measured over, and its G-buffer: coloured
//! balls on a floor, the middle one optionally moving. Shared by the effects'
//! measurements and their references, so both render exactly the same thing.

use std::sync::Arc;

use glam::{Mat4, Vec2, Vec3};
use spreadlight_render::camera::CameraInput;
use spreadlight_render::gbuffer::{DrawBatch, GBuffer, InstanceInput, Layer, LayerFeatures};
use spreadlight_render::mesh::primitives::{GridParams, SphereParams, grid, sphere};
use spreadlight_render::{Renderer, SizeRule, TextureRef};

/// The moving ball's motion per frame (world units).
const MOTION: Vec3 = Vec3::new(0.25, 0.0, 0.0);

/// Coloured balls on a floor, `at` frames on; with `moving_ball` the middle one
/// moves by `MOTION` a frame (its last frame's transform says so).
pub(super) fn scene(renderer: &Renderer, at: f32, moving_ball: bool) -> anyhow::Result<Arc<Layer>> {
    let ball = renderer.meshes.upload(
        &renderer.gpu,
        &sphere(SphereParams {
            radius: 1.0,
            sectors: 48,
            stacks: 24,
        }),
    )?;
    let floor = renderer.meshes.upload(
        &renderer.gpu,
        &grid(GridParams {
            size: Vec2::splat(30.0),
            resolution_x: 1,
            resolution_y: 1,
        }),
    )?;
    let place = |c: Vec3, r: f32| Mat4::from_translation(c) * Mat4::from_scale(Vec3::splat(r));
    let instance = |t: Mat4, previous: Mat4, color: [f32; 4]| InstanceInput {
        transform: t,
        previous_transform: previous,
        color,
        material_id: 0,
        object_id: 0,
    };
    let moving = Vec3::new(0.0, 0.8, 0.0) + MOTION * at;
    let motion = if moving_ball { MOTION } else { Vec3::ZERO };
    let balls = vec![
        instance(
            place(Vec3::new(-1.8, 0.6, 2.5), 0.6),
            place(Vec3::new(-1.8, 0.6, 2.5), 0.6),
            [0.9, 0.2, 0.1, 1.0],
        ),
        instance(
            place(moving, 0.8),
            place(moving - motion, 0.8),
            [0.1, 0.7, 0.2, 1.0],
        ),
        instance(
            place(Vec3::new(2.2, 1.2, -6.0), 1.2),
            place(Vec3::new(2.2, 1.2, -6.0), 1.2),
            [0.2, 0.3, 0.9, 1.0],
        ),
        instance(
            place(Vec3::new(0.9, 0.3, 1.0), 0.3),
            place(Vec3::new(0.9, 0.3, 1.0), 0.3),
            [1.0, 0.9, 0.3, 1.0],
        ),
    ];
    let batches = vec![
        DrawBatch {
            mesh: ball,
            instances: balls,
        },
        DrawBatch {
            mesh: floor,
            instances: vec![instance(
                Mat4::IDENTITY,
                Mat4::IDENTITY,
                [0.5, 0.5, 0.5, 1.0],
            )],
        },
    ];
    Ok(Arc::new(Layer::new(
        None,
        batches,
        LayerFeatures::default(),
        None,
    )?))
}

pub(super) fn camera(size: (u32, u32)) -> CameraInput {
    super::super::camera_looking(Vec3::new(0.0, 2.0, 6.8), Vec3::new(0.0, 0.8, 0.0), size)
}

pub(super) fn gbuffer(
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

pub(super) fn albedo(g: &Arc<GBuffer>) -> TextureRef {
    TextureRef {
        recipe: g.clone(),
        name: g.targets.color.clone(),
    }
}
