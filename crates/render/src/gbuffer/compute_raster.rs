//! The compute rasterizer's resources and pass (shaders/gbuffer/raster.wgsl).
//!
//! It writes one of two kinds of word per pixel ([`Words`]): the G-buffer's
//! 64-bit visibility (depth and triangle id), or shadow maps' 32-bit depth
//! alone. The buffer of words lives here, sized to the frame, because the
//! frame graph manages textures; the raster pass writes an ordering token
//! that the resolves read, so culling and order still come from the graph.

use std::sync::Mutex;

use wgpu::util::DeviceExt;

use crate::adapter_class::AdapterClass;
use crate::error::RenderError;
use crate::frame_graph::PassContext;
use crate::renderer::Renderer;
use crate::shaders::{Permutation, ShaderKey};

use super::{Draw, GBuffer};

pub use super::compute_raster_key::RasterKey;

/// How many big-triangle tiles one frame can queue (16 bytes each).
const TILE_CAPACITY: u32 = 1 << 18;
/// Workgroups that stride over the queued tiles on a GPU: enough to fill
/// one however few tiles are queued.
const TILE_WORKGROUPS: u32 = 1024;
/// The most workgroups that stride over the queued tiles on a CPU adapter
/// (one per thread it runs them on, see `tile_workgroups`).
const CPU_TILE_WORKGROUPS: u32 = 64;
const WORKGROUP: u32 = 64;
/// A layered raster's tile list holds this many single lists' worth at
/// most (`record_layers`): room for what the layers would queue alone
/// where there are few, without a point light's dozens of faces taking
/// hundreds of megabytes.
const LAYERED_LISTS: u32 = 8;
/// On a GPU a layered raster strides over its tiles with this many times
/// [`TILE_WORKGROUPS`] at most: the layers' tiles were that many dispatches
/// of a thousand each, one after another.
const LAYERED_TILE_SPREAD: u32 = 4;

/// Matches `Batch` in raster.wgsl.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct GpuBatch {
    first_instance: u32,
    triangles: u32,
    instance_count: u32,
    first_global: u32,
    /// The mesh's bounding sphere (centre, radius) before its instances'
    /// transforms; a negative radius: none (particles), no instance culled.
    sphere: [f32; 4],
}

impl GpuBatch {
    /// `bounds`' sphere, or none where they are missing or not finite.
    fn sphere(bounds: Option<crate::mesh::Aabb>) -> [f32; 4] {
        match bounds {
            Some(b) if b.min.is_finite() && b.max.is_finite() => {
                let (c, r) = (b.center(), (b.size() * 0.5).length());
                if r.is_finite() {
                    [c.x, c.y, c.z, r]
                } else {
                    [0.0, 0.0, 0.0, -1.0]
                }
            }
            _ => [0.0, 0.0, 0.0, -1.0],
        }
    }
}

/// The most draws one dispatch rasterizes (`RUN_BATCHES` in raster.wgsl): a
/// run's uniform is 9 KB whatever it holds, made, compared with last frame's
/// and kept on every frame a recipe is made, so a scene of more draws takes
/// one dispatch per this many (four for a thousand glTF meshes).
const RUN_BATCHES: usize = 256;

/// Matches `Run` in raster.wgsl: draws rasterized in one dispatch, a thread
/// per triangle of each, one after another.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct GpuRun {
    batches: [GpuBatch; RUN_BATCHES],
    /// The run's first thread for each batch, ascending (four to a
    /// `vec4<u32>` in the shader, a uniform array's stride).
    first_threads: [u32; RUN_BATCHES],
    /// x: batches in the run.
    count: [u32; 4],
}

struct Targets {
    /// Bytes of words the buffer holds: a view of this many or fewer (a
    /// shadow map's scrolled strips, of every size) reuses it.
    capacity: u64,
    words: Words,
    visibility: wgpu::Buffer,
    tiles: wgpu::Buffer,
    tile_count: wgpu::Buffer,
    /// What `tile_count` starts each raster with (0 queued, the capacity),
    /// copied in the encoder so several rasters can share one.
    tile_reset: wgpu::Buffer,
    /// Entries the tile list holds.
    tile_capacity: u32,
}

