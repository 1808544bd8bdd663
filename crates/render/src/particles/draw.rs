//! Drawing particles: every slot expanded into a mesh in the arena
//! (shaders/particles/draw.wgsl), camera-facing quads or copies of a shape.

use std::sync::Arc;

use bytemuck::{Pod, Zeroable};
use glam::Vec3;

use super::ParticleSystem;
use crate::error::RenderError;
use crate::geometry::{Op, run_into};
use crate::mesh::Aabb;
use crate::mesh_arena::{GpuMesh, MeshLayout};
use crate::renderer::Renderer;
use crate::shaders::ShaderKey;

/// What each particle becomes.
#[derive(Clone, Copy, Debug)]
pub enum DrawShape<'a> {
    /// A quad facing the camera, given its right and up vectors in world space.
    Sprites { right: Vec3, up: Vec3 },
    /// A copy of this mesh, scaled by the particle size (instanced meshes).
    Mesh(&'a GpuMesh),
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct Params {
    right: [f32; 4],
    up: [f32; 4],
    shape: [f32; 4],
}

/// The particles of `system` as one mesh: `size` is the sprite half size or
/// the shape's scale; `shrink` makes particles vanish over their lifetime.
/// Bounded by the system's world radius plus the particle size. Written into
/// `reuse` (last frame's output) when it fits, so the arena holds one copy.
pub fn draw(
    renderer: &Renderer,
    system: &ParticleSystem,
    shape: DrawShape<'_>,
    size: f32,
    shrink: bool,
    world_radius: f32,
    reuse: Option<&Arc<GpuMesh>>,
) -> Result<Arc<GpuMesh>, RenderError> {
    let size = if size.is_finite() { size.max(0.0) } else { 0.0 };
    let (per_vertex, per_index, input, sprites, right, up, shape_reach) = match shape {
        DrawShape::Sprites { right, up } => {
            let right = right.try_normalize().unwrap_or(Vec3::X);
            let up = up.try_normalize().unwrap_or(Vec3::Y);
            (4u32, 6u32, None, true, right, up, 1.0)
        }
        DrawShape::Mesh(mesh) => {
            let reach = mesh.bounds.min.abs().max(mesh.bounds.max.abs()).length();
            (
                mesh.vertices.len() as u32,
                mesh.indices.len() as u32,
                Some(mesh),
                false,
                Vec3::X,
                Vec3::Y,
                reach,
            )
        }
    };
    let too_many = || RenderError::Pass {
        pass: "particles draw".to_owned(),
        message: format!(
            "{} particles of {per_vertex} vertices are too many for one mesh",
            system.capacity()
        ),
    };
    let vertex_count = system
        .capacity()
        .checked_mul(per_vertex.max(1))
        .ok_or_else(too_many)?;
    let index_count = system
        .capacity()
        .checked_mul(per_index.max(1))
        .ok_or_else(too_many)?;
    let params = Params {
        right: right.extend(0.0).into(),
        up: up.extend(0.0).into(),
        shape: [
            size,
            if shrink { 1.0 } else { 0.0 },
            per_vertex.max(1) as f32,
            per_index.max(1) as f32,
        ],
    };
    let reach = world_radius.max(0.0) + size * shape_reach * 2.0;
    let features: &[&'static str] = if sprites { &["SPRITES"] } else { &[] };
    run_into(
        renderer,
        Op {
            key: ShaderKey::new("particles/draw.wgsl", features.iter().copied()),
            input,
            previous: None,
            vertex_count,
            index_count,
            threads: vertex_count.max(index_count),
            params: bytemuck::bytes_of(&params),
            extra: vec![(4, system.buffer().as_entire_binding())],
            layout: MeshLayout {
                bounds: Aabb {
                    min: Vec3::splat(-reach),
                    max: Vec3::splat(reach),
                },
                has_uvs: sprites || input.is_some_and(|m| m.has_uvs),
                has_tangents: true,
            },
        },
        reuse,
    )
}
