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