impl Targets {
    /// The targets in `slot`, made again unless they fit `bytes` of `words`
    /// and `tile_capacity` tile entries, with the words a raster covers
    /// cleared (the buffer may be larger) and the tile count reset, in `cx`'s
    /// encoder: what every raster does first (one view, or all layers).
    fn ready<'t>(
        slot: &'t mut Option<Targets>,
        device: &wgpu::Device,
        cx: &mut PassContext<'_>,
        words: Words,
        bytes: u64,
        tile_capacity: u32,
    ) -> Result<&'t Targets, RenderError> {
        if slot
            .as_ref()
            .is_none_or(|t| !t.fits(words, bytes, tile_capacity))
        {
            *slot = Some(Targets::new(device, words, bytes, tile_capacity));
        }
        let Some(targets) = slot.as_ref() else {
            return Err(RenderError::Pass {
                pass: "compute raster".to_owned(),
                message: "no visibility buffer".to_owned(),
            });
        };
        cx.encoder()
            .clear_buffer(&targets.visibility, 0, Some(bytes));
        cx.encoder()
            .copy_buffer_to_buffer(&targets.tile_reset, 0, &targets.tile_count, 0, 16);
        Ok(targets)
    }

    /// Buffers for `bytes` of `words` and a tile list of `tile_capacity` entries.
    fn new(device: &wgpu::Device, words: Words, bytes: u64, tile_capacity: u32) -> Targets {
        let storage = |label: &str, bytes: u64| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: bytes,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        };
        Targets {
            capacity: bytes,
            words,
            visibility: storage(
                match words {
                    Words::Visibility64 => "visibility (64-bit)",
                    Words::Depth32 => "raster depth (32-bit)",
                },
                bytes,
            ),
            tiles: storage("raster tiles", u64::from(tile_capacity) * 16),
            tile_count: storage("raster tile count", 16),
            tile_reset: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("raster tile count reset"),
                contents: bytemuck::cast_slice(&[0u32, tile_capacity, 0, 0]),
                usage: wgpu::BufferUsages::COPY_SRC,
            }),
            tile_capacity,
        }
    }

    /// Whether these buffers hold `bytes` of `words` and `tile_capacity` tiles.
    fn fits(&self, words: Words, bytes: u64, tile_capacity: u32) -> bool {
        self.words == words && self.capacity >= bytes && self.tile_capacity == tile_capacity
    }
}

/// What the compute rasterizer writes per pixel.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Words {
    /// 64 bits: reversed-Z depth over the triangle's id + 1 (atomicMax on
    /// u64; the adapter needs SHADER_INT64_ATOMIC_MIN_MAX). The G-buffer.
    Visibility64,
    /// 32 bits: reversed-Z depth alone (atomicMax on u32, which any adapter
    /// has: DEPTH_ONLY in raster.wgsl). Shadow maps, which need no id.
    Depth32,
}

impl Words {
    fn bytes(self) -> u64 {
        match self {
            Words::Visibility64 => 8,
            Words::Depth32 => 4,
        }
    }
}

/// What the compute rasterizer draws from and where: the camera uniform
/// (its reversed-Z view-projection and size), the instances, and the target size.
pub(crate) struct RasterView<'b> {
    pub camera: &'b wgpu::Buffer,
    pub instances: &'b wgpu::Buffer,
    pub size: (u32, u32),
    /// Back faces too (shadow maps); the G-buffer culls them.
    pub two_sided: bool,
}

/// The rasterizer's buffers, kept by the renderer under the owning node
/// (`Renderer::state`), so a recipe made again each frame (a moving camera)
/// reuses them instead of allocating 16 MB at 1080p every frame.
#[derive(Default)]
pub(crate) struct RasterTargets(Mutex<Option<Targets>>);

/// A layered raster's buffers ([`ComputeRaster::record_layers`]), kept
/// under the node apart from a single view's: its words and tile list hold
/// every layer's.
#[derive(Default)]
pub(crate) struct LayeredTargets(Mutex<Option<Targets>>);

