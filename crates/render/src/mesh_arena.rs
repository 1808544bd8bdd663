//! Every mesh on the GPU lives in one shared vertex buffer and one shared
//! index buffer. The visibility-buffer resolve fetches any pixel's triangle
//! by instance, which needs all meshes addressable from one binding; the
//! arena sub-allocates ranges (range-alloc, as wgpu-hal does) and frees them
//! when the last [`GpuMesh`] handle drops.

use std::ops::Range;
use std::sync::{Arc, Mutex};

use bytemuck::{Pod, Zeroable};
use range_alloc::RangeAllocator;

use crate::context::GpuContext;
use crate::error::RenderError;
use crate::mesh::{Aabb, MeshData};

/// 64 bytes; matches `Vertex` in shaders/lib/mesh.wgsl. `previous_position`
/// holds last frame's object-space position (xyz) and a geometry id (w, an
/// integer as a float: Emeshe's "Instance from GeomFX", 0 for uploaded meshes).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct GpuVertex {
    pub position_u: [f32; 4],
    pub normal_v: [f32; 4],
    pub tangent: [f32; 4],
    pub previous_position: [f32; 4],
}

const VERTEX_SIZE: u64 = std::mem::size_of::<GpuVertex>() as u64;

/// 16 bytes a vertex, in a stream of its own beside [`GpuVertex`] (same
/// index): the second UV set and the vertex colour (RGBA as four unorm16,
/// linear). Only the surface resolve and the alpha test read it; the
/// rasterizers (compute and hardware) and the GPU geometry passes never
/// do, so their 64-byte vertex reads stay as they were. Matches
/// `VertexExtra` in shaders/lib/mesh.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct GpuVertexExtra {
    pub second_uv: [f32; 2],
    pub color: [u32; 2],
}

const EXTRA_SIZE: u64 = std::mem::size_of::<GpuVertexExtra>() as u64;

impl GpuVertexExtra {
    /// What a vertex without the streams gets: its first UV set as the
    /// second, and white.
    pub fn new(second_uv: [f32; 2], color: [f32; 4]) -> Self {
        let unorm = |c: f32| (c.clamp(0.0, 1.0) * 65535.0).round() as u32;
        GpuVertexExtra {
            second_uv,
            color: [
                unorm(color[0]) | unorm(color[1]) << 16,
                unorm(color[2]) | unorm(color[3]) << 16,
            ],
        }
    }

    /// The colour as stored (linear RGBA).
    pub fn rgba(&self) -> [f32; 4] {
        let c = |word: u32, shift: u32| ((word >> shift) & 0xffff) as f32 / 65535.0;
        [
            c(self.color[0], 0),
            c(self.color[0], 16),
            c(self.color[1], 0),
            c(self.color[1], 16),
        ]
    }
}

struct Inner {
    vertices: wgpu::Buffer,
    /// [`GpuVertexExtra`] per vertex, allocated with `vertices`.
    extras: wgpu::Buffer,
    indices: wgpu::Buffer,
    vertex_alloc: RangeAllocator<u32>,
    index_alloc: RangeAllocator<u32>,
    /// Bumped when a buffer is replaced by a bigger one: bind groups made before must be rebuilt.
    generation: u64,
}

/// The shared mesh storage. Cheap to clone (shared).
#[derive(Clone)]
pub struct MeshArena {
    inner: Arc<Mutex<Inner>>,
}

/// A mesh uploaded to the arena. Its ranges are freed when it drops.
pub struct GpuMesh {
    arena: Arc<Mutex<Inner>>,
    pub vertices: Range<u32>,
    pub indices: Range<u32>,
    pub bounds: Aabb,
    pub has_uvs: bool,
    pub has_tangents: bool,
    pub has_previous_positions: bool,
    /// The mesh has a second UV set of its own (TEXCOORD_1).
    pub has_uvs1: bool,
    /// The mesh has vertex colours (COLOR_0).
    pub has_colors: bool,
    /// The ranges the allocator handed out (an empty mesh still holds one
    /// element of each); None for a procedural mesh, which owns nothing.
    allocated: Option<(Range<u32>, Range<u32>)>,
    /// Triangles made in the shaders from records (particles), see [`Procedural`].
    procedural: Option<Procedural>,
}

