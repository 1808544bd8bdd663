//! Extrude: every face raised into a prism along its normal
//! (shaders/geometry/extrude.wgsl), the amount per face from a spread.

use std::sync::Arc;

use glam::Vec3;
use wgpu::util::DeviceExt;

use super::displace::height_sampler;
use super::{Op, run};
use crate::error::RenderError;
use crate::mesh::Aabb;
use crate::mesh_arena::{GpuMesh, MeshLayout};
use crate::renderer::Renderer;
use crate::shaders::Permutation;
use crate::texture::GpuTexture;

pub use super::extrude_key::ExtrudeKey;

/// Vertices and triangles an input triangle becomes.
pub const VERTICES_PER_FACE: u32 = 15;
pub const TRIANGLES_PER_FACE: u32 = 7;

/// `input` with each face `amounts[face % len]` out along its normal (non-finite amounts: 0),
/// times `texture`'s red channel at the face's centroid UV when there is one.
pub fn extrude(
    renderer: &Renderer,
    input: &GpuMesh,
    previous: Option<&GpuMesh>,
    amounts: &[f32],
    texture: Option<&GpuTexture>,
) -> Result<Arc<GpuMesh>, RenderError> {
    let faces = (input.indices.len() / 3) as u32;
    let too_big = || RenderError::Pass {
        pass: "Extrude".to_owned(),
        message: format!("{faces} faces are too many to extrude into one mesh"),
    };
    let vertex_count = faces.checked_mul(VERTICES_PER_FACE).ok_or_else(too_big)?;
    let index_count = faces
        .checked_mul(TRIANGLES_PER_FACE * 3)
        .ok_or_else(too_big)?;
    let amounts: Vec<f32> = if amounts.is_empty() {
        vec![0.0]
    } else {
        amounts
            .iter()
            .map(|a| if a.is_finite() { *a } else { 0.0 })
            .collect()
    };
    // A normalized texture scales the amounts by 0..1.
    let reach = amounts.iter().fold(0.0f32, |m, a| m.max(a.abs()));
    let buffer = renderer
        .gpu
        .device
        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("extrude amounts"),
            contents: bytemuck::cast_slice(&amounts),
            usage: wgpu::BufferUsages::STORAGE,
        });
    let sampler = texture.map(|_| height_sampler(renderer));
    let mut extra = vec![("amounts", buffer.as_entire_binding())];
    if let (Some(t), Some(s)) = (texture, &sampler) {
        extra.push(("height", wgpu::BindingResource::TextureView(&t.view)));
        extra.push(("height_sampler", wgpu::BindingResource::Sampler(s)));
    }
    run(
        renderer,
        Op {
            key: ExtrudeKey {
                texture: texture.is_some(),
            }
            .key(),
            input: Some(input),
            previous,
            vertex_count,
            index_count,
            threads: vertex_count.max(index_count),
            params: &[],
            extra,
            // Every point moves at most the largest amount.
            layout: MeshLayout {
                bounds: Aabb {
                    min: input.bounds.min - Vec3::splat(reach),
                    max: input.bounds.max + Vec3::splat(reach),
                },
                has_uvs: input.has_uvs,
                has_tangents: true,
            },
        },
    )
}
