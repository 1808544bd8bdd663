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
use crate::mesh_arena::MeshArena;
use crate::report::FrameReport;
use crate::shaders::ShaderCache;

mod kept;

use kept::{KeptBuffer, KeptKey, Uploads};

pub(crate) use crate::context::read_buffer;
pub use crate::frame_graph::{
    Executor, PERSISTENT_IDLE_GRAPHS, PassOrder, Recording, SUBMIT_VAR, Submission, Timing,
};

pub struct Renderer {
    pub gpu: GpuContext,
    /// Runs frame graphs: the shader cache, the texture pool, timing.
    pub executor: Executor,
    pub meshes: MeshArena,
    output_size: Mutex<(u32, u32)>,
    /// Buffers recipes keep across their re-creation, by owner node and label
    /// (`Renderer::uniform`, `Renderer::kept_buffer`), with a uniform's last contents.
    kept: Mutex<FxHashMap<KeptKey, KeptBuffer>>,
    /// Kept-buffer writes made and skipped since the last frame graph ran.
    uploads: Mutex<Uploads>,
    /// What recipes keep between frames (shadow maps), by type and key.
    states: Mutex<FxHashMap<(std::any::TypeId, u64), Arc<dyn std::any::Any + Send + Sync>>>,
}

/// The output size until a host sets one.
pub const DEFAULT_OUTPUT_SIZE: (u32, u32) = (640, 360);

impl Renderer {
    pub fn new(gpu: GpuContext) -> Result<Self, RenderError> {
        Ok(Renderer {
            executor: Executor::new(&gpu)?,
            meshes: MeshArena::new(&gpu),
            gpu,
            output_size: Mutex::new(DEFAULT_OUTPUT_SIZE),
            states: Mutex::new(FxHashMap::default()),
            kept: Mutex::new(FxHashMap::default()),
            uploads: Mutex::new(Uploads::default()),
        })
    }

    /// A renderer on a headless device (the CLI and tests).
    pub fn headless() -> Result<Self, RenderError> {
        Self::new(GpuContext::headless()?)
    }

    pub fn shaders(&self) -> std::sync::MutexGuard<'_, ShaderCache> {
        self.executor.shaders()
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

