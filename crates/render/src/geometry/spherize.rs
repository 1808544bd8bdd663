//! Spherize: blend a mesh towards a sphere (shaders/geometry/spherize.wgsl).

use std::sync::Arc;

use bytemuck::{Pod, Zeroable};
use glam::Vec3;

use super::{Op, run};
use crate::error::RenderError;
use crate::mesh::Aabb;
use crate::mesh_arena::{GpuMesh, MeshLayout};
use crate::renderer::Renderer;
use crate::shaders::Permutation;

pub use super::spherize_key::SpherizeKey;

/// Where the sphere is and how far to go towards it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpherizeParams {
    pub center: Vec3,
    pub radius: f32,
    /// 0: the mesh as it is; 1: every vertex on the sphere. Clamped to 0..1.
    pub amount: f32,
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct Gpu {
    center: [f32; 3],
    radius: f32,
    amount: f32,
    _pad: [f32; 3],
}

/// `input` spherized into a new mesh; `previous` is last frame's output (for velocity).
pub fn spherize(
    renderer: &Renderer,
    input: &GpuMesh,
    previous: Option<&GpuMesh>,
    params: SpherizeParams,
) -> Result<Arc<GpuMesh>, RenderError> {
    let finite =
        params.center.is_finite() && params.radius.is_finite() && params.amount.is_finite();
    if !finite {
        return Err(RenderError::Pass {
            pass: "Spherize".to_owned(),
            message: "center, radius and amount must be finite numbers".to_owned(),
        });
    }
    let sphere = Aabb {
        min: params.center - Vec3::splat(params.radius.abs()),
        max: params.center + Vec3::splat(params.radius.abs()),
    };
    let gpu = Gpu {
        center: params.center.into(),
        radius: params.radius,
        amount: params.amount,
        _pad: [0.0; 3],
    };
    let (vertices, indices) = (input.vertices.len() as u32, input.indices.len() as u32);
    run(
        renderer,
        Op {
            key: SpherizeKey.key(),
            input: Some(input),
            previous,
            vertex_count: vertices,
            index_count: indices,
            threads: vertices.max(indices),
            params: bytemuck::bytes_of(&gpu),
            extra: Vec::new(),
            // Every point lies between the input's and the sphere's: their union bounds it.
            layout: MeshLayout {
                bounds: input.bounds.union(sphere),
                has_uvs: input.has_uvs,
                has_tangents: input.has_tangents,
            },
        },
    )
}

/// The layout the shader sees (shaders/layout.rs).
#[cfg(test)]
mod wgsl_layout {
    use super::*;

    #[test]
    fn gpu_matches_params_in_the_shader() {
        crate::assert_wgsl_layout!(
            Gpu,
            crate::geometry::spherize_key::SpherizeKey,
            [],
            "Params",
            [center, radius, amount, _pad]
        );
    }
}
