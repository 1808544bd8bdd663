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

/// Items `range` of `buffer`, a stream of the mesh arena holding `T`s.
fn read_range<T: bytemuck::Pod>(
    renderer: &Renderer,
    buffer: &wgpu::Buffer,
    range: std::ops::Range<u32>,
) -> Result<Vec<T>, RenderError> {
    let size = std::mem::size_of::<T>();
    let bytes = read_storage(
        renderer,
        buffer,
        u64::from(range.start) * size as u64,
        (range.len() * size) as u64,
    )?;
    Ok(bytemuck::pod_collect_to_vec(&bytes[..range.len() * size]))
}

/// An error unless `mesh` is stored in the arena (particles are drawn
/// procedurally: `instead` says what reads them).
fn stored(mesh: &GpuMesh, instead: &str) -> Result<(), RenderError> {
    if mesh.is_procedural() {
        return Err(RenderError::Pass {
            pass: "mesh readback".to_owned(),
            message: format!("the mesh is drawn procedurally (particles): {instead}"),
        });
    }
    Ok(())
}

/// A GPU mesh's vertices and (mesh-relative) indices.
pub fn read_mesh(
    renderer: &Renderer,
    mesh: &GpuMesh,
) -> Result<(Vec<GpuVertex>, Vec<u32>), RenderError> {
    stored(mesh, "read it with particles::read_drawn")?;
    let (vertices, indices, _) = renderer.meshes.buffers();
    Ok((
        read_range(renderer, &vertices, mesh.vertices.clone())?,
        read_range(renderer, &indices, mesh.indices.clone())?,
    ))
}

/// A stored mesh's vertex extras (second UV set and colour), one per vertex.
pub fn read_extras(
    renderer: &Renderer,
    mesh: &GpuMesh,
) -> Result<Vec<GpuVertexExtra>, RenderError> {
    stored(mesh, "its corners store no extras")?;
    read_range(renderer, &renderer.meshes.extras(), mesh.vertices.clone())
}
