//! Creating a patch's compute pipelines ahead, on threads, from the list
//! its last run left (`crate::precompose`), while the patch loads and its
//! first frame evaluates.
//!
//! A fresh process's first frame used to create every pipeline where a
//! pass first asked for it, one after another: on the H200 host with the
//! driver's shader cache empty that was 2.3 s of post.ron's 2.8 s start,
//! 31 pipelines each compiled by the driver in turn. wgpu's `Device` may be
//! used from many threads and Vulkan drivers compile pipelines in parallel,
//! so as soon as the device is open, threads of their own create what the
//! list names, each pipeline exactly as the frame would have (the same
//! composed module, entry point, derived layout and pipeline cache, no
//! overridable constants: `shaders/cache.rs`), and the frame's look-up
//! takes the one made ahead ([`PipelinesAhead::take`]), waits for one in
//! the making, or makes a pipeline no thread started yet itself.
//!
//! A stale list costs time, never pixels: an entry whose permutation or
//! entry point this build lacks is skipped, and a pipeline the device
//! refuses ahead (caught in an error scope of the thread) is left for the
//! frame, which makes it and reports its error where it is used.
//!
//! Besides a permutation's compute entry points, the threads make
//! generated shaders' pipelines (the fused light loop,
//! `shaders/generated.rs`: generated and composed here unless the
//! precompose threads did it first, and reflected for the frame's bind
//! groups), and render pipelines a frame's passes announce with the
//! function that builds them (never listed: a render pipeline's state is
//! code, not a name).

use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Condvar, Mutex, MutexGuard};
use std::time::{Duration, Instant};

use rustc_hash::FxHashMap;

use crate::shaders::generated::GeneratedKey;
use crate::shaders::{Reflection, ShaderComposer, ShaderKey};

/// Whether pipelines are created ahead (`SPREADLIGHT_PIPELINES_AHEAD=off|0`:
/// not, to measure the frame making them itself with the same list).
pub fn enabled() -> bool {
    !matches!(
        std::env::var("SPREADLIGHT_PIPELINES_AHEAD").as_deref(),
        Ok("off" | "0")
    )
}

/// Whether each pipeline made ahead is printed on stderr with when it
/// began and how long it took (`SPREADLIGHT_PIPELINES_AHEAD_LOG=1`).
fn log_jobs() -> bool {
    std::env::var_os("SPREADLIGHT_PIPELINES_AHEAD_LOG").is_some_and(|v| v != "0")
}

/// Whether a host waits for every listed pipeline before the first frame
/// (`SPREADLIGHT_PIPELINES_AHEAD=wait`): counts that do not depend on how
/// the threads were scheduled (tests), and how long making them all takes.
pub fn wait_before_first_frame() -> bool {
    std::env::var("SPREADLIGHT_PIPELINES_AHEAD").as_deref() == Ok("wait")
}

/// A pipeline made ahead, by what it is made of.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub enum PipelineId {
    /// A compute entry point of a permutation.
    Entry(ShaderKey, String),
    /// A generated shader's compute pipeline (its generator's entry point).
    Generated(GeneratedKey),
    /// A render pipeline of a permutation, by the variant its pass names
    /// it by (`ShaderCache::render_pipeline`); made by the [`RenderBuild`]
    /// its announcement brings.
    Render(ShaderKey, String),
}

impl PipelineId {
    /// A permutation's compute entry point.
    pub fn entry(key: &ShaderKey, entry: &str) -> PipelineId {
        PipelineId::Entry(key.clone(), entry.to_owned())
    }
}

/// How a render pipeline is made from its composed module, through the
/// pipeline cache given: what a pass's look-up builds, on a thread.
pub type RenderBuild = Arc<
    dyn Fn(&wgpu::Device, &wgpu::ShaderModule, Option<&wgpu::PipelineCache>) -> wgpu::RenderPipeline
        + Send
        + Sync,
>;

/// A pipeline to make ahead: what it is, and for a render pipeline how.
#[derive(Clone)]
pub struct Job {
    pub id: PipelineId,
    pub build: Option<RenderBuild>,
}

impl From<PipelineId> for Job {
    fn from(id: PipelineId) -> Job {
        Job { id, build: None }
    }
}

/// A pipeline made ahead, as the frame's look-up takes it.
#[derive(Clone, Debug)]
pub enum Made {
    Compute(wgpu::ComputePipeline),
    /// A generated shader's, with the reflection its bind groups are made by.
    Generated(wgpu::ComputePipeline, Arc<Reflection>),
    Render(wgpu::RenderPipeline),
}

