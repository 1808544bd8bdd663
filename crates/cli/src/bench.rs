//! `spreadlight bench`: time a patch's frames on the GPU. Every frame the
//! sinks render again (the rest of the patch stays cached, as in real use);
//! GPU times come from timestamp queries, medians over the timed frames, and
//! the adapter is named beside every figure. Prints one JSON line with
//! `--json` (the keys docs/bench/scene.md names).
//!
//! What it reports: the GPU frame span and every pass in frame order (names
//! may repeat), the idle time between them (span minus the passes' sum;
//! inside a shared compute pass a dispatch's barriers count in its pass's
//! time instead, `PassReport::idle_ms`),
//! CPU per frame split into patch evaluation and frame recording, and with
//! `--wall` the wall-clock time per frame with frames in flight (no
//! timestamps, nothing read back: what an interactive host gets) and the
//! CPU per frame there (`wall_cpu_*`, the tail after the last pass in
//! `wall_cpu_submit_ms_median`: timestamps cost CPU too, so these are the
//! frame's own CPU, not the measurement's).

use spreadlight_render::lighting::light_sets::{self, LightFusion, LightSums};
use spreadlight_render::packed_surface::{
    self as packed_surface, BLUR_INPUTS_VAR, MARCH_INPUTS_VAR, Reader, SurfaceInputs,
};
use spreadlight_render::renderer::{PassOrder, Recording, Submission, Timing};
use spreadlight_render::report::GraphTimings;
use spreadlight_render::resolution::{self, AutoChoice};

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::{Context, bail};
use spreadlight_graph::{Spread, format};

use crate::cold_start::ColdStart;
use crate::node_cpu::NodeCpu;
use crate::pin_arg::PinArg;
use crate::session::{Session, parse_size};

