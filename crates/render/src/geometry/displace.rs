//! Displace: every vertex moved along its normal by a height texture at its
//! UV, normals recomputed from the moved surface
//! (shaders/geometry/displace.wgsl): a move pass, then each triangle adds
//! its angle-weighted normal to its vertices, then each vertex normalizes.

use std::sync::Arc;

use bytemuck::{Pod, Zeroable};
use glam::Vec3;

use super::{GpuJob, Op, dispatch_steps, run, uniform};
use crate::error::RenderError;
use crate::mesh::Aabb;
use crate::mesh_arena::{GpuMesh, MeshLayout};
use crate::renderer::Renderer;
use crate::shaders::Permutation;
use crate::texture::GpuTexture;

pub use super::displace_key::DisplaceKey;

/// How far along the normal: `(height - midlevel) x amount`, height the
/// texture's red channel at the vertex's UV (sampled linearly, repeating).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DisplaceParams {
    pub amount: f32,
    pub midlevel: f32,
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct Gpu {
    amount: f32,
    midlevel: f32,
    _pad: [f32; 2],
}

/// A linear, repeating sampler: heights and extrusion amounts read from a
/// texture tile like the material maps they often are.
pub(crate) fn height_sampler(renderer: &Renderer) -> wgpu::Sampler {
    renderer
        .gpu
        .device
        .create_sampler(&wgpu::SamplerDescriptor {
            label: Some("geometry height sampler"),
            address_mode_u: wgpu::AddressMode::Repeat,
            address_mode_v: wgpu::AddressMode::Repeat,
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            ..Default::default()
        })
}

/// `input` displaced by `height` (a texture that exists before the frame).
pub fn displace(
    renderer: &Renderer,
    input: &GpuMesh,
    previous: Option<&GpuMesh>,
    height: &GpuTexture,
    params: DisplaceParams,
) -> Result<Arc<GpuMesh>, RenderError> {
    if !(params.amount.is_finite() && params.midlevel.is_finite()) {
        return Err(RenderError::Pass {
            pass: "Displace".to_owned(),
            message: "Amount and Midlevel must be finite numbers".to_owned(),
        });
    }
    let (vertex_count, index_count) = (input.vertices.len() as u32, input.indices.len() as u32);
    // Heights of a normalized texture lie in 0..1.
    let reach = params.amount.abs() * params.midlevel.abs().max((1.0 - params.midlevel).abs());
    let gpu = Gpu {
        amount: params.amount,
        midlevel: params.midlevel,
        _pad: [0.0; 2],
    };
    let sampler = height_sampler(renderer);
    let output = run(
        renderer,
        Op {
            key: DisplaceKey::Move.key(),
            input: Some(input),
            previous,
            vertex_count,
            index_count,
            threads: vertex_count.max(index_count),
            params: bytemuck::bytes_of(&gpu),
            extra: vec![
                ("height", wgpu::BindingResource::TextureView(&height.view)),
                ("height_sampler", wgpu::BindingResource::Sampler(&sampler)),
            ],
            layout: MeshLayout {
                bounds: Aabb {
                    min: input.bounds.min - Vec3::splat(reach),
                    max: input.bounds.max + Vec3::splat(reach),
                },
                has_uvs: input.has_uvs,
                has_tangents: input.has_tangents,
            },
        },
    )?;
    let sums = renderer.gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("displace normal sums"),
        size: (u64::from(vertex_count) * 12).max(16),
        usage: wgpu::BufferUsages::STORAGE,
        mapped_at_creation: false,
    });
    // The two normal passes work on the output in place.
    let job = GpuJob {
        dst_vertex: output.vertices.start,
        dst_index: output.indices.start,
        vertex_count,
        index_count,
        ..GpuJob::zeroed()
    };
    let job = uniform(renderer, "displace job", bytemuck::bytes_of(&job));
    let params = uniform(renderer, "displace params", bytemuck::bytes_of(&gpu));
    dispatch_steps(
        renderer,
        &[
            (DisplaceKey::Accumulate.key(), index_count / 3),
            (DisplaceKey::Normals.key(), vertex_count),
        ],
        &[("job", &job), ("params", &params), ("normal_sums", &sums)],
    )?;
    Ok(output)
}

/// The layout the shader sees (shaders/layout.rs).
#[cfg(test)]
mod wgsl_layout {
    use super::*;

    #[test]
    fn gpu_matches_params_in_the_shader() {
        crate::assert_wgsl_layout!(
            Gpu,
            crate::geometry::displace_key::DisplaceKey,
            [],
            "Params",
            [amount, midlevel, _pad]
        );
    }
}