/// What a layered raster draws: every layer's camera (an array of
/// `Camera`), where each layer's words start (`layer_words` in
/// raster.wgsl), how many layers and words there are in all, and the
/// instances. Back faces are kept (shadow maps).
pub(crate) struct LayeredView<'b> {
    pub cameras: &'b wgpu::Buffer,
    pub layer_words: &'b wgpu::Buffer,
    pub layers: u32,
    pub words: u64,
    pub instances: &'b wgpu::Buffer,
}

/// Draws rasterized in one dispatch: its uniform ([`GpuRun`]), how many
/// triangles it rasterizes (all its draws' instances), how many draws it
/// holds, whether they are particles (procedural) and whether they keep
/// back faces (double-sided materials). Draws share a run where they share
/// a pipeline and a side of `between`: a dispatch a draw made a scene of a
/// thousand glTF meshes a thousand dispatches, each waiting on a barrier
/// for the one before it (2.6 ms on the H200 for 224,000 triangles).
#[derive(Clone)]
struct Run {
    uniform: wgpu::Buffer,
    total: u32,
    draws: u64,
    procedural: bool,
    two_sided: bool,
}

/// A [`Run`] ready to dispatch this frame.
struct RunGroup<'p> {
    pipeline: &'p wgpu::ComputePipeline,
    groups: crate::frame_graph::BindGroups,
    total: u32,
    draws: u64,
    procedural: bool,
}

/// The names a rasterizer's kept buffers go by under its node: a node with
/// several rasterizers (a shadow node's caster sets) gives each its own, so
/// one does not overwrite another's in the same frame.
#[derive(Clone, Copy, Debug)]
pub(crate) struct RasterLabels {
    pub run: &'static str,
    pub first_triangle: &'static str,
}

impl RasterLabels {
    pub const G_BUFFER: RasterLabels = RasterLabels {
        run: "raster run",
        first_triangle: "first triangle per instance",
    };
}

pub(crate) struct ComputeRaster {
    /// The draws with triangles, in runs of one dispatch each.
    runs: Vec<Run>,
    words: Words,
    pub first_triangle: wgpu::Buffer,
    targets: std::sync::Arc<RasterTargets>,
    /// The node keeping the buffers (a layered raster finds its own under it).
    owner: Option<u32>,
}

impl ComputeRaster {
    /// `owner`: the node whose recipes share the raster buffers across
    /// frames, under `labels`.
    pub(crate) fn new(
        renderer: &Renderer,
        owner: Option<u32>,
        labels: RasterLabels,
        words: Words,
        draws: &[Draw],
        instance_count: usize,
    ) -> Self {
        // Each draw's first triangle id: the raster's words and the
        // resolve's lookup (`first_triangle`) number triangles alike.
        let firsts = first_ids(draws);
        let mut first_triangle = vec![0u32; instance_count.max(1)];
        for (draw, &first) in draws.iter().zip(&firsts) {
            let triangles = draw.index_count / 3;
            for k in 0..draw.instance_count {
                first_triangle[(draw.first_instance + k) as usize] = first + k * triangles;
            }
        }
        // The same draws as last time make the same runs: taken from the
        // node's memo, not built and compared again (a run's uniform is
        // 9 KB, and recipes are made every frame something upstream moves).
        let runs = match owner {
            Some(node) => {
                let memo = renderer.state::<KeptRuns>(u64::from(node));
                let mut memo = memo.0.lock().unwrap_or_else(|e| e.into_inner());
                match memo.get(labels.run) {
                    Some((last, runs)) if last.as_slice() == draws => runs.clone(),
                    _ => {
                        let runs = make_runs(renderer, owner, labels, draws, &firsts);
                        memo.insert(labels.run, (draws.to_vec(), runs.clone()));
                        runs
                    }
                }
            }
            None => make_runs(renderer, owner, labels, draws, &firsts),
        };
        let first_triangle = renderer.kept_init(
            owner,
            labels.first_triangle,
            bytemuck::cast_slice(&first_triangle),
            wgpu::BufferUsages::STORAGE,
        );
        ComputeRaster {
            runs,
            words,
            first_triangle,
            targets: match owner {
                Some(owner) => renderer.state::<RasterTargets>(u64::from(owner)),
                None => std::sync::Arc::default(),
            },
            owner,
        }
    }