    /// A switch of this renderer (crate::setting) under `key`: as set
    /// ([`Renderer::set_setting`]), else `read()` the first time (the
    /// environment's, which decides what an unknown value counts as).
    pub fn setting<T: Copy + Send + Sync + 'static>(
        &self,
        key: u64,
        read: impl FnOnce() -> T,
    ) -> T {
        let kept = self.state::<Kept<T>>(key);
        let mut chosen = kept.0.lock().unwrap_or_else(|e| e.into_inner());
        *chosen.get_or_insert_with(read)
    }

    /// Set a switch of this renderer under `key` (for what is declared
    /// from now on).
    pub fn set_setting<T: Copy + Send + Sync + 'static>(&self, key: u64, value: T) {
        let kept = self.state::<Kept<T>>(key);
        *kept.0.lock().unwrap_or_else(|e| e.into_inner()) = Some(value);
    }

    /// How frames are timed and recorded.
    pub fn settings(&self) -> (Timing, Recording) {
        self.executor.settings()
    }

    pub fn set_timing(&self, timing: Timing) {
        self.executor.set_timing(timing);
    }

    pub fn set_recording(&self, recording: Recording) {
        self.executor.set_recording(recording);
    }

    /// Reuse frame graphs' plans while their declarations stay the same
    /// (the default), or plan each afresh (`Executor::set_plan_reuse`).
    pub fn set_plan_reuse(&self, reuse: bool) {
        self.executor.set_plan_reuse(reuse);
    }

    /// Let dispatches on a kept plan take last frame's pipelines and bind
    /// groups (the default), or look each up (`Executor::set_kept_bindings`).
    pub fn set_kept_bindings(&self, keep: bool) {
        self.executor.set_kept_bindings(keep);
    }

    /// The order passes run in (`frame_graph::PassOrder`: declaration order,
    /// or waves of passes the GPU may run side by side).
    pub fn pass_order(&self) -> PassOrder {
        self.executor.pass_order()
    }

    pub fn set_pass_order(&self, order: PassOrder) {
        self.executor.set_pass_order(order);
    }

    /// Where frames are submitted: on the recording thread or on a
    /// submission thread (`Executor::set_submission`, `SPREADLIGHT_SUBMIT`).
    pub fn submission(&self) -> Submission {
        self.executor.submission()
    }

    pub fn set_submission(&self, submission: Submission) {
        self.executor.set_submission(submission);
    }

    /// Wait for every submission so far (frames in flight drained).
    pub fn wait_idle(&self) -> Result<(), RenderError> {
        self.executor.wait_idle()
    }

    /// The report of the last executed frame graph.
    pub fn last_report(&self) -> FrameReport {
        self.executor.last_report()
    }

    /// The timings of every frame graph executed since the last call: a
    /// frame of a patch with several Outputs executes one for each.
    pub fn take_graph_timings(&self) -> crate::report::GraphTimings {
        self.executor.take_graph_timings()
    }

    /// The errors of the last executed frame graph, by owner: what a host
    /// checks every frame, without copying the whole report.
    pub fn last_errors(&self) -> Vec<(Option<u32>, String)> {
        self.executor.last_errors()
    }

    /// A persistent texture by its name (temporal history), if a frame made it:
    /// for tests and tools that inspect or seed history.
    pub fn persistent_texture(&self, name: &str) -> Option<wgpu::Texture> {
        self.executor.persistent_texture(name)
    }

    /// The names of the persistent textures (temporal histories) frames have
    /// made and still keep, sorted: what the renderer carries from one frame to
    /// the next.
    pub fn persistent_names(&self) -> Vec<String> {
        self.executor.persistent_names()
    }

    /// Forget persistent textures (a camera cut or a resize resets history).
    pub fn reset_history(&self) {
        self.executor.reset_history();
    }
}

impl<'a> crate::frame_graph::FrameGraph<'a> {
    /// Cull, allocate, record and submit the frame on `renderer`'s executor.
    /// Returns its report (with the kept buffers' uploads since the last
    /// frame counted) and the requested textures.
    pub fn execute(
        self,
        renderer: &Renderer,
    ) -> Result<
        (
            FrameReport,
            std::collections::HashMap<String, wgpu::Texture>,
        ),
        RenderError,
    > {
        self.execute_then(renderer, |_| Vec::new())
    }

    /// [`FrameGraph::execute`], with `then`'s commands (given the textures
    /// the frame hands back) in the frame's own submission, after its passes
    /// ([`FrameGraph::execute_on_then`]).
    pub fn execute_then(
        self,
        renderer: &Renderer,
        then: impl FnOnce(&std::collections::HashMap<String, wgpu::Texture>) -> Vec<wgpu::CommandBuffer>,
    ) -> Result<
        (
            FrameReport,
            std::collections::HashMap<String, wgpu::Texture>,
        ),
        RenderError,
    > {
        self.execute_on_then(
            &renderer.executor,
            &renderer.gpu,
            || {
                let uploads = renderer.take_uploads();
                vec![
                    ("uniform uploads", uploads.made),
                    ("uniform uploads skipped", uploads.skipped),
                    ("uniform bytes uploaded", uploads.bytes),
                    ("kept bytes compared", uploads.compared),
                ]
            },
            then,
        )
    }
}

/// The one way tests get a GPU: a headless renderer, or a panic that says how
/// to get one (never a silent skip).
pub fn test_renderer() -> std::sync::Arc<Renderer> {
    match Renderer::headless() {
        Ok(r) => std::sync::Arc::new(r),
        Err(e) => panic!("GPU tests need a GPU adapter: {e}"),
    }
}

/// A renderer's switch `T` ([`Renderer::setting`]), once set or read.
struct Kept<T>(Mutex<Option<T>>);

impl<T> Default for Kept<T> {
    fn default() -> Self {
        Kept(Mutex::new(None))
    }
}
