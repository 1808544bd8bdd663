//! GPU geometry (Emeshe's GeomFX list): compute passes that read a mesh in
//! the arena and write a new one there, so meshes made on the GPU stay on the
//! GPU and flow into DeferredBase and shadow maps like any mesh.
//!
//! Every output vertex carries its position in last frame's output (when
//! that output had the same vertex count) as its previous position: animate
//! a geometry node's pins and `Velocity: From Geometry` sees the deformation.
//! A pass is one dispatch submitted when its node evaluates; the runtime
//! reuses a node whose inputs did not change, and [`GeometryStats`] counts
//! the dispatches so tests can prove nothing reran.

pub mod analytic;
pub mod decimate;
pub mod displace;
pub(crate) mod displace_key;
pub mod extrude;
pub(crate) mod extrude_key;
pub mod pn_triangles;
pub(crate) mod pn_triangles_key;
pub mod readback;
pub mod skinning;
pub(crate) mod skinning_key;
pub mod spherize;
pub(crate) mod spherize_key;
pub mod spline;
pub(crate) mod spline_key;
pub mod tessellate;
pub(crate) mod tessellate_key;

use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex};

use bytemuck::{Pod, Zeroable};
use wgpu::util::DeviceExt;

use crate::context::GpuContext;
use crate::error::RenderError;
use crate::mesh_arena::{GpuMesh, MeshLayout};
use crate::renderer::Renderer;
use crate::shaders::ShaderKey;

pub use decimate::{DecimateParams, decimate};
pub use displace::{DisplaceParams, displace};
pub use extrude::extrude;
pub use pn_triangles::pn_triangles;
pub use readback::{read_extras, read_mesh, read_storage};
pub use spherize::{SpherizeParams, spherize};
pub use spline::{Curve, Sweep, curve_point, spline};
pub use tessellate::tessellate;

/// Matches `Job` in shaders/lib/geometry.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct GpuJob {
    src_vertex: u32,
    src_index: u32,
    dst_vertex: u32,
    dst_index: u32,
    vertex_count: u32,
    index_count: u32,
    previous_vertex: u32,
    has_previous: u32,
    src_vertex_count: u32,
    src_index_count: u32,
    _pad: [u32; 2],
}

/// What GPU geometry did since the renderer started (shared by every node).
/// Its passes run when their nodes evaluate, outside the frame graph, so
/// `spreadlight bench` switches on [`GeometryStats::set_timing`] to time them.
#[derive(Default, Debug)]
pub struct GeometryStats {
    dispatches: AtomicU64,
    timing: AtomicBool,
    /// Timed dispatches whose timestamps are not read yet: read when the
    /// times are taken, after the frame, so that no dispatch waits for the
    /// GPU as its node evaluates (a wait `bench` would count as CPU time).
    pending: Mutex<Vec<(Timer, Work)>>,
    /// Timers read and free again: a timed frame makes its query sets and
    /// buffers once, not every dispatch.
    free: Mutex<Vec<Timer>>,
    /// GPU nanoseconds of timed dispatches not yet taken.
    gpu_ns: AtomicU64,
    /// Skinning's share of the above, kept apart so benchmarks can name it.
    skinning: AtomicU64,
    skinning_ns: AtomicU64,
}

/// What a dispatch is, for the counters: skinning is timed apart.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Work {
    Geometry,
    Skinning,
}

impl GeometryStats {
    /// The renderer's counters.
    pub fn of(renderer: &Renderer) -> Arc<GeometryStats> {
        renderer.state::<GeometryStats>(0)
    }

    /// Geometry and particle dispatches submitted so far.
    pub fn dispatches(&self) -> u64 {
        self.dispatches.load(Ordering::Relaxed)
    }

    pub(crate) fn count(&self) {
        self.dispatches.fetch_add(1, Ordering::Relaxed);
    }

    /// Time every dispatch on the GPU (where the adapter has timestamps):
    /// for benchmarks, not for frames. The times are read when taken
    /// ([`GeometryStats::take_gpu_ms`]), which waits for the GPU to finish them.
    pub fn set_timing(&self, on: bool) {
        self.timing.store(on, Ordering::Relaxed);
    }

    /// Whether dispatches are timed ([`GeometryStats::set_timing`]).
    pub fn timing(&self) -> bool {
        self.timing.load(Ordering::Relaxed)
    }