#[derive(clap::Args)]
pub struct Args {
    patch: PathBuf,
    #[arg(long, default_value = "1920x1080", value_parser = parse_size)]
    size: (u32, u32),
    /// Frames rendered before timing (pipelines compile, caches warm).
    #[arg(long, default_value_t = 50)]
    warmup: u64,
    /// Frames timed.
    #[arg(long, default_value_t = 200)]
    frames: u64,
    /// Override an input value: `NODE_ID.PIN=VALUE`, e.g. `--set "20.Input=10000"` (Int, Float, Bool, String or enum pins).
    #[arg(long = "set", value_name = "ID.PIN=VALUE")]
    sets: Vec<String>,
    /// Turn a Vec3 pin (a camera's position) about the vertical axis by
    /// RADIANS more each frame: `--orbit "9.Position=0.01"` times a still
    /// patch seen from a moving camera (sun cascades follow it). The pin is
    /// set and the patch reloaded before each frame, outside the CPU figures.
    #[arg(long, value_name = "ID.PIN=RADIANS")]
    orbit: Option<String>,
    /// Print one JSON line instead of a table.
    #[arg(long)]
    json: bool,
    /// Also time the frames back to back with no timestamps and no readback,
    /// up to two frames in flight: the wall-clock frame time of a host.
    #[arg(long)]
    wall: bool,
    /// Timestamps around every pass (`pass`) or only the frame's first and last (`frame`).
    #[arg(long, default_value = "pass", value_parser = ["pass", "frame"])]
    timing: String,
    /// Record the frame in one command encoder (`batched`, as the CLI and editor do) or each pass in its own (`isolated`).
    #[arg(long, default_value = "batched", value_parser = ["isolated", "batched"])]
    recording: String,
    /// Submit each frame on the recording thread (`inline`) or hand its
    /// tail (finishing the last encoders, the queue's submit) to a
    /// submission thread (`thread`), or `auto` (the thread on a GPU):
    /// docs/benchmarks.md, "cpu22". Unset: what SPREADLIGHT_SUBMIT says,
    /// else `inline`.
    #[arg(long, value_parser = ["inline", "thread", "auto"])]
    submit: Option<String>,
    /// Plan the frame graph afresh every frame instead of reusing last
    /// frame's plan while nothing declared changed: the same frames, for
    /// timing what the kept plan saves (`plans_reused` in `--json`).
    #[arg(long)]
    no_plan_reuse: bool,
    /// Look every dispatch's pipeline and bind groups up in the shader
    /// cache instead of taking what the same call resolved last frame on a
    /// kept plan: the same frames, for timing what that saves
    /// (`bind_groups_kept` in `--json`).
    #[arg(long)]
    no_kept_bindings: bool,
    /// The order the passes run in: `declared` (declaration order wherever
    /// the reads allow), `waves` (passes that read nothing of each other
    /// side by side, no barrier between them: docs/benchmarks.md, "Passes in
    /// waves") or `auto` (waves on a GPU, declared on a CPU adapter). Unset:
    /// what SPREADLIGHT_PASS_ORDER says, else `auto`.
    #[arg(long, value_parser = ["declared", "waves", "auto"])]
    schedule: Option<String>,
    /// Shade the CookTorrance nodes of one G-buffer in one dispatch
    /// (`fused`), a pass each (`separate`), or `auto` (fused on a GPU):
    /// docs/benchmarks.md, "Light sets in one dispatch". Unset: what
    /// SPREADLIGHT_LIGHT_FUSION says, else `auto`.
    #[arg(long, value_parser = ["separate", "fused", "auto"])]
    light_fusion: Option<String>,
    /// Where light sets fuse, sum them for CompositeLight (`on`: one pair
    /// of targets written and read, the sets' own made only where something
    /// else reads them) or write each set's targets (`off`):
    /// docs/benchmarks.md, "Light sets summed". Unset: what
    /// SPREADLIGHT_LIGHT_SUMS says, else `off`.
    #[arg(long, value_parser = ["on", "off"])]
    light_sums: Option<String>,
    /// What the depth-aware blurs of SSAO, SAO, HBAO and SSGI read a tap:
    /// the G-buffer's `packed` surface (one texel) or its depth and normals
    /// (`gbuffer`): docs/benchmarks.md, "The packed surface". Unset: what
    /// SPREADLIGHT_BLUR_INPUTS says, else `gbuffer`.
    #[arg(long, value_parser = ["packed", "gbuffer"])]
    blur_inputs: Option<String>,
    /// What SSAO's and SSGI's rays read a step: the `packed` view z (four
    /// steps' reads at a time) or the depth (`gbuffer`). Unset: what
    /// SPREADLIGHT_MARCH_INPUTS says, else `gbuffer`.
    #[arg(long, value_parser = ["packed", "gbuffer"])]
    march_inputs: Option<String>,
    /// Run a patch even though an unknown node type (misspelled, or a shader
    /// or subpatch file that is missing) feeds its Output or a Probe: that
    /// node's work is left out. Without it such a patch is an error.
    #[arg(long)]
    pub allow_unknown: bool,
}

/// One pass of the frame, in order, with its median.
#[derive(serde::Serialize)]
struct PassFigure {
    name: String,
    owner: Option<u32>,
    gpu_ms: Option<f64>,
    /// Median GPU idle time before the pass (after the previous one ended).
    idle_ms: Option<f64>,
    /// Median CPU time recording the pass (`PassReport::cpu_ms`).
    cpu_ms: Option<f64>,
}

fn median(mut v: Vec<f64>) -> Option<f64> {
    if v.is_empty() {
        return None;
    }
    v.sort_by(f64::total_cmp);
    Some(v[v.len() / 2])
}

/// Apply `ID.PIN=VALUE` to the patch, typed by the pin.
fn apply_set(patch: &mut spreadlight_graph::Patch, set: &str) -> anyhow::Result<()> {
    let PinArg {
        node,
        pin,
        value,
        ty,
    } = PinArg::parse(patch, "set", "VALUE", set)?;
    let bad = || anyhow::anyhow!("`--set {set}`: `{value}` is not a {ty}");
    let spread = match ty {
        spreadlight_graph::PinType::Float => Spread::Float(vec![value.parse().map_err(|_| bad())?]),
        spreadlight_graph::PinType::Int => Spread::Int(vec![value.parse().map_err(|_| bad())?]),
        spreadlight_graph::PinType::Bool => Spread::Bool(vec![value.parse().map_err(|_| bad())?]),
        spreadlight_graph::PinType::String => Spread::String(vec![value.to_owned()]),
        spreadlight_graph::PinType::Enum(options) => {
            if options.index_of(value).is_none() {
                bail!(
                    "`--set {set}`: `{value}` is not one of {}",
                    options.options.join(", ")
                );
            }
            Spread::Enum(vec![value.to_owned()])
        }
        other => bail!("`--set {set}`: pins of type {other} cannot be set from the command line"),
    };
    if let Some(node) = patch.node_mut(node) {
        node.values.insert(pin.to_owned(), spread);
    }
    Ok(())
}

