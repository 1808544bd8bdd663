//! Decimate: edge collapse to a target share of the triangles, keeping UV
//! seams and (optionally) borders, with meshoptimizer's quadric simplifier
//! (the `meshopt` crate).
//!
//! This pass runs on the CPU: it reads the mesh back, simplifies it and
//! uploads the result. Edge collapse is sequential by nature (each collapse
//! changes the costs around it) and meshoptimizer is the well-kept
//! implementation that already classifies seams (vertices sharing a position
//! with different attributes: both sides collapse together, no cracks),
//! borders and locked vertices; a GPU vertex clustering would be cheaper per
//! run but could neither keep seams nor hit a ratio without a search.
//! Decimation reruns only when its inputs change (the runtime reuses the
//! node), so the readback is paid once, not every frame.
//!
//! Simplification only removes vertices: every output vertex is an input
//! vertex with all it carries, previous position and geometry id included,
//! so an animated input's motion passes through unchanged.

use std::collections::HashMap;
use std::sync::Arc;

use meshopt::{SimplifyOptions, VertexDataAdapter};

use super::read_mesh;
use crate::error::RenderError;
use crate::mesh::{Aabb, MeshData};
use crate::mesh_arena::{GpuMesh, GpuVertex, MeshLayout};
use crate::renderer::Renderer;

/// What to keep.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DecimateParams {
    /// The share of the triangles to keep, 0..=1.
    pub ratio: f32,
    /// Vertices on the mesh's open borders never move: borders stay exactly
    /// where they were (pieces of a larger surface still meet without gaps).
    pub lock_border: bool,
}

fn bad(message: String) -> RenderError {
    RenderError::Pass {
        pass: "Decimate".to_owned(),
        message,
    }
}

/// `input` simplified to about `params.ratio` of its triangles (fewer where
/// locked borders and seams leave nothing more to collapse).
pub fn decimate(
    renderer: &Renderer,
    input: &GpuMesh,
    params: DecimateParams,
) -> Result<Arc<GpuMesh>, RenderError> {
    if !(0.0..=1.0).contains(&params.ratio) {
        return Err(bad(format!("Ratio {} is not within 0..1", params.ratio)));
    }
    let (vertices, indices) = read_mesh(renderer, input)?;
    if indices.len() < 3 {
        let layout = MeshLayout {
            bounds: Aabb::ZERO,
            has_uvs: input.has_uvs,
            has_tangents: input.has_tangents,
        };
        return renderer.meshes.allocate(&renderer.gpu, 0, 0, layout);
    }
    // meshoptimizer finds seams by equal positions; generated and imported
    // meshes often differ by an ulp where faces meet, which would make the
    // two sides independent borders that collapse apart (cracks). Positions
    // within a millionth of the mesh's size count as one for the decisions;
    // the output keeps the exact input vertices.
    let step = (input.bounds.size().max_element() * 1e-6).max(f32::MIN_POSITIVE);
    let snap = |x: f32| (x / step).round() * step;
    let positions: Vec<[f32; 3]> = vertices
        .iter()
        .map(|v| {
            [
                snap(v.position_u[0]),
                snap(v.position_u[1]),
                snap(v.position_u[2]),
            ]
        })
        .collect();
    let adapter = VertexDataAdapter::new(bytemuck::cast_slice(&positions), 12, 0)
        .map_err(|e| bad(e.to_string()))?;
    let target = ((indices.len() / 3) as f64 * f64::from(params.ratio)).round() as usize * 3;
    let options = if params.lock_border {
        SimplifyOptions::LockBorder
    } else {
        SimplifyOptions::None
    };
    // An error bound of the whole mesh's size: the ratio decides.
    let kept = meshopt::simplify(&indices, &adapter, target, 1.0, options, None);
    // Compact the kept vertices in order of first use.
    let mut remap: HashMap<u32, u32> = HashMap::new();
    let mut order = Vec::new();
    let indices: Vec<u32> = kept
        .iter()
        .map(|&i| {
            *remap.entry(i).or_insert_with(|| {
                order.push(i as usize);
                order.len() as u32 - 1
            })
        })
        .collect();
    let pick = |f: &dyn Fn(&GpuVertex) -> [f32; 4]| -> Vec<[f32; 4]> {
        order.iter().map(|&i| f(&vertices[i])).collect()
    };
    let xyz = |v: [f32; 4]| [v[0], v[1], v[2]];
    let mut mesh = MeshData {
        positions: pick(&|v| v.position_u).into_iter().map(xyz).collect(),
        normals: pick(&|v| v.normal_v).into_iter().map(xyz).collect(),
        uvs: input.has_uvs.then(|| {
            order
                .iter()
                .map(|&i| [vertices[i].position_u[3], vertices[i].normal_v[3]])
                .collect()
        }),
        tangents: input.has_tangents.then(|| pick(&|v| v.tangent)),
        // The arena's extra stream (TEXCOORD_1, COLOR_0) is not read back:
        // a decimated mesh maps every texture with its first UV set, white.
        uvs1: None,
        colors: None,
        indices,
        bounds: Aabb::ZERO,
    };
    mesh.recompute_bounds();
    let previous = pick(&|v| v.previous_position);
    renderer
        .meshes
        .upload_with_previous(&renderer.gpu, &mesh, &previous)
}