/// A mesh whose triangles every mesh-pulling shader makes on the fly
/// (shaders/lib/mesh_fetch.wgsl) from the records in `vertices`: a header
/// then one record a particle. Nothing is expanded into the arena, so a
/// particle system costs its records only (O(particles), not O(triangles)).
#[derive(Debug)]
struct Procedural {
    triangles: u32,
    /// The records' owner and, for copies of a shape, the shape: kept alive while drawn.
    _records: Arc<GpuMesh>,
    _shape: Option<Arc<GpuMesh>>,
}

/// Set in an instance's first-index word (`GpuInstance::info.x`) for a
/// procedural mesh; matches `PROCEDURAL` in shaders/lib/mesh_fetch.wgsl.
pub const PROCEDURAL_FLAG: u32 = 0x8000_0000;

/// What a mesh made on the GPU carries, known before its pass runs.
#[derive(Clone, Copy, Debug)]
pub struct MeshLayout {
    /// Conservative bounds (shadow maps fit their views to them).
    pub bounds: Aabb,
    pub has_uvs: bool,
    pub has_tangents: bool,
}

impl std::fmt::Debug for GpuMesh {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "GpuMesh({} vertices, {} indices)",
            self.vertices.len(),
            self.indices.len()
        )
    }
}

impl Drop for GpuMesh {
    fn drop(&mut self) {
        let Some((vertices, indices)) = self.allocated.take() else {
            return;
        };
        let mut inner = self.arena.lock().unwrap_or_else(|e| e.into_inner());
        inner.vertex_alloc.free_range(vertices);
        inner.index_alloc.free_range(indices);
    }
}

impl GpuMesh {
    /// How many indices a draw of this mesh runs (three a triangle).
    pub fn index_count(&self) -> u32 {
        match &self.procedural {
            Some(p) => p.triangles.saturating_mul(3),
            None => self.indices.len() as u32,
        }
    }

    /// The word an instance carries as its first index: the index range's
    /// start, or [`PROCEDURAL_FLAG`] for a procedural mesh.
    pub fn first_index_word(&self) -> u32 {
        match self.procedural {
            Some(_) => PROCEDURAL_FLAG,
            None => self.indices.start,
        }
    }

    /// True for triangles made in the shaders from records (particles).
    pub fn is_procedural(&self) -> bool {
        self.procedural.is_some()
    }
}

fn storage_buffer(gpu: &GpuContext, label: &str, size: u64) -> wgpu::Buffer {
    gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size,
        usage: wgpu::BufferUsages::STORAGE
            | wgpu::BufferUsages::COPY_DST
            | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    })
}

impl MeshArena {
    pub fn new(gpu: &GpuContext) -> Self {
        let (vertex_capacity, index_capacity) = (1u32 << 14, 1u32 << 16);
        MeshArena {
            inner: Arc::new(Mutex::new(Inner {
                vertices: storage_buffer(
                    gpu,
                    "mesh arena vertices",
                    u64::from(vertex_capacity) * VERTEX_SIZE,
                ),
                extras: storage_buffer(
                    gpu,
                    "mesh arena vertex extras",
                    u64::from(vertex_capacity) * EXTRA_SIZE,
                ),
                indices: storage_buffer(gpu, "mesh arena indices", u64::from(index_capacity) * 4),
                vertex_alloc: RangeAllocator::new(0..vertex_capacity),
                index_alloc: RangeAllocator::new(0..index_capacity),
                generation: 0,
            })),
        }
    }

    /// The shared buffers (vertices, indices) and their generation.
    pub fn buffers(&self) -> (wgpu::Buffer, wgpu::Buffer, u64) {
        let inner = self.inner.lock().unwrap_or_else(|e| e.into_inner());
        (
            inner.vertices.clone(),
            inner.indices.clone(),
            inner.generation,
        )
    }

