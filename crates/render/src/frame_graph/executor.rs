//! The executor: what running frame graphs keeps between frames, below the
//! renderer. It owns the shader permutation cache, the texture pool and the
//! persistent textures, the timestamp queries, how frames are timed and
//! recorded, the frames in flight and the last frame's report; the
//! renderer holds one and adds what recipes share (the mesh arena, kept
//! buffers, per-node state). `execute.rs` runs a graph on it, knowing
//! nothing of the renderer.

use std::collections::VecDeque;
use std::sync::Mutex;

use super::submitter::{Submission, Submitter};
use super::{Finisher, PassOrder};
use crate::context::GpuContext;
use crate::error::RenderError;
use crate::report::{FrameReport, GraphTimings};
use crate::shaders::ShaderCache;
use crate::texture_pool::TexturePool;

/// Timestamp queries a frame may write (two a timed pass).
pub(crate) const MAX_QUERIES: u32 = 512;

/// Frame graphs a persistent texture may go unwritten before it is dropped:
/// about a second at 60 frames a second, so a node briefly culled (an editor
/// viewport looking elsewhere) keeps its history.
pub const PERSISTENT_IDLE_GRAPHS: u32 = 60;

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

pub struct Executor {
    device: wgpu::Device,
    shaders: Mutex<ShaderCache>,
    textures: Mutex<TexturePool>,
    timestamps: Option<Timestamps>,
    settings: Mutex<(Timing, Recording)>,
    /// The order passes run in (waves.rs); from [`super::PASS_ORDER_VAR`] at first.
    pass_order: Mutex<PassOrder>,
    /// The passes (by name) that asked for the encoder itself in their last
    /// run: first in their wave (waves.rs). Kept only in waves.
    encoder_passes: Mutex<rustc_hash::FxHashSet<String>>,
    /// Submissions not yet known to be done, oldest first (`Timing::Off`).
    in_flight: Mutex<VecDeque<wgpu::SubmissionIndex>>,
    last_report: Mutex<FrameReport>,
    /// The timings of every graph executed since a host last took them.
    timings: Mutex<GraphTimings>,
    /// Where frames are submitted (submitter.rs); from [`super::SUBMIT_VAR`] at first.
    submission: Mutex<Submission>,
    /// The thread that submits frames with [`Submission::Thread`]; before
    /// the finisher, so that it is dropped (its last frame submitted) first.
    submitter: Submitter,
    /// The thread that finishes a batched frame's encoders beside its recording.
    finisher: Finisher,
    /// The time waited for owed submissions when the last frame returned
    /// (`FrameReport::submission_wait_ms` is the difference).
    waited_before: Mutex<std::time::Duration>,
    /// Frame graphs' plans kept across frames (plan.rs).
    plans: super::plan::Plans,
    /// What the last plan's dispatches resolved (kept_bindings.rs).
    kept_bindings: Mutex<super::kept_bindings::KeptBindings>,
}

impl Executor {
    pub(crate) fn new(gpu: &GpuContext) -> Result<Self, RenderError> {
        // The composer is made when a permutation is not composed already:
        // a process that composed ahead (`crate::precompose`) skips it.
        let shaders = ShaderCache::lazy().with_pipeline_cache(gpu.pipeline_cache().cloned());
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
        Ok(Executor {
            device: gpu.device.clone(),
            shaders: Mutex::new(shaders),
            textures: Mutex::new(TexturePool::default()),
            timestamps,
            settings: Mutex::new((Timing::default(), Recording::default())),
            pass_order: Mutex::new(PassOrder::from_env().map_err(RenderError::Graph)?),
            encoder_passes: Mutex::new(Default::default()),
            in_flight: Mutex::new(VecDeque::new()),
            last_report: Mutex::new(FrameReport::default()),
            timings: Mutex::new(GraphTimings::default()),
            finisher: Finisher::new(gpu.device.clone()),
            submission: Mutex::new(Submission::from_env().map_err(RenderError::Graph)?),
            submitter: Submitter::new(gpu),
            waited_before: Mutex::new(gpu.queue.owed().waited()),
            plans: Default::default(),
            kept_bindings: Default::default(),
        })
    }

    pub fn shaders(&self) -> std::sync::MutexGuard<'_, ShaderCache> {
        self.shaders.lock().unwrap_or_else(|e| e.into_inner())
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

    /// Reuse a frame graph's plan while its declaration stays the same (the
    /// default), or plan every graph afresh: the frames are the same either
    /// way (plan.rs), this is for tests and benchmarks to compare.
    pub fn set_plan_reuse(&self, reuse: bool) {
        self.plans.set_reuse(reuse);
    }

    /// Let a kept plan's dispatches take what they resolved last frame (the
    /// default), or resolve every pipeline and bind group through the shader
    /// cache: the frames are the same either way (kept_bindings.rs), this is
    /// for tests and benchmarks to compare.
    pub fn set_kept_bindings(&self, keep: bool) {
        self.kept_bindings().on = keep;
    }

