//! Reading GPU geometry back (tests, accuracy tables): a mesh's vertices,
//! indices and vertex extras out of the arena, and any storage buffer's bytes.

use crate::error::RenderError;
use crate::mesh_arena::{GpuMesh, GpuVertex, GpuVertexExtra};
use crate::renderer::Renderer;

/// `size` bytes of `buffer` from `offset`, copied through a mappable buffer.
pub fn read_storage(
    renderer: &Renderer,
    buffer: &wgpu::Buffer,
    offset: u64,
    size: u64,
) -> Result<Vec<u8>, RenderError> {
    let gpu = &renderer.gpu;
    let size = size.max(4);
    let staging = gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("geometry readback"),
        size,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    encoder.copy_buffer_to_buffer(buffer, offset, &staging, 0, size);
    gpu.submit([encoder.finish()]);
    crate::renderer::read_buffer(gpu, &staging, size)
}

/// A GPU mesh's vertices and (mesh-relative) indices.
pub fn read_mesh(
    renderer: &Renderer,
    mesh: &GpuMesh,
) -> Result<(Vec<GpuVertex>, Vec<u32>), RenderError> {
    if mesh.is_procedural() {
        return Err(RenderError::Pass {
            pass: "mesh readback".to_owned(),
            message:
                "the mesh is drawn procedurally (particles): read it with particles::read_drawn"
                    .to_owned(),
        });
    }
    let (vertices, indices, _) = renderer.meshes.buffers();
    let vertex_size = std::mem::size_of::<GpuVertex>() as u64;
    let v = read_storage(
        renderer,
        &vertices,
        u64::from(mesh.vertices.start) * vertex_size,
        mesh.vertices.len() as u64 * vertex_size,
    )?;
    let i = read_storage(
        renderer,
        &indices,
        u64::from(mesh.indices.start) * 4,
        mesh.indices.len() as u64 * 4,
    )?;
    let vertex_bytes = mesh.vertices.len() * vertex_size as usize;
    Ok((
        bytemuck::pod_collect_to_vec(&v[..vertex_bytes]),
        bytemuck::pod_collect_to_vec(&i[..mesh.indices.len() * 4]),
    ))
}

/// A stored mesh's vertex extras (second UV set and colour), one per vertex.
pub fn read_extras(
    renderer: &Renderer,
    mesh: &GpuMesh,
) -> Result<Vec<GpuVertexExtra>, RenderError> {
    if mesh.is_procedural() {
        return Err(RenderError::Pass {
            pass: "mesh readback".to_owned(),
            message: "the mesh is drawn procedurally (particles): its corners store no extras"
                .to_owned(),
        });
    }
    let size = std::mem::size_of::<GpuVertexExtra>() as u64;
    let bytes = read_storage(
        renderer,
        &renderer.meshes.extras(),
        u64::from(mesh.vertices.start) * size,
        mesh.vertices.len() as u64 * size,
    )?;
    Ok(bytemuck::pod_collect_to_vec(
        &bytes[..mesh.vertices.len() * size as usize],
    ))
}
