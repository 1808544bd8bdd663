//! The renderer: the shared GPU context plus what lives across frames: the
//! shader permutation cache, the texture pool, persistent textures, the mesh
//! arena, the timestamp queries, and the last frame's report.
//!
//! Nodes hold it behind an `Arc` and call it from their evaluation; its
//! interior state is behind mutexes so it is shared, not cloned.

use rustc_hash::FxHashMap;
use std::sync::{Arc, Mutex};

use crate::context::GpuContext;
use crate::error::RenderError;
use crate::frame_graph::Finisher;
use crate::mesh_arena::MeshArena;
use crate::report::FrameReport;
use crate::shaders::{ShaderCache, ShaderComposer};
use crate::texture_pool::TexturePool;

mod kept;

use kept::{KeptBuffer, KeptKey, Uploads};

pub(crate) const MAX_QUERIES: u32 = 512;

pub(crate) struct Timestamps {
    pub set: wgpu::QuerySet,
    pub resolve: wgpu::Buffer,
    pub readback: wgpu::Buffer,
}

/// How frames are timed (`FrameGraph::execute`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Timing {
    /// Timestamps around every pass, read back after each frame: the
    /// per-pass figures of `stats` and `bench`. The CPU waits for the GPU.
    #[default]
    PerPass,
    /// Timestamps at the first and the last pass only: the frame's GPU span.
    Frame,
    /// No timestamps and no waiting: frames overlap (recorded while the GPU
    /// works on the last), as an interactive host runs them.
    Off,
}

/// How passes are recorded (`FrameGraph::execute`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Recording {
    /// Each pass in its own command encoder and error scope: an error names its pass.
    #[default]
    Isolated,
    /// The whole frame in a few command encoders (`FRAME_CHUNKS` runs of
    /// passes, finished beside the recording); an error drops the frame and
    /// switches to `Isolated`.
    Batched,
}

/// Frame graphs a persistent texture may go unwritten before it is dropped:
/// about a second at 60 frames a second, so a node briefly culled (an editor
/// viewport looking elsewhere) keeps its history.
pub const PERSISTENT_IDLE_GRAPHS: u32 = 60;

pub struct Renderer {
    pub gpu: GpuContext,
    shaders: Mutex<ShaderCache>,
    textures: Mutex<TexturePool>,
    pub meshes: MeshArena,
    timestamps: Option<Timestamps>,
    settings: Mutex<(Timing, Recording)>,
    /// Submissions not yet known to be done, oldest first (`Timing::Off`).
    in_flight: Mutex<std::collections::VecDeque<wgpu::SubmissionIndex>>,
    last_report: Mutex<FrameReport>,
    output_size: Mutex<(u32, u32)>,
    /// Buffers recipes keep across their re-creation, by owner node and label
    /// (`Renderer::uniform`, `Renderer::kept_buffer`), with a uniform's last contents.
    kept: Mutex<FxHashMap<KeptKey, KeptBuffer>>,
    /// Kept-buffer writes made and skipped since the last frame graph ran.
    uploads: Mutex<Uploads>,
    /// What recipes keep between frames (shadow maps), by type and key.
    states: Mutex<FxHashMap<(std::any::TypeId, u64), Arc<dyn std::any::Any + Send + Sync>>>,
    /// The thread that finishes a batched frame's encoders beside its recording.
    finisher: Finisher,
}

/// The output size until a host sets one.
pub const DEFAULT_OUTPUT_SIZE: (u32, u32) = (640, 360);