    /// Reads the timestamps of every timed dispatch not read yet.
    fn settle(&self, gpu: &GpuContext) -> Result<(), RenderError> {
        let pending = std::mem::take(&mut *self.pending.lock().unwrap_or_else(|e| e.into_inner()));
        let mut read = Vec::with_capacity(pending.len());
        for (timer, work) in pending {
            let ns = timer.read_ns(gpu)?;
            self.gpu_ns.fetch_add(ns, Ordering::Relaxed);
            if work == Work::Skinning {
                self.skinning_ns.fetch_add(ns, Ordering::Relaxed);
            }
            read.push(timer);
        }
        self.free
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .extend(read);
        Ok(())
    }

    /// GPU milliseconds of the dispatches timed since the last call
    /// (skinning's included), once the GPU has run them.
    pub fn take_gpu_ms(&self, gpu: &GpuContext) -> Result<f64, RenderError> {
        self.settle(gpu)?;
        Ok(self.gpu_ns.swap(0, Ordering::Relaxed) as f64 * 1e-6)
    }

    /// Skinning dispatches (glTF skins and morph targets) submitted so far,
    /// also counted in [`GeometryStats::dispatches`].
    pub fn skinning_dispatches(&self) -> u64 {
        self.skinning.load(Ordering::Relaxed)
    }

    /// GPU milliseconds of the skinning dispatches timed since the last call
    /// (a part of what [`GeometryStats::take_gpu_ms`] returns).
    pub fn take_skinning_gpu_ms(&self, gpu: &GpuContext) -> Result<f64, RenderError> {
        self.settle(gpu)?;
        Ok(self.skinning_ns.swap(0, Ordering::Relaxed) as f64 * 1e-6)
    }
}

/// A query set for one timed dispatch, its resolve and readback buffers.
#[derive(Debug)]
struct Timer {
    set: wgpu::QuerySet,
    resolve: wgpu::Buffer,
    readback: wgpu::Buffer,
}

impl Timer {
    fn new(device: &wgpu::Device) -> Timer {
        let buffer = |label, usage| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: 16,
                usage,
                mapped_at_creation: false,
            })
        };
        Timer {
            set: device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("geometry timestamps"),
                ty: wgpu::QueryType::Timestamp,
                count: 2,
            }),
            resolve: buffer(
                "geometry timestamps",
                wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
            ),
            readback: buffer(
                "geometry timestamps readback",
                wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            ),
        }
    }

    /// Nanoseconds between the two timestamps, once the GPU has written them.
    fn read_ns(&self, gpu: &GpuContext) -> Result<u64, RenderError> {
        let bytes = crate::renderer::read_buffer(gpu, &self.readback, 16)?;
        let ticks: [u64; 2] = bytemuck::pod_read_unaligned(&bytes[..16]);
        let period = f64::from(gpu.queue.get_timestamp_period());
        Ok((ticks[1].saturating_sub(ticks[0]) as f64 * period) as u64)
    }
}

/// One geometry pass: a shader over an input mesh writing a new mesh.
pub struct Op<'a> {
    /// The shader (below `shaders/`) and its features; entry point `main`.
    pub key: ShaderKey,
    /// The mesh read (none for passes that make geometry from other data).
    pub input: Option<&'a GpuMesh>,
    /// Last frame's output of the same node and slice: previous positions come from it.
    pub previous: Option<&'a GpuMesh>,
    pub vertex_count: u32,
    pub index_count: u32,
    /// Invocations (at least the larger of the two counts for one-to-one passes).
    pub threads: u32,
    /// The pass's own uniform `params`, a multiple of 16 bytes; empty where the shader has none.
    pub params: &'a [u8],
    /// More bindings of group 0 (4 and up): textures, samplers, buffers.
    /// The operation's own resources, by WGSL variable name.
    pub extra: Vec<(&'static str, wgpu::BindingResource<'a>)>,
    pub layout: MeshLayout,
}

/// Runs `op` now (one submission) and returns the mesh it wrote.
pub fn run(renderer: &Renderer, op: Op<'_>) -> Result<Arc<GpuMesh>, RenderError> {
    run_into(renderer, op, None)
}