    /// Announce the pipelines [`Self::record_view`] dispatches for a view
    /// that keeps back faces where `two_sided_view` (shadow maps) or per
    /// draw (the G-buffer's) (frame_graph/gather.rs): the same keys and
    /// entry points, known from the batches when the recipe is declared, so
    /// a first frame makes them on threads instead of in the pass.
    /// `layered`: the pipelines of [`Self::record_layers`].
    pub(crate) fn announce(
        &self,
        renderer: &Renderer,
        fg: &mut crate::frame_graph::FrameGraph<'_>,
        two_sided_view: bool,
        layered: bool,
    ) {
        if !fg.gathers_pipelines() {
            return;
        }
        let particles = self.runs.iter().any(|r| r.procedural);
        let class = renderer.gpu.adapter_class();
        let key = |two_sided: bool| {
            RasterKey {
                layered,
                ..raster_flags(class, two_sided, particles, self.words)
            }
            .key()
        };
        let mut sides = [false; 2];
        for run in &self.runs {
            sides[usize::from(two_sided_view || run.two_sided)] = true;
        }
        for sided in [false, true] {
            if sides[usize::from(sided)] {
                fg.will_dispatch(&key(sided), "raster_triangles");
            }
        }
        fg.will_dispatch(&key(sides[1] || two_sided_view), "raster_tiles");
    }

    /// The visibility buffer of the last frame this G-buffer rasterized.
    pub fn visibility(&self) -> Option<wgpu::Buffer> {
        self.targets
            .0
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .as_ref()
            .map(|t| t.visibility.clone())
    }

