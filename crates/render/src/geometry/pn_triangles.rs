//! PN Triangles and plain subdivision (shaders/geometry/pn_triangles.wgsl):
//! every triangle becomes level² triangles, on the curved point-normal patch
//! of its corners or (flat) in its plane.

use std::sync::Arc;

use glam::Vec3;

use super::{Op, run};
use crate::error::RenderError;
use crate::mesh::Aabb;
use crate::mesh_arena::{GpuMesh, MeshLayout};
use crate::renderer::Renderer;
use crate::shaders::Permutation;

pub use super::pn_triangles_key::PnTrianglesKey;

/// The most segments an edge (level² triangles a face).
pub const MAX_LEVEL: u32 = 64;

/// `input` with every triangle split `level` times an edge; `curved`: on its PN patch.
pub fn pn_triangles(
    renderer: &Renderer,
    input: &GpuMesh,
    previous: Option<&GpuMesh>,
    level: u32,
    curved: bool,
) -> Result<Arc<GpuMesh>, RenderError> {
    let n = level.clamp(1, MAX_LEVEL);
    let faces = (input.indices.len() / 3) as u32;
    let too_big = || RenderError::Pass {
        pass: "PN Triangles".to_owned(),
        message: format!("{faces} faces at level {n} are too many for one mesh"),
    };
    let vertex_count = faces
        .checked_mul((n + 1) * (n + 2) / 2)
        .ok_or_else(too_big)?;
    let index_count = faces.checked_mul(3 * n * n).ok_or_else(too_big)?;
    // A PN patch bulges at most about a third of its edges beyond its corners' box.
    let size = input.bounds.size().max_element();
    let reach = if curved { size / 3.0 } else { 0.0 };
    run(
        renderer,
        Op {
            key: PnTrianglesKey { flat: !curved }.key(),
            input: Some(input),
            previous,
            vertex_count,
            index_count,
            threads: vertex_count.max(index_count),
            params: bytemuck::cast_slice(&[n, 0, 0, 0]),
            extra: Vec::new(),
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