/// Where one listed pipeline is.
enum Slot {
    /// No thread has begun it: the frame may make it itself.
    Queued,
    /// A thread is making it: the frame waits.
    Making,
    Ready(Made),
    /// Skipped (this build lacks its entry point) or refused by the device:
    /// the frame makes it, or never asks.
    Failed,
}

/// What creating ahead did (`cold_start` of the CLI's `--json`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct AheadStats {
    /// Pipelines in the list, the threads creating them.
    pub listed: usize,
    pub threads: usize,
    /// Made by the threads, and of those listed, the ones skipped or refused.
    pub created: usize,
    pub failed: usize,
    /// Frame look-ups that found theirs made, and that waited for a thread
    /// still making it (and how long, in all).
    pub taken: usize,
    pub waited: usize,
    pub wait: Duration,
    /// Listed pipelines the frame asked for before a thread began them
    /// (it made them itself).
    pub claimed: usize,
    /// From the start until the last thread ended (zero while one runs).
    pub wall: Duration,
    /// The threads' time on their pipelines, in all (composing a module
    /// where none was composed ahead, or waiting for another thread
    /// composing it, included); of it, creating shader modules (wgpu's
    /// validation of the composed module); and the longest one pipeline
    /// took. A `busy` near `threads` x `wall` while one pipeline takes far
    /// longer than when made alone means the driver made them one at a
    /// time (`SPREADLIGHT_PIPELINES_AHEAD_LOG=1` prints each on stderr).
    pub busy: Duration,
    pub modules: Duration,
    pub longest: Duration,
}

impl AheadStats {
    /// Add `other`'s counts (several runs of threads: a frame's each).
    pub fn add(&mut self, other: &AheadStats) {
        self.listed += other.listed;
        self.threads = self.threads.max(other.threads);
        self.created += other.created;
        self.failed += other.failed;
        self.taken += other.taken;
        self.waited += other.waited;
        self.wait += other.wait;
        self.claimed += other.claimed;
        self.wall += other.wall;
        self.busy += other.busy;
        self.modules += other.modules;
        self.longest = self.longest.max(other.longest);
    }
}

struct Shared {
    slots: Mutex<FxHashMap<PipelineId, Slot>>,
    changed: Condvar,
    stats: Mutex<AheadStats>,
}

/// Pipelines being created ahead, for a shader cache to take
/// (`ShaderCache::set_pipelines_ahead`). Cloning shares them.
#[derive(Clone)]
pub struct PipelinesAhead {
    shared: Arc<Shared>,
}

impl std::fmt::Debug for PipelinesAhead {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "PipelinesAhead({:?})", self.stats())
    }
}

/// `lock`'s guard, whether or not a thread panicked holding it (the slots
/// stay consistent: each change is one assignment).
fn locked<T>(lock: &Mutex<T>) -> MutexGuard<'_, T> {
    lock.lock().unwrap_or_else(|e| e.into_inner())
}

impl PipelinesAhead {
    /// Start creating `pipelines` (in the order the last run's first frame
    /// asked for them) on up to `threads` threads, on `device` through
    /// `cache` (the context's pipeline cache, as the frame's own pipelines).
    pub fn start(
        device: wgpu::Device,
        cache: Option<wgpu::PipelineCache>,
        pipelines: Vec<Job>,
        threads: usize,
    ) -> PipelinesAhead {
        let mut slots = FxHashMap::default();
        let mut order = Vec::with_capacity(pipelines.len());
        for job in pipelines {
            if slots.insert(job.id.clone(), Slot::Queued).is_none() {
                order.push(job);
            }
        }
        let threads = threads.clamp(1, order.len().max(1));
        let shared = Arc::new(Shared {
            slots: Mutex::new(slots),
            changed: Condvar::new(),
            stats: Mutex::new(AheadStats {
                listed: order.len(),
                threads,
                ..AheadStats::default()
            }),
        });
        let work = Arc::new(Work {
            order,
            next: AtomicUsize::new(0),
            running: AtomicUsize::new(threads),
            started: Instant::now(),
            device,
            cache,
        });
        for i in 0..threads {
            let (thread_shared, thread_work) = (shared.clone(), work.clone());
            let spawned = std::thread::Builder::new()
                .name(format!("pipelines ahead {i}"))
                .spawn(move || thread_work.run(&thread_shared));
            if spawned.is_err() {
                // No thread (the system refused one): what it would have
                // made stays queued for the others, or for the frame.
                work.ended(&shared);
            }
        }
        PipelinesAhead { shared }
    }

