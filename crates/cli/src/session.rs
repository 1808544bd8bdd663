//! A loaded patch ready to run: the runtime, and the renderer when the patch
//! has GPU nodes. Shared by `eval`, `render` and `stats`.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use anyhow::Context;
use spreadlight_graph::subpatch::Library;
use spreadlight_graph::{
    FrameClock, Memory, Network, NodeId, Patch, Problem, ProblemKind, Registry, Runtime, Severity,
    format,
};
use spreadlight_nodes::gpu::GPU_CATEGORIES;
use spreadlight_nodes::output::RenderedImages;
use spreadlight_nodes::shader_nodes::ShaderLibrary;
use spreadlight_render::Renderer;
use spreadlight_render::context::GpuContext;
use spreadlight_render::error::RenderError;
use spreadlight_render::pipelines_ahead::{self, Job, PipelineId, PipelinesAhead};
use spreadlight_render::precompose::{self, Precomposed};

pub struct Session {
    pub runtime: Runtime,
    pub renderer: Option<Arc<Renderer>>,
    pub images: Arc<RenderedImages>,
    /// Whether loading reported errors (they are printed already).
    pub load_errors: bool,
    /// Where opening it went: the start of a fresh process's cold start.
    pub opened: Opened,
}

/// Seconds opening a session took, by step (`cold_start.rs` reports them).
#[derive(Clone, Copy, Debug, Default)]
pub struct Opened {
    /// The node registry with the shader nodes of the user's library and the patch's folder.
    pub registry: f64,
    /// Of which the built-in node types (shader node examples are made when looked up).
    pub registry_nodes: f64,
    /// The patch compiled against the registry (does it need a GPU), its runtime made.
    pub network: f64,
    /// The adapter and device, the renderer with its shader libraries.
    pub gpu: f64,
    /// Of the start's own time, how long it waited for the GPU: `gpu` where
    /// it opened it itself; less where the GPU opened on a thread of its
    /// own beside the patch's parsing and the registry ([`OpeningGpu`]).
    pub gpu_waited: f64,
    /// The patch loaded into the runtime (nodes made, files they read at load).
    pub load: f64,
    /// The permutations composed ahead (`spreadlight_render::precompose`),
    /// with a damaged list's warning; None without a list.
    pub precompose: Option<Precomposed>,
}

/// The list of permutations `path`'s patch composed last time (`precompose.rs` in render).
fn permutation_list(path: &Path) -> PathBuf {
    let name = std::fs::canonicalize(path).unwrap_or_else(|_| path.to_path_buf());
    precompose::list_path(&name.display().to_string())
}

/// What the last run of a patch left to do ahead: its permutations being
/// composed on threads of their own, and the compute pipelines to create
/// once the device is open.
struct Ahead {
    composing: precompose::Precomposing,
    pipelines: Vec<PipelineId>,
}

/// Start opening the GPU on a thread where `force_gpu`, then composing
/// the last run's list of the patch at `path` on threads of their own (so
/// that the threads compose while the registry and the GPU are made); the
/// GPU's thread gets the list's pipelines once it is read.
fn start_opening(path: &Path, force_gpu: bool) -> (Option<OpeningGpu>, Option<Ahead>) {
    let (send, listed) = std::sync::mpsc::channel();
    let opening = force_gpu.then(|| OpeningGpu::start(listed)).flatten();
    let precomposing = start_precompose(path);
    if opening.is_some() {
        // The thread may have ended already (no adapter): nothing is lost.
        let _ = send.send(listed_pipelines(&precomposing));
    }
    (opening, precomposing)
}

/// The compute pipelines the last run's list names (none without a list).
fn listed_pipelines(ahead: &Option<Ahead>) -> Vec<PipelineId> {
    ahead
        .as_ref()
        .map_or_else(Vec::new, |ahead| ahead.pipelines.clone())
}

/// Start composing, on threads of their own, what the patch at `path`
/// composed last time; None without a list (a warning for a damaged one).
fn start_precompose(path: &Path) -> Option<Ahead> {
    if !precompose::enabled() {
        return None;
    }
    let list = permutation_list(path);
    match precompose::read(&list) {
        Ok(Some(list)) if !list.keys.is_empty() || !list.generated.is_empty() => Some(Ahead {
            composing: precompose::start(list.keys, list.generated, precompose::threads()),
            pipelines: list.pipelines,
        }),
        Ok(_) => None,
        Err(e) => {
            eprintln!("warning: {e}; composing shaders as they are needed (it is rewritten)");
            None
        }
    }
}