/// As [`run`], writing into `reuse` when it has the op's counts and layout
/// (particles redraw every frame: reusing their mesh halves the arena they
/// need), else into a new mesh.
pub fn run_into(
    renderer: &Renderer,
    op: Op<'_>,
    reuse: Option<&Arc<GpuMesh>>,
) -> Result<Arc<GpuMesh>, RenderError> {
    if op.input.is_some_and(|m| m.is_procedural()) {
        return Err(RenderError::Pass {
            pass: op.key.path().to_owned(),
            message: "particles are drawn procedurally, not stored as a mesh: a geometry pass cannot take them".to_owned(),
        });
    }
    let fits = |m: &&Arc<GpuMesh>| {
        m.vertices.len() == op.vertex_count as usize
            && m.indices.len() == op.index_count as usize
            && m.bounds == op.layout.bounds
            && m.has_uvs == op.layout.has_uvs
            && m.has_tangents == op.layout.has_tangents
    };
    let output = match reuse.filter(fits) {
        Some(m) => m.clone(),
        None => {
            renderer
                .meshes
                .allocate(&renderer.gpu, op.vertex_count, op.index_count, op.layout)?
        }
    };
    let previous = op
        .previous
        .filter(|p| p.vertices.len() == output.vertices.len());
    let job = GpuJob {
        src_vertex: op.input.map_or(0, |m| m.vertices.start),
        src_index: op.input.map_or(0, |m| m.indices.start),
        dst_vertex: output.vertices.start,
        dst_index: output.indices.start,
        vertex_count: op.vertex_count,
        index_count: op.index_count,
        previous_vertex: previous.map_or(0, |p| p.vertices.start),
        has_previous: u32::from(previous.is_some()),
        src_vertex_count: op.input.map_or(0, |m| m.vertices.len() as u32),
        src_index_count: op.input.map_or(0, |m| m.indices.len() as u32),
        _pad: [0; 2],
    };
    let arena = ArenaStreams::of(renderer);
    let job = uniform(renderer, "geometry job", bytemuck::bytes_of(&job));
    let params = (!op.params.is_empty()).then(|| uniform(renderer, "geometry params", op.params));
    let mut resources = arena.bindings([("job", job.as_entire_binding())]);
    resources.extend(params.as_ref().map(|p| ("params", p.as_entire_binding())));
    resources.extend(op.extra);
    dispatch(renderer, &op.key, resources, op.threads)?;
    Ok(output)
}

/// The mesh arena's streams every geometry pass binds (shaders/lib/geometry.wgsl),
/// taken after the pass's allocations: one may have grown the arena.
pub(crate) struct ArenaStreams {
    vertices: wgpu::Buffer,
    extras: wgpu::Buffer,
    indices: wgpu::Buffer,
}

impl ArenaStreams {
    pub(crate) fn of(renderer: &Renderer) -> ArenaStreams {
        let (vertices, indices, _) = renderer.meshes.buffers();
        ArenaStreams {
            vertices,
            extras: renderer.meshes.extras(),
            indices,
        }
    }

    /// The streams by the names the geometry library declares, then `more`.
    pub(crate) fn bindings<'a>(
        &'a self,
        more: impl IntoIterator<Item = (&'a str, wgpu::BindingResource<'a>)>,
    ) -> Vec<(&'a str, wgpu::BindingResource<'a>)> {
        let mut resources = vec![
            ("vertices", self.vertices.as_entire_binding()),
            ("extras", self.extras.as_entire_binding()),
            ("indices", self.indices.as_entire_binding()),
        ];
        resources.extend(more);
        resources
    }
}

/// A uniform buffer holding `bytes`.
pub(crate) fn uniform(renderer: &Renderer, label: &str, bytes: &[u8]) -> wgpu::Buffer {
    renderer
        .gpu
        .device
        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(label),
            contents: bytes,
            usage: wgpu::BufferUsages::UNIFORM,
        })
}