/// The costliest nodes `bench` lists by their own CPU.
const NODES_SHOWN: usize = 6;

/// The effects with a Resolution pin and the counter each adds per node
/// that ran at half resolution.
const HALF_COUNTERS: [(&str, &str); 4] = [
    ("AO", spreadlight_render::ssao::HALF_RESOLUTION),
    ("SSGI", spreadlight_render::lighting::SSGI_HALF_RESOLUTION),
    ("SSR", spreadlight_render::environment::ssr::HALF_RESOLUTION),
    ("DOF", spreadlight_render::post::dof::HALF_RESOLUTION),
];

/// The passes as a map of name to median (docs/bench/scene.md's `passes`), a
/// name that repeats (the three SSSS passes of one node) numbered from its
/// second time on, so no pass is lost.
fn unique_names(passes: &[PassFigure]) -> serde_json::Map<String, serde_json::Value> {
    let mut seen = std::collections::HashMap::<&str, u32>::new();
    let mut map = serde_json::Map::new();
    for p in passes {
        let n = seen.entry(p.name.as_str()).or_default();
        *n += 1;
        let key = if *n == 1 {
            p.name.clone()
        } else {
            format!("{} ({n})", p.name)
        };
        map.insert(key, serde_json::json!(p.gpu_ms));
    }
    map
}

/// One pass's figures over the timed frames.
#[derive(Default)]
struct PassSeries {
    name: String,
    owner: Option<u32>,
    gpu: Vec<f64>,
    idle: Vec<f64>,
    cpu: Vec<f64>,
}

/// Per-frame figures of the timed frames.
#[derive(Default)]
struct Series {
    gpu: Vec<f64>,
    idle: Vec<f64>,
    cpu: Vec<f64>,
    eval: Vec<f64>,
    record: Vec<f64>,
    submit: Vec<f64>,
    queue_submit: Vec<f64>,
    /// The recording thread's waits for the submission thread (not CPU work).
    submission_wait: Vec<f64>,
    /// The submission thread's time per frame (empty inline).
    submission_thread: Vec<f64>,
    /// CPU per frame across threads: the recording thread's and the submission thread's.
    total: Vec<f64>,
    /// The recording thread's time per frame not waiting for the GPU:
    /// its CPU and its waits for the submission thread.
    critical: Vec<f64>,
    /// Frame graphs whose kept plan was reused, and those planned afresh.
    plans_reused: u64,
    plans_made: u64,
    /// Pipelines and bind groups dispatches took from their last frame's
    /// calls without a look-up, and bind groups made.
    pipelines_kept: u64,
    bind_groups_kept: u64,
    bind_groups_created: u64,
}

impl Series {
    /// The CPU figures of one frame that took `step_ms` on the clock, with
    /// every Output's graph `timings`: its CPU is the step without the
    /// waits for the GPU and for the submission thread (counted apart),
    /// split into evaluation and recording. Returns the CPU.
    fn push_frame(&mut self, step_ms: f64, timings: &GraphTimings) -> f64 {
        let cpu = (step_ms - timings.wait_ms - timings.submission_wait_ms).max(0.0);
        self.cpu.push(cpu);
        self.record.push(timings.record_ms);
        self.submit.push(timings.submit_ms);
        self.queue_submit.push(timings.queue_submit_ms);
        self.eval.push((cpu - timings.record_ms).max(0.0));
        self.submission_wait.push(timings.submission_wait_ms);
        let thread = timings.submission_thread_ms;
        self.submission_thread.extend(thread);
        self.total.push(cpu + thread.unwrap_or(0.0));
        self.critical.push(cpu + timings.submission_wait_ms);
        cpu
    }
}

/// Frames run back to back with timing off (frames in flight): what a host gets.
struct Wall {
    ms_per_frame: f64,
    /// Medians of the CPU per frame (evaluation + recording, no waiting
    /// for the GPU), with no timestamps written or read back.
    cpu: Series,
}