/// A renderer being opened on a thread of its own, from the start of a
/// session that needs the GPU whatever the patch holds (`render`, `bench`,
/// `view`): the driver's adapter and device (about 0.2 s on the H200 host)
/// overlap parsing the patch, the registry and the network.
///
/// The same thread starts creating the last run's pipelines the moment
/// the device is open, before the renderer's own setup (about 18 ms on the
/// H200 host): a warm start's first frame waits for those pipelines, which
/// the driver makes one at a time (docs/benchmarks.md, "Session 25").
pub struct OpeningGpu {
    thread: std::thread::JoinHandle<OpenedGpu>,
}

/// What the thread opening the GPU hands back: the renderer (or why there
/// is none), the pipelines it started making, the seconds it took.
type OpenedGpu = (Result<Renderer, RenderError>, Option<PipelinesAhead>, f64);

impl OpeningGpu {
    /// Start opening it, and then making the pipelines `listed` brings (the
    /// last run's list, sent once read; none if the sender is dropped
    /// unsent); None where no thread could be made (the session opens it
    /// itself, as before). The list comes by channel so that the driver
    /// starts before the list is read and the threads composing it start.
    pub fn start(listed: std::sync::mpsc::Receiver<Vec<PipelineId>>) -> Option<OpeningGpu> {
        std::thread::Builder::new()
            .name("open gpu".to_owned())
            .spawn(move || {
                let started = std::time::Instant::now();
                let (renderer, making) = match GpuContext::headless() {
                    Ok(gpu) => {
                        let pipelines = listed.recv().unwrap_or_default();
                        let making = start_pipelines_ahead(&gpu, pipelines);
                        let renderer = Renderer::new(gpu);
                        if let (Ok(renderer), Some(making)) = (&renderer, &making) {
                            renderer.shaders().set_pipelines_ahead(making.clone());
                        }
                        (renderer, making)
                    }
                    Err(e) => (Err(e), None),
                };
                (renderer, making, started.elapsed().as_secs_f64())
            })
            .ok()
            .map(|thread| OpeningGpu { thread })
    }

    /// The renderer (or why there is none), the pipelines being made ahead,
    /// and the seconds opening it took on its thread.
    fn finish(self) -> anyhow::Result<OpenedGpu> {
        self.thread
            .join()
            .map_err(|_| anyhow::anyhow!("the thread opening the GPU panicked"))
    }
}

/// Start creating `pipelines` (the last run's list) on threads of their own
/// on `gpu`'s device; None where the list is empty or that is turned off.
fn start_pipelines_ahead(gpu: &GpuContext, pipelines: Vec<PipelineId>) -> Option<PipelinesAhead> {
    if pipelines.is_empty() || !pipelines_ahead::enabled() {
        return None;
    }
    Some(PipelinesAhead::start(
        gpu.device.clone(),
        gpu.pipeline_cache().cloned(),
        pipelines.into_iter().map(Job::from).collect(),
        precompose::threads(),
    ))
}

/// A load problem as a headless command reports it: its line, and its
/// severity there. An unknown node type is kept as a placeholder that
/// outputs nothing; one that feeds a sink (an Output, a Probe) would let the
/// command succeed without that node's work (a misspelled `CookTorance`
/// renders the frame unlit), so here it is an error unless `allow_unknown`.
/// The editor keeps it a warning: there a type may be half written. For a
/// shader node type the line names the file that would make it and the
/// folders searched.
pub fn headless_problem(problem: &Problem, path: &Path, allow_unknown: bool) -> (Severity, String) {
    let mut severity = problem.severity;
    let mut note = String::new();
    if let ProblemKind::UnknownNodeType { feeds, .. } = &problem.kind {
        if let Some(missing) = ShaderLibrary::for_patch(Some(path)).missing_file(&problem.node_type)
        {
            note = format!("; {missing}");
        }
        if feeds.is_some() && !allow_unknown {
            severity = Severity::Error;
            note.push_str(" (--allow-unknown runs the patch without it)");
        }
    }
    let line = Problem {
        severity,
        ..problem.clone()
    }
    .located(path);
    (severity, line + &note)
}

/// Whether any node of the patch, or of a subpatch in it, needs a GPU
/// (shader nodes always do).
pub fn needs_gpu(patch: &Patch, path: &Path, registry: &Registry) -> bool {
    let library = Library::beside(path.parent().unwrap_or(Path::new("")));
    let network = Network::compile_with(patch, registry, &library);
    network
        .nodes()
        .iter()
        .filter_map(|n| n.def.as_ref())
        .any(|def| GPU_CATEGORIES.contains(&&*def.category) || def.category.starts_with("Shader"))
}

/// How many earlier frames the nodes of the patch that run remember, and the
/// node types that make it so ([`Network::memory`]): what a render that
/// starts past frame 0 must evaluate first to match a run from frame 0.
pub fn memory(patch: &Patch, path: &Path) -> (Memory, Vec<String>) {
    let (registry, _) = registry_for(Some(path));
    let library = Library::beside(path.parent().unwrap_or(Path::new("")));
    Network::compile_with(patch, &registry, &library).memory()
}