    pub fn record(
        &self,
        g: &GBuffer,
        renderer: &Renderer,
        cx: &mut PassContext<'_>,
    ) -> Result<(), RenderError> {
        let size = g.pixel_size(cx.output_size);
        let view = RasterView {
            camera: g.camera_buffer(),
            instances: &g.instances,
            size,
            // Per draw: each keeps its back faces only if its material asks.
            two_sided: false,
        };
        match g.published_depth() {
            Some(name) => {
                let view_projection = g.camera.view_projection();
                let mut publish = |cx: &mut PassContext<'_>, visibility: &wgpu::Buffer| {
                    super::published_depth::publish(
                        renderer,
                        cx,
                        name,
                        super::published_depth::DepthSource::Compute(visibility),
                        size,
                        view_projection,
                    )
                };
                self.record_view(&view, renderer, cx, Some(&mut publish))?;
            }
            None => {
                self.record_view(&view, renderer, cx, None)?;
            }
        }
        Ok(())
    }

    /// Rasterize into the buffer of words for `view`, which this returns (a
    /// caller may record several views in a row: each clears it first).
    /// `between`: run after the meshes and before the particles (procedural
    /// draws), given the buffer: what publishes a depth without particles.
    pub(crate) fn record_view(
        &self,
        view: &RasterView<'_>,
        renderer: &Renderer,
        cx: &mut PassContext<'_>,
        between: Option<Between<'_>>,
    ) -> Result<wgpu::Buffer, RenderError> {
        let device = cx.gpu.device.clone();
        let size = view.size;
        let mut guard = self.targets.0.lock().unwrap_or_else(|e| e.into_inner());
        let words = self.words;
        let needed = (u64::from(size.0) * u64::from(size.1) * words.bytes()).max(words.bytes());
        let targets = Targets::ready(&mut guard, &device, cx, words, needed, TILE_CAPACITY)?;

        // Back faces kept per draw (double-sided materials) or for all (shadow maps).
        // On a CPU adapter a raster with no particle system fetches its
        // corners without the particle path (MESHES_ONLY, adapter_class.rs);
        // a GPU keeps the one shader it always ran.
        let particles = self.runs.iter().any(|r| r.procedural);
        let class = cx.gpu.adapter_class();
        let key = |two_sided: bool| raster_key(class, two_sided, particles, words);
        let mut triangle_pipelines: [Option<wgpu::ComputePipeline>; 2] = [None, None];
        for run in &self.runs {
            let sided = view.two_sided || run.two_sided;
            if triangle_pipelines[usize::from(sided)].is_none() {
                triangle_pipelines[usize::from(sided)] =
                    Some(cx.compute_pipeline(&key(sided), "raster_triangles")?);
            }
        }
        // Big triangles queued as tiles are set up again there: with back
        // faces turned around when any draw queued some (a front face is
        // rasterized the same either way).
        let any_two_sided = triangle_pipelines[1].is_some() || view.two_sided;
        let tiles_pipeline = cx.compute_pipeline(&key(any_two_sided), "raster_tiles")?;
        let (vertices, indices, _) = renderer.meshes.buffers();
        // The same buffers every frame (kept under the node): the groups are cached.
        let groups_of = |cx: &mut PassContext<'_>,
                         sided: bool,
                         entry: &str,
                         pipeline: &wgpu::ComputePipeline,
                         run: Option<&wgpu::Buffer>| {
            let b = super::mesh_bindings(&vertices, &indices, view.instances)
                .buffer("camera", view.camera)
                .buffer("visibility", &targets.visibility)
                .buffer("tiles", &targets.tiles)
                .buffer("tile_count", &targets.tile_count)
                .buffer_opt("run", run);
            cx.bind_groups(&key(sided), entry, pipeline, b)
        };
        let mut run_groups: Vec<RunGroup<'_>> = Vec::with_capacity(self.runs.len());
        for r in &self.runs {
            let sided = view.two_sided || r.two_sided;
            let Some(pipeline) = triangle_pipelines[usize::from(sided)].as_ref() else {
                continue;
            };
            run_groups.push(RunGroup {
                pipeline,
                groups: groups_of(cx, sided, "raster_triangles", pipeline, Some(&r.uniform))?,
                total: r.total,
                draws: r.draws,
                procedural: r.procedural,
            });
        }
        let tiles_groups = groups_of(cx, any_two_sided, "raster_tiles", &tiles_pipeline, None)?;
        let tiles = (&tiles_pipeline, tiles_groups.as_slice());
        match between {
            None => {
                let all: Vec<_> = run_groups.iter().collect();
                raster_runs(cx, tiles, &all, 1);
            }
            Some(between) => {
                let (particles, meshes): (Vec<_>, Vec<_>) =
                    run_groups.iter().partition(|r| r.procedural);
                raster_runs(cx, tiles, &meshes, 1);
                between(cx, &targets.visibility)?;
                if !particles.is_empty() {
                    cx.encoder().copy_buffer_to_buffer(
                        &targets.tile_reset,
                        0,
                        &targets.tile_count,
                        0,
                        16,
                    );
                    raster_runs(cx, tiles, &particles, 1);
                }
            }
        }
        Ok(targets.visibility.clone())
    }

    /// Rasterize every layer of `view` in one chain (LAYERED in
    /// raster.wgsl): one clear of all layers' words, one reset of the tile
    /// list, each run's triangles dispatched once with the layer as
    /// workgroup_id.z, one tile kernel over every layer's big triangles.
    /// Each layer's words get the atomics a [`Self::record_view`] of it
    /// alone gives them (the same triangles set up through the same camera),
    /// so they hold the same depth; layer k's start at `layer_words[k]` of
    /// the buffer this returns. Back faces are kept (shadow maps). The tile
    /// list holds [`LAYERED_LISTS`] single lists at most: a frame whose
    /// layers queue more big-triangle tiles than that drops the rest, where
    /// a layer alone drops what passes one list.
    pub(crate) fn record_layers(
        &self,
        view: &LayeredView<'_>,
        renderer: &Renderer,
        cx: &mut PassContext<'_>,
    ) -> Result<wgpu::Buffer, RenderError> {
        let device = cx.gpu.device.clone();
        let words = self.words;
        let needed = (view.words * words.bytes()).max(words.bytes());
        let tile_capacity = TILE_CAPACITY * view.layers.clamp(1, LAYERED_LISTS);
        let state = match self.owner {
            Some(owner) => renderer.state::<LayeredTargets>(u64::from(owner)),
            None => std::sync::Arc::default(),
        };
        let mut guard = state.0.lock().unwrap_or_else(|e| e.into_inner());
        let targets = Targets::ready(&mut guard, &device, cx, words, needed, tile_capacity)?;
        let particles = self.runs.iter().any(|r| r.procedural);
        let class = cx.gpu.adapter_class();
        let key = RasterKey {
            layered: true,
            ..raster_flags(class, true, particles, words)
        }
        .key();
        let triangles = cx.compute_pipeline(&key, "raster_triangles")?;
        let tiles_pipeline = cx.compute_pipeline(&key, "raster_tiles")?;
        let (vertices, indices, _) = renderer.meshes.buffers();
        let groups_of = |cx: &mut PassContext<'_>,
                         entry: &str,
                         pipeline: &wgpu::ComputePipeline,
                         run: Option<&wgpu::Buffer>| {
            let b = super::mesh_bindings(&vertices, &indices, view.instances)
                .buffer("cameras", view.cameras)
                .buffer("layer_words", view.layer_words)
                .buffer("visibility", &targets.visibility)
                .buffer("tiles", &targets.tiles)
                .buffer("tile_count", &targets.tile_count)
                .buffer_opt("run", run);
            cx.bind_groups(&key, entry, pipeline, b)
        };
        let mut run_groups: Vec<RunGroup<'_>> = Vec::with_capacity(self.runs.len());
        for r in &self.runs {
            run_groups.push(RunGroup {
                pipeline: &triangles,
                groups: groups_of(cx, "raster_triangles", &triangles, Some(&r.uniform))?,
                total: r.total,
                draws: r.draws,
                procedural: r.procedural,
            });
        }
        let tiles_groups = groups_of(cx, "raster_tiles", &tiles_pipeline, None)?;
        let all: Vec<_> = run_groups.iter().collect();
        raster_runs(
            cx,
            (&tiles_pipeline, tiles_groups.as_slice()),
            &all,
            view.layers.max(1),
        );
        Ok(targets.visibility.clone())
    }
}