    /// The bytes the shared vertex and index buffers hold now (tests prove
    /// what a mesh costs by them).
    pub fn buffer_sizes(&self) -> (u64, u64) {
        let inner = self.inner.lock().unwrap_or_else(|e| e.into_inner());
        (inner.vertices.size(), inner.indices.size())
    }

    pub fn upload(&self, gpu: &GpuContext, mesh: &MeshData) -> Result<Arc<GpuMesh>, RenderError> {
        self.upload_inner(gpu, mesh, None)
    }

    /// The second UV set and colour of every vertex ([`GpuVertexExtra`]),
    /// indexed as the vertices of [`MeshArena::buffers`]. Replaced together
    /// with them when the arena grows (same generation).
    pub fn extras(&self) -> wgpu::Buffer {
        let inner = self.inner.lock().unwrap_or_else(|e| e.into_inner());
        inner.extras.clone()
    }

    /// Uploads an animated mesh: `previous` holds each vertex's position last
    /// frame (xyz) and its geometry id (w, a whole number), so `Velocity: From
    /// Geometry` sees its deformation and "Instance from GeomFX" its ids.
    pub fn upload_with_previous(
        &self,
        gpu: &GpuContext,
        mesh: &MeshData,
        previous: &[[f32; 4]],
    ) -> Result<Arc<GpuMesh>, RenderError> {
        if previous.len() != mesh.positions.len()
            || !previous.iter().flatten().all(|x| x.is_finite())
        {
            return Err(RenderError::Pass {
                pass: "mesh upload".to_owned(),
                message: format!(
                    "previous positions must be {} finite points, one per vertex (got {})",
                    mesh.positions.len(),
                    previous.len()
                ),
            });
        }
        self.upload_inner(gpu, mesh, Some(previous))
    }

    /// Reserves room for a mesh that a compute pass will write (GPU geometry):
    /// nothing is uploaded. The caller writes every vertex, its extras and
    /// every index in range (shaders/lib/geometry.wgsl's `write_vertex`
    /// writes the extras; a mesh remade every frame, as a skinned one is,
    /// would otherwise upload them every frame).
    pub fn allocate(
        &self,
        gpu: &GpuContext,
        vertex_count: u32,
        index_count: u32,
        layout: MeshLayout,
    ) -> Result<Arc<GpuMesh>, RenderError> {
        let mut inner = self.inner.lock().unwrap_or_else(|e| e.into_inner());
        let vertex_range = allocate(gpu, &mut inner, vertex_count.max(1), Stream::Vertices)?;
        let index_range = match allocate(gpu, &mut inner, index_count.max(1), Stream::Indices) {
            Ok(r) => r,
            Err(e) => {
                inner.vertex_alloc.free_range(vertex_range);
                return Err(e);
            }
        };
        Ok(Arc::new(GpuMesh {
            arena: self.inner.clone(),
            vertices: vertex_range.start..vertex_range.start + vertex_count,
            indices: index_range.start..index_range.start + index_count,
            allocated: Some((vertex_range, index_range)),
            bounds: layout.bounds,
            has_uvs: layout.has_uvs,
            has_tangents: layout.has_tangents,
            has_previous_positions: true,
            procedural: None,
            has_uvs1: false,
            has_colors: false,
        }))
    }

    /// A procedural mesh of `triangles` over the records of `records` (a
    /// header, then one record a particle: see shaders/lib/mesh_fetch.wgsl),
    /// keeping `records` and `shape` alive while it is drawn.
    pub fn procedural(
        &self,
        records: &Arc<GpuMesh>,
        shape: Option<Arc<GpuMesh>>,
        triangles: u32,
        layout: MeshLayout,
    ) -> Arc<GpuMesh> {
        Arc::new(GpuMesh {
            arena: self.inner.clone(),
            vertices: records.vertices.clone(),
            indices: 0..0,
            allocated: None,
            bounds: layout.bounds,
            has_uvs: layout.has_uvs,
            has_tangents: layout.has_tangents,
            has_previous_positions: true,
            procedural: Some(Procedural {
                triangles,
                _records: records.clone(),
                _shape: shape,
            }),
            // Corners are made from the records: no extras stored.
            has_uvs1: false,
            has_colors: false,
        })
    }