/// The node types a patch can use: the built-in ones plus the shader nodes of
/// the user's library and of the `shaders/` folder beside the patch. Files that
/// do not compile are returned (their nodes show the error too).
pub fn registry_for(path: Option<&Path>) -> (Registry, Vec<String>) {
    let mut registry = spreadlight_nodes::registry();
    let errors = poll_shader_library(path, &mut registry);
    (registry, errors)
}

/// Add the shader nodes of the user's library and of the `shaders/` folder
/// beside the patch to `registry`; the errors of files that do not compile.
fn poll_shader_library(path: Option<&Path>, registry: &mut Registry) -> Vec<String> {
    let mut library = ShaderLibrary::for_patch(path);
    library.poll(registry);
    library
        .errors()
        .values()
        .map(|e| format!("error: {e}"))
        .collect()
}

impl Session {
    /// Load `path`; open a GPU if the patch needs one or `force_gpu` says so.
    /// `allow_unknown`: see [`headless_problem`].
    pub fn open(
        path: &Path,
        force_gpu: bool,
        size: Option<(u32, u32)>,
        allow_unknown: bool,
    ) -> anyhow::Result<Self> {
        // Opened beside the patch's parsing when it is needed for sure.
        let (opening, precomposing) = start_opening(path, force_gpu);
        let patch = format::load(path)?;
        Self::build_opening(
            &patch,
            path,
            size,
            true,
            allow_unknown,
            (opening, precomposing),
            force_gpu,
        )
    }

    pub fn from_patch(
        patch: &Patch,
        path: &Path,
        force_gpu: bool,
        size: Option<(u32, u32)>,
    ) -> anyhow::Result<Self> {
        Self::build(patch, path, force_gpu, size, true, false)
    }

    /// `capture`: whether Output nodes read their images back for the host (a benchmark does not).
    pub fn build(
        patch: &Patch,
        path: &Path,
        force_gpu: bool,
        size: Option<(u32, u32)>,
        capture: bool,
        allow_unknown: bool,
    ) -> anyhow::Result<Self> {
        let (opening, precomposing) = start_opening(path, force_gpu);
        Self::build_opening(
            patch,
            path,
            size,
            capture,
            allow_unknown,
            (opening, precomposing),
            force_gpu,
        )
    }

    /// [`Session::build`] with the GPU perhaps being opened already.
    fn build_opening(
        patch: &Patch,
        path: &Path,
        size: Option<(u32, u32)>,
        capture: bool,
        allow_unknown: bool,
        (opening, precomposing): (Option<OpeningGpu>, Option<Ahead>),
        force_gpu: bool,
    ) -> anyhow::Result<Self> {
        let started = std::time::Instant::now();
        let mut opened = Opened::default();
        let mut registry = spreadlight_nodes::registry();
        opened.registry_nodes = started.elapsed().as_secs_f64();
        let shader_errors = poll_shader_library(Some(path), &mut registry);
        opened.registry = started.elapsed().as_secs_f64();
        for error in &shader_errors {
            eprintln!("{error}");
        }
        let started = std::time::Instant::now();
        let gpu = force_gpu || needs_gpu(patch, path, &registry);
        let mut runtime = Runtime::new(registry);
        opened.network = started.elapsed().as_secs_f64();
        let dir = path.parent().unwrap_or(Path::new("")).to_path_buf();
        runtime.provide(Arc::new(spreadlight_graph::PatchDir(dir)));
        let images = Arc::new(RenderedImages::default());
        if capture {
            runtime.provide(images.clone());
        }
        let started = std::time::Instant::now();
        let mut pipelines_making = None;
        let mut gpu_on_thread = None;
        let renderer = if gpu {
            let (renderer, making, on_thread) = match opening {
                Some(opening) => {
                    let (renderer, making, seconds) = opening.finish()?;
                    (renderer, making, Some(seconds))
                }
                None => (Renderer::headless(), None, None),
            };
            let renderer = Arc::new(renderer.context("cannot open the GPU this patch needs")?);
            gpu_on_thread = on_thread;
            // The device is open: the last run's pipelines are created on
            // threads while the patch loads and its first frame evaluates
            // (started by the thread that opened it, else here).
            pipelines_making = making.or_else(|| {
                let making = start_pipelines_ahead(&renderer.gpu, listed_pipelines(&precomposing))?;
                renderer.shaders().set_pipelines_ahead(making.clone());
                Some(making)
            });
            // A few command encoders a frame, not one a pass: 1.2 ms less CPU
            // on post.ron on the H100 (docs/benchmarks.md); a failing frame falls back to
            // recording pass by pass, which names the pass.
            renderer.set_recording(spreadlight_render::renderer::Recording::Batched);
            if let Some(size) = size {
                // Past the adapter's largest texture nothing could render: say so before any work.
                let max = renderer.gpu.device.limits().max_texture_dimension_2d;
                if size.0 > max || size.1 > max {
                    anyhow::bail!(
                        "--size {}x{} is past the adapter's limit max_texture_dimension_2d ({max}) on {}",
                        size.0,
                        size.1,
                        renderer.gpu.adapter_name()
                    );
                }
                renderer.set_output_size(size);
            }
            spreadlight_nodes::gpu::provide_renderer(&mut runtime, renderer.clone());
            Some(renderer)
        } else {
            None
        };
        opened.gpu_waited = started.elapsed().as_secs_f64();
        // On a thread: its own time; the setup after the wait (the
        // renderer's settings, the pipelines started) counts as waiting.
        opened.gpu = gpu_on_thread.unwrap_or(opened.gpu_waited);
        let started = std::time::Instant::now();
        let mut load_errors = !shader_errors.is_empty();
        for problem in runtime.load(patch) {
            let (severity, line) = headless_problem(problem, path, allow_unknown);
            eprintln!("{line}");
            load_errors |= severity == Severity::Error;
        }
        opened.load = started.elapsed().as_secs_f64();
        opened.precompose = precomposing.map(|ahead| ahead.composing.finish());
        if let Some(making) =
            pipelines_making.filter(|_| pipelines_ahead::wait_before_first_frame())
        {
            making.wait();
        }
        Ok(Session {
            runtime,
            renderer,
            images,
            load_errors,
            opened,
        })
    }

