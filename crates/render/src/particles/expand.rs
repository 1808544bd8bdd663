//! Reading drawn particles back: the triangles of a procedural mesh as the
//! drawing passes make them (shaders/particles/expand.wgsl runs the same
//! shaders/lib/mesh_fetch.wgsl function they do), for tests and tables.

use glam::{Mat4, Vec3};

use crate::error::RenderError;
use crate::gbuffer::GpuInstance;
use crate::geometry::{dispatch, read_storage, uniform};
use crate::mesh_arena::{GpuMesh, GpuVertex};
use crate::renderer::Renderer;
use crate::shaders::Permutation;

pub use super::expand_key::ExpandKey;

/// Every triangle of `mesh` drawn by a view whose axes in world space are
/// `right` and `up` (sprites face it), with the identity transform: three
/// vertices a triangle, and indices 0, 1, 2, ... to match.
pub fn read_drawn(
    renderer: &Renderer,
    mesh: &GpuMesh,
    right: Vec3,
    up: Vec3,
) -> Result<(Vec<GpuVertex>, Vec<u32>), RenderError> {
    let triangles = mesh.index_count() / 3;
    let count = triangles as usize * 3;
    let vertex_size = std::mem::size_of::<GpuVertex>() as u64;
    let instance = GpuInstance {
        model: Mat4::IDENTITY.to_cols_array_2d(),
        previous_model: Mat4::IDENTITY.to_cols_array_2d(),
        normal_matrix: Mat4::IDENTITY.to_cols_array_2d(),
        color: [1.0; 4],
        info: [mesh.first_index_word(), mesh.vertices.start, 0, 0],
    };
    let device = &renderer.gpu.device;
    let instances = {
        use wgpu::util::DeviceExt;
        device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("read drawn: instance"),
            contents: bytemuck::bytes_of(&instance),
            usage: wgpu::BufferUsages::STORAGE,
        })
    };
    let out = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("read drawn: triangles"),
        size: (count.max(1) as u64) * vertex_size,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let params: [f32; 8] = [
        right.x,
        right.y,
        right.z,
        f32::from_bits(triangles),
        up.x,
        up.y,
        up.z,
        0.0,
    ];
    let params = uniform(renderer, "read drawn: params", bytemuck::bytes_of(&params));
    let (vertices, indices, _) = renderer.meshes.buffers();
    dispatch(
        renderer,
        &ExpandKey.key(),
        vec![
            ("params", params.as_entire_binding()),
            ("vertices", vertices.as_entire_binding()),
            ("indices", indices.as_entire_binding()),
            ("instances", instances.as_entire_binding()),
            ("out", out.as_entire_binding()),
        ],
        count as u32,
    )?;
    let bytes = read_storage(renderer, &out, 0, count as u64 * vertex_size)?;
    Ok((
        bytemuck::pod_collect_to_vec(&bytes[..count * vertex_size as usize]),
        (0..count as u32).collect(),
    ))
}