    fn upload_inner(
        &self,
        gpu: &GpuContext,
        mesh: &MeshData,
        previous: Option<&[[f32; 4]]>,
    ) -> Result<Arc<GpuMesh>, RenderError> {
        mesh.validate().map_err(|e| RenderError::Pass {
            pass: "mesh upload".to_owned(),
            message: e.to_string(),
        })?;
        let vertices: Vec<GpuVertex> = (0..mesh.positions.len())
            .map(|i| {
                let p = mesh.positions[i];
                let n = mesh.normals[i];
                let uv = mesh.uvs.as_ref().map_or([0.0; 2], |u| u[i]);
                let t = mesh
                    .tangents
                    .as_ref()
                    .map_or([1.0, 0.0, 0.0, 1.0], |t| t[i]);
                GpuVertex {
                    position_u: [p[0], p[1], p[2], uv[0]],
                    normal_v: [n[0], n[1], n[2], uv[1]],
                    tangent: t,
                    previous_position: match previous {
                        Some(before) => before[i],
                        None => [p[0], p[1], p[2], 0.0],
                    },
                }
            })
            .collect();
        let extras: Vec<GpuVertexExtra> = (0..mesh.positions.len())
            .map(|i| {
                // Without a second set, the first stands in: a map on
                // TEXCOORD_1 of such a mesh reads TEXCOORD_0.
                let uv1 = match (&mesh.uvs1, &mesh.uvs) {
                    (Some(uv1), _) => uv1[i],
                    (None, Some(uv)) => uv[i],
                    (None, None) => [0.0; 2],
                };
                let color = mesh.colors.as_ref().map_or([1.0; 4], |c| c[i]);
                GpuVertexExtra::new(uv1, color)
            })
            .collect();
        let too_big = |what: &str| RenderError::Pass {
            pass: "mesh upload".to_owned(),
            message: format!("the mesh has too many {what} for one draw (over 2^31)"),
        };
        let vertex_count = u32::try_from(vertices.len()).map_err(|_| too_big("vertices"))?;
        let index_count = u32::try_from(mesh.indices.len()).map_err(|_| too_big("indices"))?;
        let mut inner = self.inner.lock().unwrap_or_else(|e| e.into_inner());
        let vertex_range = allocate(gpu, &mut inner, vertex_count, Stream::Vertices)?;
        let index_range = match allocate(gpu, &mut inner, index_count.max(1), Stream::Indices) {
            Ok(r) => r,
            Err(e) => {
                inner.vertex_alloc.free_range(vertex_range);
                return Err(e);
            }
        };
        gpu.queue.write_buffer(
            &inner.vertices,
            u64::from(vertex_range.start) * VERTEX_SIZE,
            bytemuck::cast_slice(&vertices),
        );
        gpu.queue.write_buffer(
            &inner.extras,
            u64::from(vertex_range.start) * EXTRA_SIZE,
            bytemuck::cast_slice(&extras),
        );
        if !mesh.indices.is_empty() {
            gpu.queue.write_buffer(
                &inner.indices,
                u64::from(index_range.start) * 4,
                bytemuck::cast_slice(&mesh.indices),
            );
        }
        Ok(Arc::new(GpuMesh {
            arena: self.inner.clone(),
            vertices: vertex_range.clone(),
            indices: index_range.start..index_range.start + index_count,
            allocated: Some((vertex_range, index_range)),
            bounds: mesh.bounds,
            has_uvs: mesh.uvs.is_some(),
            has_tangents: mesh.tangents.is_some(),
            has_previous_positions: previous.is_some(),
            procedural: None,
            has_uvs1: mesh.uvs1.is_some(),
            has_colors: mesh.colors.is_some(),
        }))
    }
}