/// The first triangle id of each of `draws`: the triangles of all
/// instances of the draws before it.
fn first_ids(draws: &[Draw]) -> Vec<u32> {
    let mut global = 0u32;
    draws
        .iter()
        .map(|draw| {
            let first = global;
            let triangles = draw.index_count / 3;
            global = global.saturating_add(triangles.saturating_mul(draw.instance_count));
            first
        })
        .collect()
}

/// `draws`' runs: those that share a pipeline (back faces kept or not) and
/// a side of `between` (meshes or particles) together, in draw order, up to
/// [`RUN_BATCHES`] a run, each run's uniform kept under `owner` by `labels`.
/// `firsts`: each draw's first triangle id ([`first_ids`]).
fn make_runs(
    renderer: &Renderer,
    owner: Option<u32>,
    labels: RasterLabels,
    draws: &[Draw],
    firsts: &[u32],
) -> Vec<Run> {
    // Runs being filled, by (back faces kept, particles), in the order
    // each kind first appears; a full run is closed and another opened.
    let mut open: Vec<((bool, bool), GpuRun, u32)> = Vec::new();
    let mut closed: Vec<((bool, bool), GpuRun, u32)> = Vec::new();
    for (draw, &first) in draws.iter().zip(firsts) {
        let triangles = draw.index_count / 3;
        let total = triangles.saturating_mul(draw.instance_count);
        if total > 0 {
            let kind = (draw.two_sided, draw.procedural);
            let at = match open.iter().position(|(k, _, _)| *k == kind) {
                Some(at) if (open[at].1.count[0] as usize) < RUN_BATCHES => at,
                full => {
                    if let Some(at) = full {
                        closed.push(open.remove(at));
                    }
                    open.push((kind, bytemuck::Zeroable::zeroed(), 0));
                    open.len() - 1
                }
            };
            let (_, run, threads) = &mut open[at];
            let n = run.count[0] as usize;
            run.batches[n] = GpuBatch {
                first_instance: draw.first_instance,
                triangles,
                instance_count: draw.instance_count,
                first_global: first,
                sphere: GpuBatch::sphere(draw.bounds),
            };
            run.first_threads[n] = *threads;
            run.count[0] += 1;
            *threads = threads.saturating_add(total);
        }
    }
    closed.extend(open);
    closed
        .into_iter()
        .enumerate()
        .map(|(i, ((two_sided, procedural), run, total))| Run {
            // Kept under the node, one per run: the same buffers (and
            // bind groups) every frame the draws stay the same.
            uniform: renderer.kept_init_at(
                owner,
                labels.run,
                i as u32,
                bytemuck::bytes_of(&run),
                wgpu::BufferUsages::UNIFORM,
            ),
            total,
            draws: u64::from(run.count[0]),
            procedural,
            two_sided,
        })
        .collect()
}

