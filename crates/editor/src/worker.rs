//! The patch worker: a thread that owns the patch's [`Runtime`], evaluates it
//! and renders the viewports, so a patch that takes 200 ms a frame does not
//! hold the editor's UI at 5 frames a second.
//!
//! The UI sends [`Request`]s (the document when it changed, the clock when
//! time moved, what the viewports show and at which size); requests that pile
//! up while a frame is being worked on are merged into one, so the worker
//! always works on the newest state and drops the frames in between. When a
//! frame is finished the worker publishes a [`Frame`]: a snapshot of the
//! runtime (live values, errors, statistics) and the viewports' textures. The
//! UI draws the latest finished frame; it never waits longer than
//! [`FrameWait`] allows.
//!
//! The viewports render on egui-wgpu's own device and queue (both `Send +
//! Sync`) into textures registered with egui: the last step of a viewport's
//! frame is one blit into its texture, and the queue runs submissions in
//! order, so egui samples either the previous finished image or the new one,
//! never a half-drawn one.

use std::collections::HashMap;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::PathBuf;
use std::sync::{Arc, Condvar, Mutex, MutexGuard};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use spreadlight_graph::{
    FrameClock, NodeId, Patch, PatchDir, Registry, ResourceKind, Runtime, RuntimeSnapshot, Spread,
};
use spreadlight_nodes::input::HostInput;
use spreadlight_nodes::media::midi_in::MidiLearn;
use spreadlight_render::{GateCounts, SubmissionGate, TextureRef};

use crate::gpu::WorkerGpu;
use crate::previews::engine::PreviewEngine;
use crate::previews::schedule::Measured;
use crate::previews::{PreviewOuts, PreviewRequest};
use crate::recording::{RecordCommand, Recording, RecordingStatus};
use crate::viewport::{self, ViewTarget, ViewportError};

/// How long a UI frame waits for the patch frame it asked for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FrameWait {
    /// Always wait: every UI frame shows the patch as of that frame. Tests
    /// use this (deterministic); a slow patch then slows the UI.
    Always,
    /// Wait at most this long, then draw the latest finished frame: a fast
    /// patch still shows in the very frame that changed it.
    AtMost(Duration),
}

impl Default for FrameWait {
    /// A quarter of a 60 Hz frame: enough for a light patch to show without lag.
    fn default() -> Self {
        FrameWait::AtMost(Duration::from_millis(4))
    }
}

/// What one viewport shows: a texture output (or why there is none) at a size in pixels.
#[derive(Clone, Debug, PartialEq)]
pub struct ViewRequest {
    pub texture: Result<(NodeId, String), ViewportError>,
    pub size: (u32, u32),
}

/// Work for the worker. Every part is optional; [`Request::merge`] folds a
/// newer request into an older one that has not been started.
#[derive(Default)]
pub struct Request {
    /// Start over with a fresh runtime on this registry (a new document).
    pub reset: Option<Registry>,
    /// Node types changed (shader files): the next load compiles against these.
    pub registry: Option<Registry>,
    /// The folder relative file names resolve in.
    pub patch_dir: Option<PathBuf>,
    /// The document changed: its generation and the patch to load.
    pub patch: Option<(u64, Arc<Patch>)>,
    /// Time moved: evaluate at this clock.
    pub clock: Option<FrameClock>,
    /// What the viewports show, when that changed.
    pub views: Option<Vec<ViewRequest>>,
    /// The previews the canvas draws, when that changed (`previews`).
    pub previews: Option<Vec<PreviewRequest>>,
    /// Start or stop recording the first viewport (`recording.rs`).
    pub record: Option<RecordCommand>,
    /// How media nodes keep up with the clock, when that changed.
    pub playback: Option<spreadlight_nodes::media::Playback>,
}

impl Request {
    pub fn is_empty(&self) -> bool {
        self.reset.is_none()
            && self.registry.is_none()
            && self.patch_dir.is_none()
            && self.patch.is_none()
            && self.clock.is_none()
            && self.views.is_none()
            && self.previews.is_none()
            && self.record.is_none()
            && self.playback.is_none()
    }