/// A render pipeline drawing from the arena: its vertex shader `vs` pulls
/// vertices and indices from the arena's storage buffers (so it has no
/// vertex buffers), and its fragment shader `fs` writes `targets`; with
/// none there is no fragment stage (a depth-only pass).
pub(crate) fn pulled_pipeline(
    device: &wgpu::Device,
    module: &wgpu::ShaderModule,
    cache: Option<&wgpu::PipelineCache>,
    label: &str,
    primitive: wgpu::PrimitiveState,
    depth_stencil: Option<wgpu::DepthStencilState>,
    targets: &[Option<wgpu::ColorTargetState>],
) -> wgpu::RenderPipeline {
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(label),
        layout: None,
        vertex: wgpu::VertexState {
            module,
            entry_point: Some("vs"),
            compilation_options: Default::default(),
            buffers: &[],
        },
        primitive,
        depth_stencil,
        multisample: Default::default(),
        fragment: (!targets.is_empty()).then(|| wgpu::FragmentState {
            module,
            entry_point: Some("fs"),
            compilation_options: Default::default(),
            targets,
        }),
        multiview_mask: None,
        cache,
    })
}

#[derive(Clone, Copy)]
enum Stream {
    Vertices,
    Indices,
}

/// Allocate `count` elements, growing the buffer (and copying what it holds) when full.
fn allocate(
    gpu: &GpuContext,
    inner: &mut Inner,
    count: u32,
    stream: Stream,
) -> Result<Range<u32>, RenderError> {
    let (alloc, element) = match stream {
        Stream::Vertices => (&mut inner.vertex_alloc, VERTEX_SIZE),
        Stream::Indices => (&mut inner.index_alloc, 4),
    };
    if let Ok(range) = alloc.allocate_range(count) {
        return Ok(range);
    }
    let old_end = alloc.initial_range().end;
    let needed = old_end
        .checked_add(count)
        .ok_or_else(|| RenderError::Pass {
            pass: "mesh upload".to_owned(),
            message: "the mesh arena cannot grow past 2^32 elements".to_owned(),
        })?;
    let new_end = needed.max(old_end.saturating_mul(2));
    let max = gpu.device.limits().max_storage_buffer_binding_size / element;
    if u64::from(new_end) > max {
        return Err(RenderError::Pass {
            pass: "mesh upload".to_owned(),
            message: format!(
                "all meshes together would exceed the GPU's storage buffer limit ({max} elements)"
            ),
        });
    }
    alloc.grow_to(new_end);
    let grown = |old: &wgpu::Buffer, element: u64| {
        let bigger = storage_buffer(gpu, "mesh arena", u64::from(new_end) * element);
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        encoder.copy_buffer_to_buffer(old, 0, &bigger, 0, u64::from(old_end) * element);
        gpu.submit([encoder.finish()]);
        bigger
    };
    match stream {
        Stream::Vertices => {
            inner.vertices = grown(&inner.vertices, VERTEX_SIZE);
            inner.extras = grown(&inner.extras, EXTRA_SIZE);
        }
        Stream::Indices => inner.indices = grown(&inner.indices, 4),
    }
    inner.generation += 1;
    let alloc = match stream {
        Stream::Vertices => &mut inner.vertex_alloc,
        Stream::Indices => &mut inner.index_alloc,
    };
    alloc.allocate_range(count).map_err(|_| RenderError::Pass {
        pass: "mesh upload".to_owned(),
        message: "the mesh arena could not grow".to_owned(),
    })
}

/// The layout the shader sees (shaders/layout.rs).
#[cfg(test)]
mod wgsl_layout {
    use super::*;

    #[test]
    fn gpu_vertex_matches_vertex_in_the_shader() {
        crate::assert_wgsl_layout!(
            GpuVertex,
            "lib/mesh.wgsl",
            [],
            "Vertex",
            [position_u, normal_v, tangent, previous_position]
        );
    }

    #[test]
    fn gpu_vertex_extra_matches_vertexextra_in_the_shader() {
        crate::assert_wgsl_layout!(
            GpuVertexExtra,
            "lib/mesh.wgsl",
            ["VERTEX_EXTRAS"],
            "VertexExtra",
            [second_uv, color]
        );
    }
}