/// A node's runs as last made, by label (a node with several rasterizers,
/// a shadow node's caster sets, keeps each apart), with the draws they were
/// made from.
#[derive(Default)]
struct KeptRuns(Mutex<std::collections::HashMap<&'static str, MadeRuns>>);

/// Runs and the draws they were made from.
type MadeRuns = (Vec<Draw>, Vec<Run>);

/// What runs between a raster's meshes and its particles.
pub(crate) type Between<'b> =
    &'b mut dyn FnMut(&mut PassContext<'_>, &wgpu::Buffer) -> Result<(), RenderError>;

/// The raster's permutation on a `class` adapter: back faces kept or not,
/// on a CPU adapter, where no draw is a particle system, corner positions
/// fetched alone (MESHES_ONLY, adapter_class.rs), and 32-bit depth words.
fn raster_key(class: AdapterClass, two_sided: bool, particles: bool, words: Words) -> ShaderKey {
    raster_flags(class, two_sided, particles, words).key()
}

/// [`raster_key`]'s switches, one layer at a time.
fn raster_flags(class: AdapterClass, two_sided: bool, particles: bool, words: Words) -> RasterKey {
    let meshes_only = class == AdapterClass::Cpu && !particles;
    RasterKey {
        two_sided,
        meshes_only,
        depth_only: words == Words::Depth32,
        layered: false,
    }
}

/// How many workgroups stride over the queued tiles on a `class` adapter
/// whose host has `cpu_threads` threads. A GPU runs its thousand side by
/// side. A CPU adapter (llvmpipe) runs them a few at a time, one a thread,
/// and a workgroup that finds no tile still goes through its whole kernel
/// there (llvmpipe steps every row of lanes through both sides of each
/// branch): the thousand cost gbuffer-spheres' raster 75-230 ms a frame at
/// 160x90, a few 1 ms (docs/benchmarks.md, "lavapipe"). One a thread keeps
/// every thread busy. Every workgroup strides over the queue, so any count
/// draws the same words.
fn tile_workgroups(class: AdapterClass, cpu_threads: usize) -> u32 {
    match class {
        AdapterClass::Gpu => TILE_WORKGROUPS,
        AdapterClass::Cpu => u32::try_from(cpu_threads)
            .map_or(CPU_TILE_WORKGROUPS, |t| t.clamp(1, CPU_TILE_WORKGROUPS)),
    }
}

/// The threads a CPU adapter runs workgroups on: llvmpipe starts one per core.
/// Asked once a process: on Linux `available_parallelism` reads the cgroup's
/// quota files, tens of microseconds that every raster view (the G-buffer's,
/// each shadow cascade's) paid on every frame (docs/benchmarks.md, session 17).
fn cpu_threads() -> usize {
    static THREADS: std::sync::OnceLock<usize> = std::sync::OnceLock::new();
    *THREADS.get_or_init(|| std::thread::available_parallelism().map_or(1, |n| n.get()))
}