/// `args.frames` frames run back to back with timing off (frames in
/// flight), after `args.warmup` more to settle.
fn wall_clock(
    session: &mut Session,
    args: &Args,
    renderer: &spreadlight_render::Renderer,
    reported: &mut std::collections::BTreeSet<String>,
    turn: &mut dyn FnMut(&mut Session, u64),
) -> anyhow::Result<Wall> {
    let mut cpu = Series::default();
    let before = renderer.settings().0;
    renderer.set_timing(Timing::Off);
    // Nor the geometry passes' timestamps, which nothing reads here.
    let geometry = spreadlight_render::geometry::GeometryStats::of(renderer);
    let geometry_timed = geometry.timing();
    geometry.set_timing(false);
    let start_frame = args.warmup + args.frames.max(1);
    let mut started = std::time::Instant::now();
    for k in 0..args.warmup + args.frames.max(1) {
        if k == args.warmup {
            // Waiting here drains the warm-up frames out of the timed span.
            renderer.wait_idle()?;
            started = std::time::Instant::now();
        }
        let frame = start_frame + k;
        turn(session, frame);
        session.runtime.invalidate_sinks();
        renderer.take_graph_timings();
        let step = std::time::Instant::now();
        if session.step(frame, 60.0, &args.patch, reported) {
            bail!("frame {frame} failed (errors above)");
        }
        if k >= args.warmup {
            // Every Output's graph, not only the last one's; without the
            // wait for a frame in flight to finish.
            let timings = renderer.take_graph_timings();
            cpu.push_frame(step.elapsed().as_secs_f64() * 1e3, &timings);
        }
    }
    renderer.wait_idle()?;
    let ms = started.elapsed().as_secs_f64() * 1e3 / args.frames.max(1) as f64;
    renderer.set_timing(before);
    geometry.set_timing(geometry_timed);
    Ok(Wall {
        ms_per_frame: ms,
        cpu,
    })
}