/// Records and submits one dispatch of `key`'s `main` over `threads`
/// invocations with `resources` bound by WGSL variable name (those the
/// permutation compiled out are dropped), inside a validation scope: a
/// broken pass is an error, not a broken frame. Counted in [`GeometryStats`].
pub(crate) fn dispatch(
    renderer: &Renderer,
    key: &ShaderKey,
    resources: Vec<(&str, wgpu::BindingResource<'_>)>,
    threads: u32,
) -> Result<(), RenderError> {
    dispatch_as(renderer, key, resources, threads, Work::Geometry)
}

/// The steps of a multi-pass operation, in order: one [`dispatch`] per
/// (permutation, threads), each binding the arena's streams
/// ([`ArenaStreams`]) and `bindings`, by name.
pub(crate) fn dispatch_steps(
    renderer: &Renderer,
    steps: &[(ShaderKey, u32)],
    bindings: &[(&str, &wgpu::Buffer)],
) -> Result<(), RenderError> {
    let arena = ArenaStreams::of(renderer);
    for (key, threads) in steps {
        let resources = arena.bindings(
            bindings
                .iter()
                .map(|(b, buf)| (*b, buf.as_entire_binding())),
        );
        dispatch(renderer, key, resources, *threads)?;
    }
    Ok(())
}

/// [`dispatch`], counted and timed as `work`.
pub(crate) fn dispatch_as(
    renderer: &Renderer,
    key: &ShaderKey,
    resources: Vec<(&str, wgpu::BindingResource<'_>)>,
    threads: u32,
    work: Work,
) -> Result<(), RenderError> {
    let gpu = &renderer.gpu;
    let device = &gpu.device;
    let stats = GeometryStats::of(renderer);
    let timer = (stats.timing.load(Ordering::Relaxed) && gpu.has_timestamps()).then(|| {
        let free = stats.free.lock().unwrap_or_else(|e| e.into_inner()).pop();
        free.unwrap_or_else(|| Timer::new(device))
    });
    let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
    let recorded = (|| {
        let mut shaders = renderer.shaders();
        let pipeline = shaders.compute_pipeline(device, key, "main")?;
        let groups = shaders.named_groups(
            device,
            key,
            &["main"],
            &crate::shaders::PipelineRef::Compute(pipeline.clone()),
            &resources,
            &[],
        )?;
        drop(shaders);
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some(key.path()),
        });
        {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some(key.path()),
                timestamp_writes: timer.as_ref().map(|t| wgpu::ComputePassTimestampWrites {
                    query_set: &t.set,
                    beginning_of_pass_write_index: Some(0),
                    end_of_pass_write_index: Some(1),
                }),
            });
            pass.set_pipeline(&pipeline);
            for (i, group) in groups.iter().enumerate() {
                pass.set_bind_group(i as u32, group, &[]);
            }
            let (x, y) = workgroups(threads);
            pass.dispatch_workgroups(x, y, 1);
        }
        if let Some(t) = &timer {
            encoder.resolve_query_set(&t.set, 0..2, &t.resolve, 0);
            encoder.copy_buffer_to_buffer(&t.resolve, 0, &t.readback, 0, 16);
        }
        Ok::<_, RenderError>(encoder.finish())
    })();
    let validation = pollster::block_on(scope.pop());
    match (recorded, validation) {
        (Err(e), _) => Err(e),
        (Ok(_), Some(e)) => Err(RenderError::Validation {
            pass: key.path().to_owned(),
            message: e.to_string(),
        }),
        (Ok(commands), None) => {
            gpu.submit([commands]);
            stats.count();
            if work == Work::Skinning {
                stats.skinning.fetch_add(1, Ordering::Relaxed);
            }
            if let Some(t) = timer {
                stats
                    .pending
                    .lock()
                    .unwrap_or_else(|e| e.into_inner())
                    .push((t, work));
            }
            Ok(())
        }
    }
}

/// Workgroups of 64 for `threads` invocations, spread over x and y so that
/// neither exceeds the 65,535 a dimension allows.
pub(crate) fn workgroups(threads: u32) -> (u32, u32) {
    let groups = threads.div_ceil(64).max(1);
    let x = groups.min(65_535);
    (x, groups.div_ceil(x))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn workgroups_cover_every_thread_within_the_limits() {
        for threads in [0, 1, 64, 65, 4_194_240, 4_194_241, 10_000_000, u32::MAX] {
            let (x, y) = workgroups(threads);
            assert!(x <= 65_535 && y <= 65_535, "{threads}: {x} x {y}");
            assert!(u64::from(x) * u64::from(y) * 64 >= u64::from(threads));
        }
    }
}

/// The layout the shader sees (shaders/layout.rs).
#[cfg(test)]
mod wgsl_layout {
    use super::*;

    #[test]
    fn gpu_job_matches_job_in_the_shader() {
        crate::assert_wgsl_layout!(
            GpuJob,
            crate::geometry::spherize_key::SpherizeKey,
            [],
            "Job",
            [
                src_vertex,
                src_index,
                dst_vertex,
                dst_index,
                vertex_count,
                index_count,
                previous_vertex,
                has_previous,
                src_vertex_count,
                src_index_count,
                _pad
            ]
        );
    }
}