    /// The pipeline `id` made ahead: taken if ready, waited for if a
    /// thread is making it; None when it is not in the list, failed, or no
    /// thread began it yet (then no thread will: the caller makes it).
    pub fn take(&self, id: &PipelineId) -> Option<Made> {
        let mut slots = locked(&self.shared.slots);
        let mut waited = None;
        loop {
            match slots.get(id) {
                None | Some(Slot::Failed) => return None,
                Some(Slot::Queued) => {
                    slots.insert(id.clone(), Slot::Failed);
                    drop(slots);
                    locked(&self.shared.stats).claimed += 1;
                    return None;
                }
                Some(Slot::Making) => {
                    waited.get_or_insert_with(Instant::now);
                    slots = self
                        .shared
                        .changed
                        .wait(slots)
                        .unwrap_or_else(|e| e.into_inner());
                }
                Some(Slot::Ready(pipeline)) => {
                    let pipeline = pipeline.clone();
                    drop(slots);
                    let mut stats = locked(&self.shared.stats);
                    match waited {
                        Some(since) => {
                            stats.waited += 1;
                            stats.wait += since.elapsed();
                        }
                        None => stats.taken += 1,
                    }
                    return Some(pipeline);
                }
            }
        }
    }

    /// Whether `id` is in its list (made, being made or still to make).
    pub fn has(&self, id: &PipelineId) -> bool {
        locked(&self.shared.slots).contains_key(id)
    }

    /// What it did so far.
    pub fn stats(&self) -> AheadStats {
        *locked(&self.shared.stats)
    }

    /// Wait until every thread ended (tests; a caller that must know the counts are final).
    pub fn wait(&self) -> AheadStats {
        let mut slots = locked(&self.shared.slots);
        while slots.values().any(|s| matches!(s, Slot::Making))
            || locked(&self.shared.stats).wall == Duration::ZERO
        {
            slots = self
                .shared
                .changed
                .wait(slots)
                .unwrap_or_else(|e| e.into_inner());
        }
        drop(slots);
        self.stats()
    }
}

/// What the threads share: the list in order, the next to take.
struct Work {
    order: Vec<Job>,
    next: AtomicUsize,
    /// Threads still running; the last one to end notes the wall time.
    running: AtomicUsize,
    started: Instant,
    device: wgpu::Device,
    cache: Option<wgpu::PipelineCache>,
}

impl Work {
    fn run(&self, shared: &Shared) {
        // Made only where a permutation was not composed already (by
        // `crate::precompose`'s threads, which usually ran ahead of these).
        let mut composer: Option<ShaderComposer> = None;
        while let Some(job) = self.order.get(self.next.fetch_add(1, Ordering::Relaxed)) {
            let id = &job.id;
            {
                let mut slots = locked(&shared.slots);
                match slots.get_mut(id) {
                    Some(slot @ Slot::Queued) => *slot = Slot::Making,
                    // The frame claimed it first.
                    _ => continue,
                }
            }
            let began = Instant::now();
            let mut module_time = Duration::ZERO;
            let made = self.make(&mut composer, job, &mut module_time);
            let took = began.elapsed();
            let mut stats = locked(&shared.stats);
            match made {
                Some(_) => stats.created += 1,
                None => stats.failed += 1,
            }
            stats.busy += took;
            stats.modules += module_time;
            stats.longest = stats.longest.max(took);
            drop(stats);
            if log_jobs() {
                eprintln!(
                    "pipelines ahead: {id:?} began at {:.1} ms, took {:.1} ms (shader module {:.1} ms)",
                    (began - self.started).as_secs_f64() * 1e3,
                    took.as_secs_f64() * 1e3,
                    module_time.as_secs_f64() * 1e3,
                );
            }
            let slot = made.map_or(Slot::Failed, Slot::Ready);
            locked(&shared.slots).insert(id.clone(), slot);
            shared.changed.notify_all();
        }
        self.ended(shared);
    }

    /// One thread ended: the last notes the wall time.
    fn ended(&self, shared: &Shared) {
        if self.running.fetch_sub(1, Ordering::AcqRel) == 1 {
            // At least a nanosecond: zero means "still running" to `wait`.
            locked(&shared.stats).wall = self.started.elapsed().max(Duration::from_nanos(1));
            let _slots = locked(&shared.slots);
            shared.changed.notify_all();
        }
    }