    pub(crate) fn kept_bindings(
        &self,
    ) -> std::sync::MutexGuard<'_, super::kept_bindings::KeptBindings> {
        self.kept_bindings.lock().unwrap_or_else(|e| e.into_inner())
    }

    pub(crate) fn plans(&self) -> &super::plan::Plans {
        &self.plans
    }

    /// The order passes run in ([`PassOrder`]).
    pub fn pass_order(&self) -> PassOrder {
        *self.pass_order.lock().unwrap_or_else(|e| e.into_inner())
    }

    pub fn set_pass_order(&self, order: PassOrder) {
        *self.pass_order.lock().unwrap_or_else(|e| e.into_inner()) = order;
    }

    /// The passes that used the encoder itself in their last run (waves.rs).
    pub(crate) fn encoder_passes(
        &self,
    ) -> std::sync::MutexGuard<'_, rustc_hash::FxHashSet<String>> {
        self.encoder_passes
            .lock()
            .unwrap_or_else(|e| e.into_inner())
    }

    pub(crate) fn texture_pool(&self) -> std::sync::MutexGuard<'_, TexturePool> {
        self.textures.lock().unwrap_or_else(|e| e.into_inner())
    }

    pub(crate) fn finisher(&self) -> &Finisher {
        &self.finisher
    }

    /// Where frames are submitted ([`Submission`]).
    pub fn submission(&self) -> Submission {
        *self.submission.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// Submit frames on the recording thread or on a submission thread;
    /// a frame still owed is submitted before the next either way.
    pub fn set_submission(&self, submission: Submission) {
        *self.submission.lock().unwrap_or_else(|e| e.into_inner()) = submission;
    }

    pub(crate) fn submitter(&self) -> &Submitter {
        &self.submitter
    }

    /// The time waited for owed submissions since the last frame returned;
    /// the reading is kept for the next frame.
    pub(crate) fn submission_wait_since_last_frame(&self) -> std::time::Duration {
        let now = self.submitter.waited();
        let mut before = self.waited_before.lock().unwrap_or_else(|e| e.into_inner());
        let since = now.saturating_sub(*before);
        *before = now;
        since
    }

    /// Put the errors of a submission made since the last report into it
    /// (without waiting for one still owed), and record apart from now on
    /// if its validation failed, as an inline submission does.
    fn settle(&self) {
        if self.submitter.is_owed() {
            return;
        }
        let (errors, failed) = self.submitter.take_errors();
        if failed {
            self.set_recording(Recording::Isolated);
        }
        if !errors.is_empty() {
            let mut report = self.last_report.lock().unwrap_or_else(|e| e.into_inner());
            report.errors.extend(errors.into_iter().map(|e| (None, e)));
        }
    }

    pub(crate) fn timestamps(&self) -> Option<&Timestamps> {
        self.timestamps.as_ref()
    }

    /// Keep a copy of `report` as the last one (in the last one's storage),
    /// and add its timings to those not yet taken.
    pub(crate) fn set_last_report(&self, report: &FrameReport) {
        self.last_report
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .copy_from(report);
        self.timings
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .add(report);
    }

    /// The timings of every graph executed since the last call.
    pub fn take_graph_timings(&self) -> GraphTimings {
        std::mem::take(&mut *self.timings.lock().unwrap_or_else(|e| e.into_inner()))
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
                self.device
                    .poll(wgpu::PollType::Wait {
                        submission_index: Some(oldest),
                        timeout: None,
                    })
                    .map_err(|e| RenderError::Readback(e.to_string()))?;
            }
        }
        Ok(())
    }

    /// Wait for every submission so far (frames in flight drained); the
    /// errors of a frame submitted on the submission thread go into the
    /// last report.
    pub fn wait_idle(&self) -> Result<(), RenderError> {
        self.submitter.wait();
        self.settle();
        self.in_flight
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .clear();
        self.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map(|_| ())
            .map_err(|e| RenderError::Readback(e.to_string()))
    }

    /// The report of the last executed frame graph. With a submission
    /// thread, its submission's errors are in it once it was submitted
    /// (this does not wait for it: [`Executor::wait_idle`] does).
    pub fn last_report(&self) -> FrameReport {
        self.settle();
        self.last_report
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .clone()
    }

    /// The errors of the last executed frame graph, by owner (without
    /// copying the whole report, as [`Executor::last_report`] does).
    pub fn last_errors(&self) -> Vec<(Option<u32>, String)> {
        self.settle();
        self.last_report
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .errors
            .clone()
    }

    /// A persistent texture by its name (temporal history), if a frame made it.
    pub fn persistent_texture(&self, name: &str) -> Option<wgpu::Texture> {
        self.texture_pool()
            .persistent
            .get(name)
            .map(|(_, t)| t.clone())
    }

    /// The names of the persistent textures frames have made and still keep, sorted.
    pub fn persistent_names(&self) -> Vec<String> {
        let mut names: Vec<String> = self.texture_pool().persistent.keys().cloned().collect();
        names.sort();
        names
    }

    /// Forget persistent textures (a camera cut or a resize resets history).
    pub fn reset_history(&self) {
        let mut guard = self.texture_pool();
        let pool = &mut *guard;
        for (_, (_, texture)) in pool.persistent.drain() {
            pool.views.forget(&texture);
        }
    }
}
