//! Drawing particles: a procedural mesh over the system's records. Nothing
//! is expanded: every pass that pulls meshes makes each particle's quad
//! (facing the view that draws it) or shape copy on the fly from its record
//! and the header written here (shaders/lib/mesh_fetch.wgsl).

use std::sync::Arc;

use bytemuck::{Pod, Zeroable};
use glam::Vec3;

use super::ParticleSystem;
use crate::error::RenderError;
use crate::mesh::Aabb;
use crate::mesh_arena::{GpuMesh, MeshLayout};
use crate::renderer::Renderer;

/// What each particle becomes.
#[derive(Clone, Copy, Debug)]
pub enum DrawShape<'a> {
    /// A quad facing whichever view draws it (the camera in the G-buffer,
    /// the light in a shadow map).
    Sprites,
    /// A copy of this mesh, scaled by the particle size (instanced meshes).
    Mesh(&'a Arc<GpuMesh>),
}

/// Matches `ParticleHeader` as packed in shaders/lib/particle.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct Header {
    shape: [u32; 4],
    size: [f32; 4],
    unused: [f32; 8],
}

/// The particles of `system` as one procedural mesh: `size` is the sprite
/// half size or the shape's scale; `shrink` makes particles vanish over
/// their lifetime. Bounded by the system's world radius plus the particle
/// size. Costs a 64-byte header write: the records are the geometry.
pub fn draw(
    renderer: &Renderer,
    system: &ParticleSystem,
    shape: DrawShape<'_>,
    size: f32,
    shrink: bool,
    world_radius: f32,
) -> Result<Arc<GpuMesh>, RenderError> {
    let size = if size.is_finite() { size.max(0.0) } else { 0.0 };
    let (header, per_particle, shape_mesh, has_uvs, reach) = match shape {
        DrawShape::Sprites => ([0, 0, 0, 2], 2, None, true, 1.0),
        DrawShape::Mesh(mesh) => {
            if mesh.is_procedural() {
                return Err(RenderError::Pass {
                    pass: "particles draw".to_owned(),
                    message: "the Shape is itself drawn procedurally (particles): give a mesh"
                        .to_owned(),
                });
            }
            let triangles = mesh.index_count() / 3;
            (
                [1, mesh.indices.start, mesh.vertices.start, triangles],
                triangles,
                Some(mesh.clone()),
                mesh.has_uvs,
                mesh.bounds.min.abs().max(mesh.bounds.max.abs()).length(),
            )
        }
    };
    let triangles =
        system
            .capacity()
            .checked_mul(per_particle)
            .ok_or_else(|| RenderError::Pass {
                pass: "particles draw".to_owned(),
                message: format!(
                    "{} particles of {per_particle} triangles are too many for one draw",
                    system.capacity()
                ),
            })?;
    let header = Header {
        shape: header,
        size: [size, if shrink { 1.0 } else { 0.0 }, 0.0, 0.0],
        unused: [0.0; 8],
    };
    let records = system.records();
    let (vertices, _, _) = renderer.meshes.buffers();
    renderer.gpu.queue.write_buffer(
        &vertices,
        u64::from(records.vertices.start) * std::mem::size_of::<Header>() as u64,
        bytemuck::bytes_of(&header),
    );
    let reach = world_radius.max(0.0) + size * reach * 2.0;
    Ok(renderer.meshes.procedural(
        records,
        shape_mesh,
        triangles,
        MeshLayout {
            bounds: Aabb {
                min: Vec3::splat(-reach),
                max: Vec3::splat(reach),
            },
            has_uvs,
            has_tangents: true,
        },
    ))
}