    /// Remember the permutations the renderer composed so far and its
    /// compute pipelines, for the next run of the patch at `path` to compose
    /// and create ahead (`precompose.rs`, `pipelines_ahead.rs` in render).
    pub fn remember_permutations(&self, path: &Path) {
        let Some(renderer) = self.renderer.as_ref().filter(|_| precompose::enabled()) else {
            return;
        };
        let shaders = renderer.shaders();
        let keys = shaders.used_permutations();
        if keys.is_empty() {
            return;
        }
        let list = permutation_list(path);
        if let Err(e) = precompose::remember(&list, &keys, shaders.compute_pipelines_used()) {
            // Nothing else is lost: the next run composes as the first frame needs.
            eprintln!(
                "warning: could not save the permutation list {}: {e}",
                list.display()
            );
        }
    }

    /// Evaluate frame `frame` at `fps`; print node errors and GPU pass errors
    /// (each with the node it belongs to) the first time they appear.
    pub fn step(
        &mut self,
        frame: u64,
        fps: f64,
        path: &Path,
        reported: &mut std::collections::BTreeSet<String>,
    ) -> bool {
        self.runtime.evaluate(FrameClock::fixed(frame, fps));
        let errors = self.frame_errors(path);
        for line in &errors {
            if reported.insert(line.clone()) {
                eprintln!("{line} (frame {frame})");
            }
        }
        !errors.is_empty()
    }

    /// The errors of the frame just evaluated: failed nodes and failed GPU
    /// passes, each with the node it belongs to.
    pub fn frame_errors(&self, path: &Path) -> Vec<String> {
        let mut errors = Vec::new();
        for (node, error) in self.runtime.node_errors_at() {
            let node = path_text(node);
            errors.push(format!("error: {}: node {node}: {error}", path.display()));
        }
        if let Some(renderer) = &self.renderer {
            for (owner, error) in renderer.last_errors() {
                let node = owner.map_or("the renderer".to_owned(), |n| {
                    let place = self.runtime.path_of(NodeId(n));
                    format!("node {}", place.map_or(format!("#{n}"), path_text))
                });
                errors.push(format!("error: {}: {node}: {error}", path.display()));
            }
        }
        errors
    }
}

/// A node's place: `#4` at the top, `#4 > #2` inside the subpatch node #4.
pub fn path_text(path: &[NodeId]) -> String {
    let parts: Vec<String> = path.iter().map(|id| id.to_string()).collect();
    parts.join(" > ")
}

/// Parse `WIDTHxHEIGHT`.
pub fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("`{s}` is not WIDTHxHEIGHT (e.g. 1920x1080)"))?;
    let parse = |v: &str| {
        v.trim()
            .parse::<u32>()
            .ok()
            .filter(|v| (1..=16384).contains(v))
    };
    match (parse(w), parse(h)) {
        (Some(w), Some(h)) => Ok((w, h)),
        _ => Err(format!(
            "`{s}`: width and height must be whole numbers from 1 to 16384"
        )),
    }
}