    /// Fold `newer` in: the newest of each part wins; a reset drops what came before it.
    pub fn merge(&mut self, newer: Request) {
        if newer.reset.is_some() {
            *self = Request::default();
        }
        let Request {
            reset,
            registry,
            patch_dir,
            patch,
            clock,
            views,
            previews,
            record,
            playback,
        } = newer;
        self.reset = reset.or(self.reset.take());
        self.registry = registry.or(self.registry.take());
        self.patch_dir = patch_dir.or(self.patch_dir.take());
        self.patch = patch.or(self.patch.take());
        self.clock = clock.or(self.clock.take());
        self.views = views.or(self.views.take());
        self.previews = previews.or(self.previews.take());
        self.record = record.or(self.record.take());
        self.playback = playback.or(self.playback.take());
    }
}

/// What the worker's frames cost the UI, counted since it started
/// ([`Frame::counts`]); machine-independent, unlike their times.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct WorkerCounts {
    /// Submissions through the gate and waits there (`GateCounts`).
    pub gate: GateCounts,
    /// Frames published: each calls the UI's wake.
    pub published: u64,
    /// Thumbnails (not the hovered preview) scaled from a frame.
    pub thumbnails_scaled: u64,
}

/// One viewport's finished image, or why there is none.
#[derive(Clone, Default)]
pub struct ViewOut {
    pub target: Option<ViewTarget>,
    pub error: Option<ViewportError>,
    /// The viewport size it was rendered for. The image itself may have
    /// another (an image file's texture keeps the file's size).
    pub for_size: Option<(u32, u32)>,
}

/// A finished frame: what the UI shows until the next one.
#[derive(Clone, Default)]
pub struct Frame {
    pub runtime: RuntimeSnapshot,
    /// The document generation this frame was evaluated from.
    pub generation: Option<u64>,
    /// The clock it was evaluated at.
    pub clock: FrameClock,
    /// Evaluations since the editor started.
    pub evaluations: u64,
    pub views: Vec<ViewOut>,
    /// The previews asked for, as far as they are made.
    pub previews: PreviewOuts,
    /// GPU milliseconds of the first viewport's passes, by the node that declared them.
    pub gpu_ms: HashMap<u32, f64>,
    /// Errors of the first viewport's passes, by node.
    pub gpu_errors: HashMap<u32, String>,
    /// Seconds the worker spent on this frame (evaluation and rendering).
    pub seconds: f64,
    /// The thumbnails' schedule: the patch's frame alone and one thumbnail's cost.
    pub thumbnail_cost: Measured,
    /// What cost the UI, counted since the worker started (compare two
    /// frames for what happened between them): submissions through the
    /// renderer's gate and the waits there (each a repaint request: a UI
    /// frame), frames published (each wakes the UI once), thumbnails scaled.
    pub counts: WorkerCounts,
    /// A panic in a node or pass, caught so the editor keeps the document.
    pub failure: Option<String>,
    /// The recording in progress, or the last one finished.
    pub recording: Option<RecordingStatus>,
}

#[derive(Default)]
struct State {
    pending: Request,
    /// Sequence number of the last request submitted and of the last one finished.
    submitted: u64,
    finished: u64,
    latest: Option<Arc<Frame>>,
    /// Frames the UI is done with, freed here: a frame holds a spread per
    /// output of every node, and freeing them on the UI thread made its
    /// frame grow with the patch.
    retired: Vec<Arc<Frame>>,
    stop: bool,
}

#[derive(Default)]
struct Shared {
    state: Mutex<State>,
    work: Condvar,
    done: Condvar,
    /// Called after each published frame (egui's `request_repaint`), so an idle UI picks it up.
    wake: Mutex<Option<Box<dyn Fn() + Send>>>,
}

impl Shared {
    fn lock(&self) -> MutexGuard<'_, State> {
        // The worker catches panics of the patch; a poisoned lock still holds whole data.
        self.state.lock().unwrap_or_else(|e| e.into_inner())
    }
}

/// How long the worker waits for the next request before finishing the
/// thumbnails a playing frame left for later (the patch may have paused).
const PENDING_PREVIEWS_AFTER: Duration = Duration::from_millis(300);

/// The UI's handle on the worker thread (stopped and joined on drop).
pub struct Worker {
    shared: Arc<Shared>,
    thread: Option<JoinHandle<()>>,
    host: Arc<HostInput>,
    /// MIDI learn between the inspector and the patch's MidiIn nodes.
    midi_learn: Arc<MidiLearn>,
    /// The renderer's submission gate, opened for good before the thread is
    /// joined: it may be waiting there for a frame the UI no longer runs.
    gate: Option<SubmissionGate>,
}

