//! Test scenes made in code (the brief: nothing downloaded), shared by the
//! tests and by `spreadlight accuracy`, whose CPU references know the same
//! geometry analytically.

use std::sync::Arc;

use glam::{Mat4, Vec2, Vec3};

use crate::error::RenderError;
use crate::gbuffer::{DrawBatch, InstanceInput, Layer};
use crate::mesh::primitives::{GridParams, SphereParams, grid, sphere};
use crate::renderer::Renderer;

/// Balls (centre, radius) over a square floor of side `floor` at y = 0, in
/// one layer: a unit sphere of `detail` sectors (half as many stacks)
/// scaled per ball, and a two-triangle floor. Grey, material 0.
pub fn balls_on_floor(
    renderer: &Renderer,
    balls: &[(Vec3, f32)],
    floor: f32,
    detail: u32,
) -> Result<Arc<Layer>, RenderError> {
    let ball = renderer.meshes.upload(
        &renderer.gpu,
        &sphere(SphereParams {
            radius: 1.0,
            sectors: detail.max(3),
            stacks: (detail / 2).max(2),
        }),
    )?;
    let ground = renderer.meshes.upload(
        &renderer.gpu,
        &grid(GridParams {
            size: Vec2::splat(floor),
            resolution_x: 1,
            resolution_y: 1,
        }),
    )?;
    let instance = |t: Mat4| InstanceInput {
        transform: t,
        previous_transform: t,
        color: [0.8, 0.8, 0.8, 1.0],
        material_id: 0,
        object_id: 0,
    };
    let balls = balls
        .iter()
        .map(|&(c, r)| instance(Mat4::from_translation(c) * Mat4::from_scale(Vec3::splat(r))))
        .collect();
    let batches = vec![
        DrawBatch {
            mesh: ball,
            instances: balls,
        },
        DrawBatch {
            mesh: ground,
            instances: vec![instance(Mat4::IDENTITY)],
        },
    ];
    Ok(Arc::new(Layer::plain(batches)))
}

/// `layer` from [`balls_on_floor`] with the balls given material `ball` and
/// the floor material `floor` (ids written to the G-buffer).
pub fn with_materials(layer: &Layer, ball: u32, floor: u32) -> Arc<Layer> {
    let mut layer = layer.clone();
    layer.features.ids = true;
    for (batch, id) in layer.batches.iter_mut().zip([ball, floor]) {
        for instance in &mut batch.instances {
            instance.material_id = id;
        }
    }
    Arc::new(layer)
}

/// What an environment probe's tests and its accuracy measure look at: a
/// ball (material 0) and, in a layer of their own so a probe at the ball's
/// centre can be given them without the ball, a red box (material 1) and a
/// grey floor of side `floor` at y = 0 (material 1).
pub struct MirrorBesideBox {
    pub ball: Arc<Layer>,
    pub surroundings: Arc<Layer>,
}

/// The albedo of [`MirrorBesideBox`]'s box: red.
pub const RED_BOX: [f32; 4] = [0.9, 0.05, 0.05, 1.0];

/// A ball of `radius` at `ball`, a box of side `box_size` standing on the
/// floor at `red_box` (x, z), and the floor.
pub fn mirror_beside_box(
    renderer: &Renderer,
    (ball, radius): (Vec3, f32),
    red_box: Vec2,
    box_size: f32,
    floor: f32,
) -> Result<MirrorBesideBox, RenderError> {
    let upload = |m| renderer.meshes.upload(&renderer.gpu, &m);
    let ball_mesh = upload(sphere(SphereParams {
        radius: 1.0,
        sectors: 32,
        stacks: 16,
    }))?;
    let box_mesh = upload(crate::mesh::primitives::box_mesh(Default::default()))?;
    let ground = upload(grid(GridParams {
        size: Vec2::splat(floor),
        resolution_x: 1,
        resolution_y: 1,
    }))?;
    let instance = |t: Mat4, color: [f32; 4], material_id: u32| InstanceInput {
        transform: t,
        previous_transform: t,
        color,
        material_id,
        object_id: material_id,
    };
    let layer = |batches: Vec<DrawBatch>| {
        let mut layer = Layer::plain(batches);
        layer.features.ids = true;
        Arc::new(layer)
    };
    let ball = layer(vec![DrawBatch {
        mesh: ball_mesh,
        instances: vec![instance(
            Mat4::from_translation(ball) * Mat4::from_scale(Vec3::splat(radius)),
            [0.9, 0.9, 0.9, 1.0],
            0,
        )],
    }]);
    // A hair above the floor: its bottom and the floor would fight for depth.
    let box_transform =
        Mat4::from_translation(Vec3::new(red_box.x, box_size * 0.5 + 0.002, red_box.y))
            * Mat4::from_scale(Vec3::splat(box_size));
    let surroundings = layer(vec![
        DrawBatch {
            mesh: box_mesh,
            instances: vec![instance(box_transform, RED_BOX, 1)],
        },
        DrawBatch {
            mesh: ground,
            instances: vec![instance(Mat4::IDENTITY, [0.5, 0.5, 0.5, 1.0], 1)],
        },
    ]);
    Ok(MirrorBesideBox { ball, surroundings })
}