    /// The pipeline as the shader cache's look-up makes it
    /// (`ShaderCache::compute_pipeline`, `generated_pipeline`,
    /// `render_pipeline`); None where the entry point is not a compute
    /// entry point of the module, the generator refuses the parts, a render
    /// pipeline came without its build, or the device refuses it.
    fn make(
        &self,
        composer: &mut Option<ShaderComposer>,
        job: &Job,
        module_time: &mut Duration,
    ) -> Option<Made> {
        match &job.id {
            PipelineId::Entry(key, entry) => {
                let module = self.module(composer, key)?;
                if !has_compute_entry(&module, entry) {
                    return None;
                }
                let label = format!("{}{}", key.path(), key.describe_defs());
                self.scoped(|| {
                    let shader = self.shader(&label, module, module_time);
                    let label = format!("{label}::{entry}");
                    Made::Compute(crate::shaders::compute_pipeline_of(
                        &self.device,
                        self.cache.as_ref(),
                        &shader,
                        &label,
                        entry,
                    ))
                })
            }
            PipelineId::Generated(key) => {
                let (label, module) = match crate::shaders::embedded_generated_or_wait(key) {
                    Some(made) => made,
                    None => composer_of(composer)?.generate(key).ok()?,
                };
                let entry = key.generator.entry;
                if !has_compute_entry(&module, entry) {
                    return None;
                }
                let reflection = Arc::new(super::reflection::reflect(&module, entry).ok()?);
                self.scoped(|| {
                    let shader = self.shader(&label, module, module_time);
                    let pipeline = crate::shaders::compute_pipeline_of(
                        &self.device,
                        self.cache.as_ref(),
                        &shader,
                        &format!("{label}::{entry}"),
                        entry,
                    );
                    Made::Generated(pipeline, reflection)
                })
            }
            PipelineId::Render(key, _) => {
                let build = job.build.as_ref()?;
                let module = self.module(composer, key)?;
                let label = format!("{}{}", key.path(), key.describe_defs());
                self.scoped(|| {
                    let shader = self.shader(&label, module, module_time);
                    Made::Render(build(&self.device, &shader, self.cache.as_ref()))
                })
            }
        }
    }

    /// Permutation `key` composed: by the precompose threads or another
    /// composer of the process, else by this thread's.
    fn module(
        &self,
        composer: &mut Option<ShaderComposer>,
        key: &ShaderKey,
    ) -> Option<naga::Module> {
        match crate::shaders::embedded_module(key) {
            Some(module) => Some(module),
            None => composer_of(composer)?.compose(key).ok(),
        }
    }

    /// The module made (validated by wgpu), its time added to `spent`.
    fn shader(
        &self,
        label: &str,
        module: naga::Module,
        spent: &mut Duration,
    ) -> wgpu::ShaderModule {
        let began = Instant::now();
        let shader = self
            .device
            .create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(label),
                source: wgpu::ShaderSource::Naga(std::borrow::Cow::Owned(module)),
            });
        *spent += began.elapsed();
        shader
    }

    /// `make`'s result, None where the device raised an error making it:
    /// errors of this thread's calls land in its own scopes, not in the
    /// device's uncaptured errors, which a host reports against its frame.
    fn scoped(&self, make: impl FnOnce() -> Made) -> Option<Made> {
        let scopes = [
            wgpu::ErrorFilter::OutOfMemory,
            wgpu::ErrorFilter::Internal,
            wgpu::ErrorFilter::Validation,
        ]
        .map(|filter| self.device.push_error_scope(filter));
        let made = make();
        // Popped innermost first, as they must be.
        let mut refused = false;
        for scope in scopes.into_iter().rev() {
            refused |= pollster::block_on(scope.pop()).is_some();
        }
        (!refused).then_some(made)
    }
}

/// Whether `module` has a compute entry point named `entry`.
fn has_compute_entry(module: &naga::Module, entry: &str) -> bool {
    module
        .entry_points
        .iter()
        .any(|e| e.name == entry && e.stage == naga::ShaderStage::Compute)
}

/// A thread's composer, made the first time one is needed (most
/// permutations were composed already by `crate::precompose`'s threads).
fn composer_of(composer: &mut Option<ShaderComposer>) -> Option<&mut ShaderComposer> {
    if composer.is_none() {
        *composer = ShaderComposer::new().ok();
    }
    composer.as_mut()
}

/// The threads to compose or create pipelines with: every core but the one
/// the main thread uses, at most 16.
pub fn threads() -> usize {
    std::thread::available_parallelism()
        .map_or(1, |n| n.get().saturating_sub(1))
        .clamp(1, 16)
}

#[cfg(test)]
mod tests;