impl Worker {
    pub fn new(registry: Registry, gpu: Option<WorkerGpu>) -> Self {
        let shared = Arc::new(Shared::default());
        let host = Arc::new(HostInput::default());
        let gate = gpu
            .as_ref()
            .map(|g| g.renderer.gpu.submission_gate().clone());
        let midi_learn = Arc::new(MidiLearn::default());
        let mut engine = Engine::new(registry, gpu, (host.clone(), midi_learn.clone()));
        let inner = shared.clone();
        let thread = std::thread::Builder::new()
            .name("spreadlight patch".to_owned())
            .spawn(move || engine.serve(&inner))
            .ok();
        Worker {
            shared,
            thread,
            host,
            midi_learn,
            gate,
        }
    }

    /// The MIDI learn service the patch's MidiIn nodes feed.
    pub fn midi_learn(&self) -> &Arc<MidiLearn> {
        &self.midi_learn
    }

    /// The input service the patch's Mouse, Keyboard and WindowSize nodes read.
    pub fn host_input(&self) -> &Arc<HostInput> {
        &self.host
    }

    /// Call `wake` after every finished frame.
    pub fn set_wake(&self, wake: Box<dyn Fn() + Send>) {
        *self.shared.wake.lock().unwrap_or_else(|e| e.into_inner()) = Some(wake);
    }

    /// Hand over work; returns its sequence number for [`Worker::wait`].
    pub fn submit(&self, request: Request) -> u64 {
        let mut s = self.shared.lock();
        s.pending.merge(request);
        s.submitted += 1;
        self.shared.work.notify_one();
        s.submitted
    }

    /// Wait until request `seq` is finished, at most `wait`; whether it is.
    pub fn wait(&self, seq: u64, wait: FrameWait) -> bool {
        let s = self.shared.lock();
        if self.thread.is_none() {
            return true;
        }
        let done = |s: &mut State| s.finished < seq && !s.stop;
        match wait {
            FrameWait::Always => {
                let s = self
                    .shared
                    .done
                    .wait_while(s, done)
                    .unwrap_or_else(|e| e.into_inner());
                s.finished >= seq
            }
            FrameWait::AtMost(d) => {
                let (s, _) = self
                    .shared
                    .done
                    .wait_timeout_while(s, d, done)
                    .unwrap_or_else(|e| e.into_inner());
                s.finished >= seq
            }
        }
    }

    /// Hand back a frame the UI no longer shows, to be freed on the worker
    /// thread (with the next frame it finishes).
    pub fn retire(&self, frame: Arc<Frame>) {
        self.shared.lock().retired.push(frame);
    }

    /// The latest finished frame.
    pub fn latest(&self) -> Option<Arc<Frame>> {
        self.shared.lock().latest.clone()
    }

    /// Whether the worker has work it has not finished.
    pub fn busy(&self) -> bool {
        let s = self.shared.lock();
        s.finished < s.submitted
    }
}

