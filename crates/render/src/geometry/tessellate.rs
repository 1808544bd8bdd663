//! Tessellate: area-adaptive, crack-free subdivision
//! (shaders/geometry/tessellate.wgsl). Triangles larger than Max Area are
//! split into grids fine enough that no output triangle exceeds it; every
//! edge is cut by a rule of its two end positions alone, so neighbours agree
//! and a closed mesh stays closed (across UV seams too).
//!
//! The output's size depends on the input's triangles, so the pass runs in
//! three dispatches: each triangle's level and a scan of the counts within
//! its workgroup, a scan of the workgroups' totals, then the write. Between
//! them the CPU reads back one number, the output's size, to reserve the
//! mesh in the arena; the mesh itself never leaves the GPU.

use std::sync::Arc;

use bytemuck::{Pod, Zeroable};

use super::{GpuJob, Op, dispatch_steps, read_storage, run, uniform};
use crate::error::RenderError;
use crate::mesh_arena::{GpuMesh, MeshLayout};
use crate::renderer::Renderer;
use crate::shaders::Permutation;

/// The most segments an edge (a triangle becomes at most this squared).
pub const MAX_LEVEL: u32 = 64;

pub use super::tessellate_key::TessellateKey;

/// Matches `Params` in the shader.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct Gpu {
    max_area: f32,
    segment: f32,
    max_level: u32,
    blocks: u32,
}

/// The longest edge segment for `max_area`: a triangle with all edges this
/// short has at most `max_area` (half its square: a right isosceles one).
pub fn segment_length(max_area: f32) -> f32 {
    (2.0 * max_area).sqrt()
}

/// `input` with every triangle over `max_area` split (edges at most
/// [`segment_length`], triangles at most `max_area`, unless `max_level`
/// segments an edge stop it first). Zero-area triangles fill the grids where
/// a finer triangle meets a coarser edge; they draw nothing.
pub fn tessellate(
    renderer: &Renderer,
    input: &GpuMesh,
    previous: Option<&GpuMesh>,
    max_area: f32,
    max_level: u32,
) -> Result<Arc<GpuMesh>, RenderError> {
    let bad = |message: String| RenderError::Pass {
        pass: "Tessellate".to_owned(),
        message,
    };
    if !(max_area.is_finite() && max_area > 0.0) {
        return Err(bad(format!(
            "Max Area must be a positive number, got {max_area}"
        )));
    }
    let max_level = max_level.clamp(1, MAX_LEVEL);
    let faces = (input.indices.len() / 3) as u32;
    // The scan counts in u32: refuse what could overflow it.
    let worst = u64::from(faces) * u64::from((max_level + 1) * (max_level + 2) / 2);
    if worst > u64::from(u32::MAX / 4) {
        return Err(bad(format!(
            "{faces} triangles at up to level {max_level} could exceed one mesh; lower Max Level"
        )));
    }
    let layout = MeshLayout {
        // Flat: every point stays in its triangle.
        bounds: input.bounds,
        has_uvs: input.has_uvs,
        has_tangents: true,
    };
    let blocks = faces.div_ceil(64).max(1);
    let params = Gpu {
        max_area,
        segment: segment_length(max_area),
        max_level,
        blocks,
    };
    let device = &renderer.gpu.device;
    let storage = |label, size: u64| {
        device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size: size.max(16),
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        })
    };
    let levels = storage("tessellate levels", u64::from(faces) * 4);
    let offsets = storage("tessellate offsets", u64::from(faces) * 8);
    let totals = storage("tessellate totals", u64::from(blocks + 1) * 8);
    let job = GpuJob {
        src_vertex: input.vertices.start,
        src_index: input.indices.start,
        src_vertex_count: input.vertices.len() as u32,
        src_index_count: faces * 3,
        ..GpuJob::zeroed()
    };
    let job = uniform(renderer, "tessellate job", bytemuck::bytes_of(&job));
    let params_buffer = uniform(renderer, "tessellate params", bytemuck::bytes_of(&params));
    dispatch_steps(
        renderer,
        &[
            (TessellateKey::Count.key(), faces),
            (TessellateKey::Sums.key(), 64),
        ],
        &[
            ("job", &job),
            ("params", &params_buffer),
            ("levels", &levels),
            ("offsets", &offsets),
            ("blocks", &totals),
        ],
    )?;
    let total = read_storage(renderer, &totals, u64::from(blocks) * 8, 8)?;
    let [vertex_count, triangle_count]: [u32; 2] = bytemuck::pod_read_unaligned(&total[..8]);
    let index_count = triangle_count
        .checked_mul(3)
        .ok_or_else(|| bad(format!("{triangle_count} triangles are too many")))?;
    run(
        renderer,
        Op {
            key: TessellateKey::Write.key(),
            input: Some(input),
            previous,
            vertex_count,
            index_count,
            threads: faces,
            params: bytemuck::bytes_of(&params),
            extra: vec![
                ("levels", levels.as_entire_binding()),
                ("offsets", offsets.as_entire_binding()),
                ("blocks", totals.as_entire_binding()),
            ],
            layout,
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
            crate::geometry::tessellate_key::TessellateKey,
            [],
            "Params",
            [max_area, segment, max_level, blocks]
        );
    }
}