impl Renderer {
    pub fn new(gpu: GpuContext) -> Result<Self, RenderError> {
        let shaders = ShaderCache::new(ShaderComposer::new()?);
        let timestamps = gpu.has_timestamps().then(|| Timestamps {
            set: gpu.device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("pass timestamps"),
                ty: wgpu::QueryType::Timestamp,
                count: MAX_QUERIES,
            }),
            resolve: gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("timestamp resolve"),
                size: u64::from(MAX_QUERIES) * 8,
                usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            }),
            readback: gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("timestamp readback"),
                size: u64::from(MAX_QUERIES) * 8,
                usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
        });
        let meshes = MeshArena::new(&gpu);
        let finisher = Finisher::new(gpu.device.clone());
        Ok(Renderer {
            gpu,
            shaders: Mutex::new(shaders),
            textures: Mutex::new(TexturePool::default()),
            meshes,
            timestamps,
            settings: Mutex::new((Timing::default(), Recording::default())),
            in_flight: Mutex::new(std::collections::VecDeque::new()),
            last_report: Mutex::new(FrameReport::default()),
            output_size: Mutex::new(DEFAULT_OUTPUT_SIZE),
            states: Mutex::new(FxHashMap::default()),
            kept: Mutex::new(FxHashMap::default()),
            uploads: Mutex::new(Uploads::default()),
            finisher,
        })
    }

    /// A renderer on a headless device (the CLI and tests).
    pub fn headless() -> Result<Self, RenderError> {
        Self::new(GpuContext::headless()?)
    }

    pub fn shaders(&self) -> std::sync::MutexGuard<'_, ShaderCache> {
        self.shaders.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// The size sinks render at (`--size`, or the editor's viewport).
    pub fn output_size(&self) -> (u32, u32) {
        *self.output_size.lock().unwrap_or_else(|e| e.into_inner())
    }

    pub fn set_output_size(&self, size: (u32, u32)) {
        *self.output_size.lock().unwrap_or_else(|e| e.into_inner()) =
            (size.0.max(1), size.1.max(1));
    }

    /// State a recipe keeps across frames and across its own re-creation
    /// (a node re-evaluated makes a new recipe), under `key` (usually the
    /// node id): made with `T::default()` the first time.
    pub fn state<T: Default + Send + Sync + 'static>(&self, key: u64) -> Arc<T> {
        let mut states = self.states.lock().unwrap_or_else(|e| e.into_inner());
        let entry = states
            .entry((std::any::TypeId::of::<T>(), key))
            .or_insert_with(|| Arc::new(T::default()));
        match entry.clone().downcast::<T>() {
            Ok(state) => state,
            // Keyed by the type's id: another type cannot be under it.
            Err(_) => unreachable!("state keyed by its TypeId"),
        }
    }

    /// How frames are timed and recorded.
    pub fn settings(&self) -> (Timing, Recording) {
        *self.settings.lock().unwrap_or_else(|e| e.into_inner())
    }

    pub fn set_timing(&self, timing: Timing) {
        self.settings.lock().unwrap_or_else(|e| e.into_inner()).0 = timing;
    }

    pub fn set_recording(&self, recording: Recording) {
        self.settings.lock().unwrap_or_else(|e| e.into_inner()).1 = recording;
    }

    pub(crate) fn texture_pool(&self) -> std::sync::MutexGuard<'_, TexturePool> {
        self.textures.lock().unwrap_or_else(|e| e.into_inner())
    }

    pub(crate) fn finisher(&self) -> &Finisher {
        &self.finisher
    }

    pub(crate) fn timestamps(&self) -> Option<&Timestamps> {
        self.timestamps.as_ref()
    }

    pub(crate) fn set_last_report(&self, report: FrameReport) {
        *self.last_report.lock().unwrap_or_else(|e| e.into_inner()) = report;
    }

    /// Remember `submission`; wait until no more than `frames` are unfinished.
    pub(crate) fn throttle(
        &self,
        submission: wgpu::SubmissionIndex,
        frames: usize,
    ) -> Result<(), RenderError> {
        let mut in_flight = self.in_flight.lock().unwrap_or_else(|e| e.into_inner());
        in_flight.push_back(submission);
        while in_flight.len() > frames {
            if let Some(oldest) = in_flight.pop_front() {
                self.gpu
                    .device
                    .poll(wgpu::PollType::Wait {
                        submission_index: Some(oldest),
                        timeout: None,
                    })
                    .map_err(|e| RenderError::Readback(e.to_string()))?;
            }
        }
        Ok(())
    }

    /// Wait for every submission so far (frames in flight drained).
    pub fn wait_idle(&self) -> Result<(), RenderError> {
        self.in_flight
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .clear();
        self.gpu
            .device
            .poll(wgpu::PollType::wait_indefinitely())
            .map(|_| ())
            .map_err(|e| RenderError::Readback(e.to_string()))
    }

    /// The report of the last executed frame graph.
    pub fn last_report(&self) -> FrameReport {
        self.last_report
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .clone()
    }

    /// The errors of the last executed frame graph, by owner: what a host
    /// checks every frame, without copying the whole report (every pass's
    /// name and the counters) as [`Renderer::last_report`] does.
    pub fn last_errors(&self) -> Vec<(Option<u32>, String)> {
        self.last_report
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .errors
            .clone()
    }

    /// A persistent texture by its name (temporal history), if a frame made it:
    /// for tests and tools that inspect or seed history.
    pub fn persistent_texture(&self, name: &str) -> Option<wgpu::Texture> {
        self.textures
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .persistent
            .get(name)
            .map(|(_, t)| t.clone())
    }

    /// The names of the persistent textures (temporal histories) frames have
    /// made and still keep, sorted: what the renderer carries from one frame to
    /// the next.
    pub fn persistent_names(&self) -> Vec<String> {
        let mut names: Vec<String> = self
            .textures
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .persistent
            .keys()
            .cloned()
            .collect();
        names.sort();
        names
    }

    /// Forget persistent textures (a camera cut or a resize resets history).
    pub fn reset_history(&self) {
        self.textures
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .persistent
            .clear();
    }
}

/// Copy a mappable buffer's first `size` bytes to the CPU, waiting for the GPU.
pub(crate) fn read_buffer(
    gpu: &GpuContext,
    buffer: &wgpu::Buffer,
    size: u64,
) -> Result<Vec<u8>, RenderError> {
    let slice = buffer.slice(0..size);
    let (tx, rx) = std::sync::mpsc::channel();
    slice.map_async(wgpu::MapMode::Read, move |r| {
        let _ = tx.send(r);
    });
    gpu.device
        .poll(wgpu::PollType::wait_indefinitely())
        .map_err(|e| RenderError::Readback(e.to_string()))?;
    rx.recv()
        .map_err(|e| RenderError::Readback(e.to_string()))?
        .map_err(|e| RenderError::Readback(e.to_string()))?;
    let data = slice
        .get_mapped_range()
        .map_err(|e| RenderError::Readback(e.to_string()))?
        .to_vec();
    buffer.unmap();
    Ok(data)
}

/// The one way tests get a GPU: a headless renderer, or a panic that says how
/// to get one (never a silent skip).
pub fn test_renderer() -> std::sync::Arc<Renderer> {
    match Renderer::headless() {
        Ok(r) => std::sync::Arc::new(r),
        Err(e) => panic!("GPU tests need a GPU adapter: {e}"),
    }
}