impl Drop for Worker {
    fn drop(&mut self) {
        self.shared.lock().stop = true;
        self.shared.work.notify_all();
        if let Some(gate) = &self.gate {
            gate.open_for_good();
        }
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

/// The worker thread's side: the runtime and the viewports' state.
struct Engine {
    registry: Registry,
    runtime: Runtime,
    gpu: Option<WorkerGpu>,
    host: Arc<HostInput>,
    midi_learn: Arc<MidiLearn>,
    clock: FrameClock,
    generation: Option<u64>,
    evaluations: u64,
    views: Vec<(Option<ViewRequest>, ViewOut, bool)>,
    gpu_ms: HashMap<u32, f64>,
    gpu_errors: HashMap<u32, String>,
    previews: PreviewEngine,
    /// The pins of the viewports after the first (the texture-pin viewport's).
    viewed_pins: Vec<(Vec<NodeId>, String)>,
    /// What the runtime was last asked to evaluate besides the sinks.
    demanded: Vec<(Vec<NodeId>, String)>,
    playback: spreadlight_nodes::media::Playback,
    recording: Option<Recording>,
    recorded: Option<RecordingStatus>,
    /// Frames published and thumbnails scaled so far (`WorkerCounts`).
    published: u64,
    thumbnails_scaled: u64,
}

impl Engine {
    fn new(
        registry: Registry,
        gpu: Option<WorkerGpu>,
        (host, midi_learn): (Arc<HostInput>, Arc<MidiLearn>),
    ) -> Self {
        let mut engine = Engine {
            runtime: Runtime::new(registry.clone()),
            registry,
            gpu,
            host,
            midi_learn,
            clock: FrameClock::default(),
            generation: None,
            evaluations: 0,
            views: Vec::new(),
            gpu_ms: HashMap::new(),
            gpu_errors: HashMap::new(),
            previews: PreviewEngine::default(),
            viewed_pins: Vec::new(),
            demanded: Vec::new(),
            playback: spreadlight_nodes::media::Playback::Live,
            recording: None,
            recorded: None,
            published: 0,
            thumbnails_scaled: 0,
        };
        engine.reset(engine.registry.clone());
        engine
    }

    fn reset(&mut self, registry: Registry) {
        self.registry = registry;
        self.runtime = Runtime::new(self.registry.clone());
        self.runtime.provide(self.host.clone());
        self.runtime.provide(self.midi_learn.clone());
        self.runtime.provide(Arc::new(self.playback));
        if let Some(gpu) = &self.gpu {
            spreadlight_nodes::gpu::provide_renderer(&mut self.runtime, gpu.renderer.clone());
            gpu.renderer.reset_history();
        }
        self.generation = None;
        self.clock = FrameClock::default();
        // A fresh runtime evaluates only its sinks until told again.
        self.demanded.clear();
    }

    fn serve(&mut self, shared: &Shared) {
        loop {
            let (request, seq) = {
                let s = shared.lock();
                let idle = |s: &mut State| s.pending.is_empty() && !s.stop;
                let mut s = if self.previews.has_pending() {
                    // Thumbnails a playing frame left for later: when no
                    // request follows (the patch was paused), a frame of
                    // their own, with no budget, finishes them.
                    shared
                        .work
                        .wait_timeout_while(s, PENDING_PREVIEWS_AFTER, idle)
                        .map(|(s, _)| s)
                        .unwrap_or_else(|e| e.into_inner().0)
                } else {
                    shared
                        .work
                        .wait_while(s, idle)
                        .unwrap_or_else(|e| e.into_inner())
                };
                if s.stop {
                    return;
                }
                (std::mem::take(&mut s.pending), s.submitted)
            };
            let started = Instant::now();
            let failure = catch_unwind(AssertUnwindSafe(|| self.run(request)))
                .err()
                .map(|panic| {
                    let what = panic
                        .downcast_ref::<String>()
                        .cloned()
                        .or_else(|| panic.downcast_ref::<&str>().map(|s| (*s).to_owned()))
                        .unwrap_or_else(|| "unknown panic".to_owned());
                    format!("the patch's evaluation panicked: {what}")
                });
            let frame = Arc::new(Frame {
                runtime: self.runtime.snapshot(),
                generation: self.generation,
                clock: self.clock,
                evaluations: self.evaluations,
                views: self.views.iter().map(|(_, out, _)| out.clone()).collect(),
                previews: self.previews.outputs(),
                gpu_ms: self.gpu_ms.clone(),
                gpu_errors: self.gpu_errors.clone(),
                seconds: started.elapsed().as_secs_f64(),
                thumbnail_cost: self.previews.measurements(),
                counts: self.counts(),
                failure,
                recording: self
                    .recording
                    .as_ref()
                    .map(|r| r.status.clone())
                    .or_else(|| self.recorded.clone()),
            });
            let (previous, retired) = {
                let mut s = shared.lock();
                let previous = s.latest.replace(frame);
                s.finished = seq;
                shared.done.notify_all();
                (previous, std::mem::take(&mut s.retired))
            };
            // Freed here, outside the lock, not on the UI thread.
            drop((previous, retired));
            if let Some(wake) = &*shared.wake.lock().unwrap_or_else(|e| e.into_inner()) {
                wake();
            }
        }
    }

    /// What this worker's frames cost so far, this one counted as published.
    fn counts(&mut self) -> WorkerCounts {
        self.published += 1;
        WorkerCounts {
            gate: self
                .gpu
                .as_ref()
                .map(|g| g.renderer.gpu.submission_gate().counts())
                .unwrap_or_default(),
            published: self.published,
            thumbnails_scaled: self.thumbnails_scaled,
        }
    }

    fn run(&mut self, request: Request) {
        if let Some(registry) = request.reset {
            self.reset(registry);
        }
        if let Some(registry) = request.registry {
            self.registry = registry.clone();
            self.runtime.set_registry(registry);
        }
        if let Some(playback) = request.playback {
            self.playback = playback;
            self.runtime.provide(Arc::new(playback));
        }
        match request.record {
            Some(RecordCommand::Start(settings)) => {
                self.recorded = self.recording.take().map(Recording::finish);
                self.recording = Some(Recording::new(settings));
            }
            Some(RecordCommand::Stop) => {
                self.recorded = self.recording.take().map(Recording::finish);
            }
            None => {}
        }
        if let Some(dir) = request.patch_dir {
            self.runtime.provide(Arc::new(PatchDir(dir)));
        }
        let mut evaluate = false;
        if let Some((generation, patch)) = request.patch {
            self.runtime.load(&patch);
            self.generation = Some(generation);
            evaluate = true;
        }
        if let Some(clock) = request.clock {
            self.clock = clock;
            evaluate = true;
        }
        if let Some(previews) = request.previews {
            self.previews.set_requests(previews);
        }
        // Time moved: a playing patch, whose frame time the thumbnails keep to their budget.
        self.previews.set_budgeted(request.clock.is_some());
        if let Some(views) = &request.views {
            self.viewed_pins = views
                .iter()
                .skip(1)
                .filter_map(|v| v.texture.as_ref().ok())
                .map(|(node, pin)| (vec![*node], pin.clone()))
                .collect();
        }
        // A preview of a pin that feeds no sink, or the texture-pin viewport's
        // pin, evaluates its branch; `render` and `play` never ask for this.
        let mut demand = self.previews.pins();
        demand.extend(self.viewed_pins.iter().cloned());
        demand.sort();
        demand.dedup();
        if demand != self.demanded {
            self.runtime.demand_also(demand.clone());
            self.demanded = demand;
            evaluate |= self.generation.is_some();
        }
        if evaluate {
            self.runtime.evaluate(self.clock);
            self.evaluations += 1;
            for v in &mut self.views {
                v.2 = true;
            }
        }
        if let Some(views) = request.views {
            self.views.resize_with(views.len(), Default::default);
            for (v, want) in self.views.iter_mut().zip(views) {
                if v.0.as_ref() != Some(&want) {
                    v.0 = Some(want);
                    v.2 = true;
                }
            }
        }
        if self.previews.is_due() && !self.views.is_empty() {
            // The previews render in the first viewport's frame.
            self.views[0].2 = true;
        }
        for k in 0..self.views.len() {
            if std::mem::take(&mut self.views[k].2) {
                self.render_view(k);
            }
        }
        if let Some(gpu) = &self.gpu {
            self.previews.probe_again(&gpu.renderer, &gpu.blitter);
            self.previews.free_stale(&gpu.state);
        }
        if evaluate {
            self.record_view();
        }
    }

    /// Hand the first viewport's new frame to the recording, if one runs.
    fn record_view(&mut self) {
        let (Some(recording), Some(gpu)) = (&mut self.recording, &self.gpu) else {
            return;
        };
        let Some((_, out, _)) = self.views.first() else {
            return;
        };
        if let (Some(target), None) = (&out.target, &out.error) {
            recording.capture(&gpu.renderer.gpu, &target.texture, self.clock);
        }
    }

    /// The texture on a viewport's pin, if the runtime evaluated it.
    fn texture(&self, want: &ViewRequest) -> Result<TextureRef, ViewportError> {
        let (node, pin) = want.texture.clone()?;
        let network = self.runtime.network();
        let needed = network
            .index_at(&[node])
            .or_else(|| network.instance_output(&[node], &pin))
            .is_some_and(|i| self.runtime.is_demanded(i));
        if !needed {
            return Err(ViewportError::NotEvaluated(format!("{node}.{pin}")));
        }
        match self.runtime.output(node, &pin).map(|s| &**s) {
            Some(Spread::Resource(ResourceKind::Texture, handles)) => handles
                .first()
                .and_then(|h| h.downcast_arc::<TextureRef>())
                .map(|t| (*t).clone())
                .ok_or(ViewportError::NoTexture),
            _ => Err(ViewportError::NoTexture),
        }
    }

    fn render_view(&mut self, k: usize) {
        let Some(gpu) = &self.gpu else {
            return;
        };
        let Some(want) = self.views[k].0.clone() else {
            return;
        };
        let texture = self.texture(&want);
        let out = &mut self.views[k].1;
        let result = if k == 0 && !self.previews.is_empty() {
            // The first viewport's frame graph renders the previews too: a
            // pass both need runs once, and one the viewport needs anyway
            // costs a preview nothing but its scaling.
            let main = texture.as_ref().ok();
            let size = if want.size.0 < 16 || want.size.1 < 16 {
                (640, 360)
            } else {
                want.size
            };
            let frame = self.previews.render(
                &self.runtime,
                gpu,
                (main, &mut out.target),
                size,
                self.clock.time,
            );
            self.thumbnails_scaled += self.previews.scaled() as u64;
            match (texture, frame) {
                (Err(e), _) => Err(e),
                (Ok(_), None) => Err(ViewportError::NoTexture),
                (Ok(_), Some(shown)) => shown,
            }
        } else {
            texture.and_then(|t| {
                viewport::render_into(
                    &gpu.state,
                    &gpu.renderer,
                    &gpu.blitter,
                    &t,
                    want.size,
                    &mut out.target,
                )
            })
        };
        out.for_size = Some(want.size);
        match result {
            Ok(report) => {
                out.error = None;
                if k == 0 {
                    self.gpu_ms.clear();
                    for pass in report.passes {
                        // A pass two nodes share (the frame graph merged
                        // theirs) counts half to each.
                        let share = if pass.partner.is_some() { 0.5 } else { 1.0 };
                        for owner in [pass.owner, pass.partner].into_iter().flatten() {
                            if let Some(ms) = pass.gpu_ms {
                                *self.gpu_ms.entry(owner).or_default() += ms * share;
                            }
                        }
                    }
                    self.gpu_errors.clear();
                    for (owner, message) in report.errors {
                        if let Some(owner) = owner {
                            self.gpu_errors.insert(owner, message);
                        }
                    }
                }
            }
            Err(e) => out.error = Some(e),
        }
    }
}

#[cfg(test)]
mod tests {
    use spreadlight_graph::{LinkDoc, NodeDoc};

    use super::*;

    fn lfo_probe() -> Arc<Patch> {
        let mut p = Patch::default();
        p.add(NodeDoc::new(1, "LFO"));
        p.add(NodeDoc::new(2, "Probe"));
        p.links.push(LinkDoc::new(1, "Output", 2, "Input"));
        Arc::new(p)
    }

    #[test]
    fn requests_merge_newest_first_and_a_reset_drops_older_work() {
        let mut a = Request {
            clock: Some(FrameClock::default()),
            patch: Some((1, Arc::new(Patch::default()))),
            ..Default::default()
        };
        let later = FrameClock {
            frame: 7,
            ..Default::default()
        };
        a.merge(Request {
            clock: Some(later),
            ..Default::default()
        });
        assert_eq!(a.clock.map(|c| c.frame), Some(7));
        assert_eq!(a.patch.as_ref().map(|p| p.0), Some(1), "kept");
        a.merge(Request {
            reset: Some(Registry::new()),
            ..Default::default()
        });
        assert!(a.reset.is_some());
        assert!(a.patch.is_none() && a.clock.is_none(), "older work dropped");
        assert!(!a.is_empty());
        assert!(Request::default().is_empty());
    }

    #[test]
    fn the_worker_evaluates_off_the_calling_thread_and_publishes_snapshots() {
        let worker = Worker::new(crate::nodes::registry(), None);
        let main = std::thread::current().id();
        let seq = worker.submit(Request {
            patch: Some((3, lfo_probe())),
            clock: Some(FrameClock::default()),
            ..Default::default()
        });
        assert!(worker.wait(seq, FrameWait::Always));
        let frame = worker.latest().expect("a frame");
        assert_eq!(frame.generation, Some(3));
        assert_eq!(frame.evaluations, 1);
        assert!(frame.failure.is_none());
        assert!(frame.runtime.output(NodeId(1), "Output").is_some());
        assert_eq!(frame.runtime.stats().evaluated, 2);
        // Several requests before the worker takes them become one frame at the newest clock.
        let mut last = 0;
        for f in 1..=5u64 {
            last = worker.submit(Request {
                clock: Some(FrameClock {
                    frame: f,
                    time: f as f64 / 60.0,
                    delta: 1.0 / 60.0,
                }),
                ..Default::default()
            });
        }
        assert!(worker.wait(last, FrameWait::Always));
        let frame = worker.latest().expect("a frame");
        assert_eq!(frame.clock.frame, 5);
        assert!((2..=6).contains(&frame.evaluations));
        assert_eq!(std::thread::current().id(), main);
    }
}