pub fn run(args: &Args) -> anyhow::Result<ExitCode> {
    let mut patch = format::load(&args.patch)?;
    for set in &args.sets {
        apply_set(&mut patch, set)?;
    }
    let orbit = args
        .orbit
        .as_deref()
        .map(|text| crate::orbit::Orbit::parse(&patch, text))
        .transpose()?;
    let mut session = Session::build(
        &patch,
        &args.patch,
        true,
        Some(args.size),
        false,
        args.allow_unknown,
    )?;
    if session.load_errors {
        bail!("the patch has errors (above); fix them before timing it");
    }
    let renderer = session.renderer.clone().context("no renderer")?;
    renderer.set_timing(if args.timing == "frame" {
        Timing::Frame
    } else {
        Timing::PerPass
    });
    renderer.set_recording(if args.recording == "batched" {
        Recording::Batched
    } else {
        Recording::Isolated
    });
    let submission = match args.submit.as_deref().and_then(Submission::parse) {
        Some(submission) => submission,
        // A bench must not measure another setting than the one asked for.
        None => Submission::from_env().map_err(anyhow::Error::msg)?,
    };
    renderer.set_submission(submission);
    // The setting taken, `auto` resolved for this adapter.
    let submission = submission.on(renderer.gpu.adapter_class());
    renderer.set_plan_reuse(!args.no_plan_reuse);
    renderer.set_kept_bindings(!args.no_kept_bindings);
    if let Some(order) = args.schedule.as_deref().and_then(PassOrder::parse) {
        renderer.set_pass_order(order);
    }
    let fusion = match args.light_fusion.as_deref().and_then(LightFusion::parse) {
        Some(fusion) => fusion,
        // A bench must not measure another setting than the one asked for.
        None => LightFusion::from_env().map_err(anyhow::Error::msg)?,
    };
    light_sets::set_light_fusion(&renderer, fusion);
    let sums = match args.light_sums.as_deref().and_then(LightSums::parse) {
        Some(sums) => sums,
        None => LightSums::from_env().map_err(anyhow::Error::msg)?,
    };
    light_sets::set_light_sums(&renderer, sums);
    let light_sums = match sums {
        LightSums::On => "on",
        LightSums::Off => "off",
    };
    let surface_inputs = [
        (Reader::Blurs, &args.blur_inputs, BLUR_INPUTS_VAR),
        (Reader::Rays, &args.march_inputs, MARCH_INPUTS_VAR),
    ]
    .map(|(reader, flag, var)| {
        let inputs = match flag.as_deref().and_then(SurfaceInputs::parse) {
            Some(inputs) => inputs,
            // A bench must not measure another way than the one asked for.
            None => SurfaceInputs::from_env(var).map_err(anyhow::Error::msg)?,
        };
        packed_surface::set_inputs(&renderer, reader, inputs);
        anyhow::Ok(inputs.name())
    });
    let [blur_inputs, march_inputs] = surface_inputs;
    // What Resolution Auto resolves to (SPREADLIGHT_RESOLUTION_AUTO): a
    // bench must not measure another setting than the one asked for.
    let auto = AutoChoice::from_env().map_err(anyhow::Error::msg)?;
    resolution::set_auto_choice(&renderer, auto);
    let (blur_inputs, march_inputs) = (blur_inputs?, march_inputs?);
    let light_fusion = if fusion.fuses_on(renderer.gpu.adapter_class()) {
        "fused"
    } else {
        "separate"
    };
    // The order taken, `auto` resolved for this adapter.
    let schedule = match renderer.pass_order().on(renderer.gpu.adapter_class()) {
        PassOrder::Waves => "waves",
        _ => "declared",
    };
    // Geometry and particle passes run as their nodes evaluate: time them too.
    let geometry = spreadlight_render::geometry::GeometryStats::of(&renderer);
    geometry.set_timing(true);
    let mut reported = Default::default();
    let mut series = Series::default();
    let mut half_effects = HALF_COUNTERS.map(|(effect, _)| (effect, 0));
    // Per pass position (frames render the same passes in the same order).
    let mut passes: Vec<PassSeries> = Vec::new();
    let total = args.warmup + args.frames.max(1);
    let mut cold_start = None;
    // The orbiting pin moved and the patch reloaded (only that node re-evaluates).
    let mut turned = patch.clone();
    let mut turn = |session: &mut Session, frame: u64| {
        if let Some(orbit) = &orbit {
            orbit.place(&mut turned, frame);
            // The same patch but for one value: it loaded without problems above.
            let _ = session.runtime.load(&turned);
        }
    };
    let mut node_cpu = NodeCpu::default();
    for frame in 0..total {
        turn(&mut session, frame);
        session.runtime.invalidate_sinks();
        renderer.take_graph_timings();
        let started = std::time::Instant::now();
        if session.step(frame, 60.0, &args.patch, &mut reported) {
            bail!("frame {frame} failed (errors above)");
        }
        let wall_ms = started.elapsed().as_secs_f64() * 1e3;
        if frame == 0 {
            cold_start = Some(ColdStart::now(&session, wall_ms / 1e3));
            // What the first frame composed, for the next run to compose ahead.
            session.remember_permutations(&args.patch);
        }
        // Read after the frame's CPU time is taken: reading waits for the GPU.
        let geometry_ms = geometry.take_gpu_ms(&renderer.gpu)?;
        // Skinning (glTF skins and morph targets) is a part of the above, named apart.
        let skinning_ms = geometry.take_skinning_gpu_ms(&renderer.gpu)?;
        if frame < args.warmup {
            continue;
        }
        let report = renderer.last_report();
        // Every Output's graph (a patch may have several), not only the
        // last one's: what `report` holds.
        let timings = renderer.take_graph_timings();
        // CPU: evaluating the patch and recording the frame, without the
        // wait for the GPU.
        series.push_frame(wall_ms, &timings);
        series.plans_reused += report.counter("plans reused");
        series.plans_made += report.counter("plans made");
        series.pipelines_kept += report.counter("pipelines kept");
        series.bind_groups_kept += report.counter("bind groups kept");
        series.bind_groups_created += report.counter("bind groups created");
        // Which effects ran at half resolution (the last timed frame's).
        half_effects = HALF_COUNTERS.map(|(effect, counter)| (effect, report.counter(counter)));
        node_cpu.push(session.runtime.stats());
        if let Some(span) = timings.gpu_frame_ms {
            series.gpu.push(span + geometry_ms);
            if let Some(sum) = timings.gpu_ms {
                series.idle.push((span - sum).max(0.0));
            }
        }
        for (k, p) in report.passes.iter().enumerate() {
            if passes.len() <= k {
                passes.push(PassSeries {
                    name: p.name.clone(),
                    owner: p.owner,
                    ..Default::default()
                });
            }
            passes[k].gpu.extend(p.gpu_ms);
            passes[k].idle.extend(p.idle_ms);
            passes[k].cpu.push(p.cpu_ms);
        }
        if renderer.gpu.has_timestamps() {
            const GEOMETRY: &str = "geometry and particles (compute)";
            const SKINNING: &str = "skinning (compute)";
            // The skinning line appears once a patch has skinned something.
            let skinned = geometry.skinning_dispatches() > 0;
            let lines = [
                (GEOMETRY, (geometry_ms - skinning_ms).max(0.0)),
                (SKINNING, skinning_ms),
            ];
            for (name, ms) in lines.into_iter().take(if skinned { 2 } else { 1 }) {
                match passes.iter_mut().find(|p| p.name == name) {
                    Some(p) => p.gpu.push(ms),
                    None => passes.push(PassSeries {
                        name: name.to_owned(),
                        gpu: vec![ms],
                        ..Default::default()
                    }),
                }
            }
        }
    }
    let wall = if args.wall {
        Some(wall_clock(
            &mut session,
            args,
            &renderer,
            &mut reported,
            &mut turn,
        )?)
    } else {
        None
    };
    // The wall frames' figures across threads.
    let wall_threads = wall.as_ref().map_or((None, None, None, None), |w| {
        (
            median(w.cpu.submission_wait.clone()),
            median(w.cpu.submission_thread.clone()),
            median(w.cpu.total.clone()),
            median(w.cpu.critical.clone()),
        )
    });
    let wall_cpu = wall.as_ref().map_or((None, None, None, None), |w| {
        (
            median(w.cpu.cpu.clone()),
            median(w.cpu.eval.clone()),
            median(w.cpu.record.clone()),
            median(w.cpu.submit.clone()),
        )
    });
    let adapter = renderer.gpu.adapter_name();
    let passes: Vec<PassFigure> = passes
        .into_iter()
        .map(|p| PassFigure {
            name: p.name,
            owner: p.owner,
            gpu_ms: median(p.gpu),
            idle_ms: median(p.idle),
            cpu_ms: median(p.cpu),
        })
        .collect();
    let (gpu, cpu) = (median(series.gpu), median(series.cpu));
    let (idle, eval, record, submit) = (
        median(series.idle),
        median(series.eval),
        median(series.record),
        median(series.submit),
    );
    if args.json {
        let mut line = serde_json::json!({
            "patch": args.patch.display().to_string(),
            "size": format!("{}x{}", args.size.0, args.size.1),
            "sets": args.sets,
            "orbit": args.orbit,
            "adapter": adapter,
            "frames": args.frames,
            "timing": args.timing,
            "recording": args.recording,
            "schedule": schedule,
            "light_fusion": light_fusion,
            "light_sums": light_sums,
            "blur_inputs": blur_inputs,
            "march_inputs": march_inputs,
            "resolution_auto": auto.name(),
            // Per effect, how many of its nodes ran at half resolution
            // (Auto resolved, or set); the rest ran at Full.
            "half_resolution": half_effects
                .iter()
                .map(|&(effect, n)| (effect.to_owned(), serde_json::json!(n)))
                .collect::<serde_json::Map<_, _>>(),
            "gpu_ms_median": gpu,
            "gpu_idle_ms_median": idle,
            "cpu_ms_median": cpu,
            "cpu_eval_ms_median": eval,
            "cpu_record_ms_median": record,
            "cpu_submit_ms_median": submit,
            "cpu_queue_submit_ms_median": median(series.queue_submit),
            // Over the timed frames (not `--wall`'s).
            "plans_reused": series.plans_reused,
            "plans_made": series.plans_made,
            "pipelines_kept": series.pipelines_kept,
            "bind_groups_kept": series.bind_groups_kept,
            "bind_groups_created": series.bind_groups_created,
            "wall_ms_per_frame": wall.as_ref().map(|w| w.ms_per_frame),
            "wall_cpu_ms_median": wall_cpu.0,
            "wall_cpu_eval_ms_median": wall_cpu.1,
            "wall_cpu_record_ms_median": wall_cpu.2,
            // The tail after the last pass with no timestamps to resolve.
            "wall_cpu_submit_ms_median": wall_cpu.3,
            "passes": unique_names(&passes),
            "pass_order": passes,
            "cold_start": cold_start.map(|c| c.json()),
        });
        // The costliest nodes' own CPU (node_cpu.rs): where evaluation goes.
        let nodes = serde_json::json!({ "node_cpu_ms_median": node_cpu.costliest(NODES_SHOWN) });
        // Where frames were submitted, and the figures across threads (a
        // second object: one `json!` of them all passes the macro's recursion limit).
        let threads = serde_json::json!({
            "submit": submission.name(),
            // The recording thread's waits for the submission thread, the
            // submission thread's CPU, the CPU across both threads, and the
            // recording thread's time not waiting for the GPU (CPU + waits).
            "cpu_submission_wait_ms_median": median(series.submission_wait.clone()),
            "cpu_submission_thread_ms_median": median(series.submission_thread.clone()),
            "cpu_total_ms_median": median(series.total.clone()),
            "cpu_critical_ms_median": median(series.critical.clone()),
            "wall_cpu_submission_wait_ms_median": wall_threads.0,
            "wall_cpu_submission_thread_ms_median": wall_threads.1,
            "wall_cpu_total_ms_median": wall_threads.2,
            "wall_cpu_critical_ms_median": wall_threads.3,
        });
        if let Some(line) = line.as_object_mut() {
            for part in [threads, nodes] {
                if let serde_json::Value::Object(part) = part {
                    line.extend(part);
                }
            }
        }
        println!("{line}");
    } else {
        println!(
            "{} at {}x{} on {adapter}, median of {} frames ({} timing, {} recording, {schedule} order, light sets {light_fusion}, light sums {light_sums}, blurs read {blur_inputs}, rays {march_inputs}, Resolution Auto {}: {})",
            args.patch.display(),
            args.size.0,
            args.size.1,
            args.frames,
            args.timing,
            args.recording,
            auto.name(),
            half_effects
                .iter()
                .map(|(effect, n)| format!("{effect} half {n}"))
                .collect::<Vec<_>>()
                .join(", ")
        );
        let show =
            |v: Option<f64>| v.map_or("n/a (no timestamps)".to_owned(), |ms| format!("{ms:.3} ms"));
        if let Some(cold) = cold_start {
            println!("  {}", cold.line());
        }
        println!("  GPU frame              {}", show(gpu));
        println!("  GPU idle between passes {}", show(idle));
        println!("  CPU frame              {}", show(cpu));
        println!("    evaluating the patch {}", show(eval));
        for n in node_cpu.costliest(NODES_SHOWN) {
            let name = format!("{} #{}", n.type_name, n.node);
            println!("      {name:<38} {:.3} ms", n.median_ms);
        }
        println!("    recording the frame  {}", show(record));
        println!("      of which finishing and submitting {}", show(submit));
        if submission == Submission::Thread {
            println!(
                "    submission thread    {} (waited for {}; CPU across threads {})",
                show(median(series.submission_thread.clone())),
                show(median(series.submission_wait.clone())),
                show(median(series.total.clone()))
            );
        }
        println!(
            "    frame graph plans  {} reused, {} made",
            series.plans_reused, series.plans_made
        );
        println!(
            "    dispatches kept    {} pipelines, {} bind groups ({} bind groups made)",
            series.pipelines_kept, series.bind_groups_kept, series.bind_groups_created
        );
        if let Some(w) = &wall {
            println!(
                "  wall clock, frames in flight {:.3} ms a frame (CPU {} = {} + {}, no timestamps)",
                w.ms_per_frame,
                show(wall_cpu.0),
                show(wall_cpu.1),
                show(wall_cpu.2)
            );
        }
        for p in &passes {
            // The idle time before a pass, where it is worth a look.
            let idle = p
                .idle_ms
                .filter(|&ms| ms >= 0.0005)
                .map_or(String::new(), |ms| format!("  (idle before {ms:.3} ms)"));
            let cpu = p
                .cpu_ms
                .map_or(String::new(), |ms| format!("  (CPU {ms:.3} ms)"));
            println!("  {:<44} {}{idle}{cpu}", p.name, show(p.gpu_ms));
        }
    }
    Ok(ExitCode::SUCCESS)
}