/// `runs`' triangles, then the big triangles' tiles, in the open compute
/// pass; `layers` of them where the raster is layered (the triangles'
/// workgroup_id.z), 1 otherwise. Counts the runs' draws.
fn raster_runs(
    cx: &mut PassContext<'_>,
    (tiles, tiles_groups): (&wgpu::ComputePipeline, &[wgpu::BindGroup]),
    runs: &[&RunGroup<'_>],
    layers: u32,
) {
    let class = cx.gpu.adapter_class();
    let tile_workgroups = tile_workgroups(class, cpu_threads())
        * match class {
            // Every workgroup strides over the whole list, so any count
            // draws the same words.
            AdapterClass::Gpu => layers.clamp(1, LAYERED_TILE_SPREAD),
            // One a thread already keeps every thread busy.
            AdapterClass::Cpu => 1,
        };
    let pass = cx.compute_pass("compute raster");
    let mut draws = 0;
    for r in runs {
        pass.set_pipeline(r.pipeline);
        let workgroups = r.total.div_ceil(WORKGROUP);
        // Over 65,535 workgroups spill into y; the shader folds y back into one index.
        let x = workgroups.min(65_535);
        for (i, group) in r.groups.iter().enumerate() {
            pass.set_bind_group(i as u32, group, &[]);
        }
        pass.dispatch_workgroups(x, workgroups.div_ceil(x), layers);
        draws += r.draws;
    }
    pass.set_pipeline(tiles);
    for (i, group) in tiles_groups.iter().enumerate() {
        pass.set_bind_group(i as u32, group, &[]);
    }
    pass.dispatch_workgroups(tile_workgroups, 1, 1);
    cx.draws += draws;
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_gpu_strides_over_the_tiles_with_a_thousand_workgroups_a_cpu_adapter_with_one_a_thread() {
        // The GPU's count does not depend on the host.
        for threads in [1, 2, 16, 256] {
            assert_eq!(tile_workgroups(AdapterClass::Gpu, threads), 1024);
        }
        // A CPU adapter: one a thread, never none, never a GPU's thousand.
        assert_eq!(tile_workgroups(AdapterClass::Cpu, 0), 1);
        assert_eq!(tile_workgroups(AdapterClass::Cpu, 1), 1);
        assert_eq!(tile_workgroups(AdapterClass::Cpu, 2), 2);
        assert_eq!(tile_workgroups(AdapterClass::Cpu, 16), 16);
        assert_eq!(tile_workgroups(AdapterClass::Cpu, 256), 64);
        assert_eq!(tile_workgroups(AdapterClass::Cpu, usize::MAX), 64);
    }

    /// The layered raster (shadow maps' layers in one chain) composes and
    /// validates with every other switch, as the single-view one does.
    #[test]
    fn every_raster_permutation_composes_layered_or_not() {
        let mut composer = crate::shaders::ShaderComposer::new().expect("libraries compose");
        let all = RasterKey::all();
        assert_eq!(all.len(), 16);
        for key in all {
            let module = composer
                .compose(&key.key())
                .unwrap_or_else(|e| panic!("{key:?}: {e}"));
            naga::valid::Validator::new(
                naga::valid::ValidationFlags::all(),
                naga::valid::Capabilities::all(),
            )
            .validate(&module)
            .unwrap_or_else(|e| panic!("{key:?}: {e}"));
        }
    }

    #[test]
    fn a_cpu_adapter_fetches_positions_alone_where_no_draw_is_a_particle_system() {
        for two_sided in [false, true] {
            let key = |meshes_only, depth_only| {
                RasterKey {
                    two_sided,
                    meshes_only,
                    depth_only,
                    layered: false,
                }
                .key()
            };
            // A GPU keeps the shader it always ran, particles or not.
            assert_eq!(
                raster_key(AdapterClass::Gpu, two_sided, false, Words::Visibility64),
                key(false, false)
            );
            assert_eq!(
                raster_key(AdapterClass::Gpu, two_sided, true, Words::Visibility64),
                key(false, false)
            );
            assert_eq!(
                raster_key(AdapterClass::Cpu, two_sided, false, Words::Visibility64),
                key(true, false)
            );
            // Particles need the procedural path.
            assert_eq!(
                raster_key(AdapterClass::Cpu, two_sided, true, Words::Visibility64),
                key(false, false)
            );
            // Shadow maps' 32-bit depth words are a permutation of their own.
            assert_eq!(
                raster_key(AdapterClass::Gpu, two_sided, true, Words::Depth32),
                key(false, true)
            );
        }
    }
}

/// The layout the shader sees (shaders/layout.rs).
#[cfg(test)]
mod wgsl_layout {
    use super::*;

    #[test]
    fn gpu_batch_matches_batch_in_the_shader() {
        crate::assert_wgsl_layout!(
            GpuBatch,
            crate::gbuffer::compute_raster_key::RasterKey,
            [],
            "Batch",
            [
                first_instance,
                triangles,
                instance_count,
                first_global,
                sphere
            ]
        );
    }

    #[test]
    fn gpu_run_matches_run_in_the_shader() {
        crate::assert_wgsl_layout!(
            GpuRun,
            crate::gbuffer::compute_raster_key::RasterKey,
            [],
            "Run",
            [batches, first_threads, count]
        );
    }
}
