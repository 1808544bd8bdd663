//! `spreadlight bench`: time a patch's frames on the GPU. Every frame the
//! sinks render again (the rest of the patch stays cached, as in real use);
//! GPU times come from timestamp queries, medians over the timed frames, and
//! the adapter is named beside every figure. Prints one JSON line with
//! `--json` (the keys of shared/bench/README.md).

use std::collections::BTreeMap;
use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::{Context, bail};
use spreadlight_graph::{NodeId, Spread, format};

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
    /// Print one JSON line instead of a table.
    #[arg(long)]
    json: bool,
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
    let (target, value) = set
        .rsplit_once('=')
        .with_context(|| format!("`--set {set}`: expected ID.PIN=VALUE"))?;
    let (id, pin) = target
        .split_once('.')
        .with_context(|| format!("`--set {set}`: expected ID.PIN=VALUE"))?;
    let id: u32 = id
        .trim()
        .trim_start_matches('#')
        .parse()
        .with_context(|| format!("`--set {set}`: `{id}` is not a node id"))?;
    let registry = spreadlight_nodes::registry();
    let node = patch
        .node_mut(NodeId(id))
        .with_context(|| format!("`--set {set}`: the patch has no node #{id}"))?;
    let def = registry
        .get(&node.type_name)
        .with_context(|| format!("`--set {set}`: node #{id} has an unknown type"))?;
    let k = def.input_index(pin).with_context(|| {
        format!(
            "`--set {set}`: node #{id} `{}` has no input `{pin}`",
            def.name
        )
    })?;
    let bad = || anyhow::anyhow!("`--set {set}`: `{value}` is not a {}", def.inputs[k].ty);
    let spread = match def.inputs[k].ty {
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
    node.values.insert(pin.to_owned(), spread);
    Ok(())
}

pub fn run(args: &Args) -> anyhow::Result<ExitCode> {
    let mut patch = format::load(&args.patch)?;
    for set in &args.sets {
        apply_set(&mut patch, set)?;
    }
    let mut session = Session::build(&patch, &args.patch, true, Some(args.size), false)?;
    if session.load_errors {
        bail!("the patch has errors (above); fix them before timing it");
    }
    let renderer = session.renderer.clone().context("no renderer")?;
    // Geometry and particle passes run as their nodes evaluate: time them too.
    let geometry = spreadlight_render::geometry::GeometryStats::of(&renderer);
    geometry.set_timing(true);
    let mut reported = Default::default();
    let (mut gpu, mut cpu) = (Vec::new(), Vec::new());
    let mut passes: BTreeMap<String, Vec<f64>> = BTreeMap::new();
    let total = args.warmup + args.frames.max(1);
    for frame in 0..total {
        session.runtime.invalidate_sinks();
        let started = std::time::Instant::now();
        if session.step(frame, 60.0, &args.patch, &mut reported) {
            bail!("frame {frame} failed (errors above)");
        }
        let wall_ms = started.elapsed().as_secs_f64() * 1e3;
        let geometry_ms = geometry.take_gpu_ms();
        if frame < args.warmup {
            continue;
        }
        let report = renderer.last_report();
        if let Some(ms) = report.gpu_frame_ms {
            gpu.push(ms + geometry_ms);
        }
        if renderer.gpu.has_timestamps() {
            passes
                .entry("geometry and particles (compute)".to_owned())
                .or_default()
                .push(geometry_ms);
        }
        // CPU: evaluating the patch and recording the frame, without the wait for the GPU.
        cpu.push((wall_ms - report.wait_ms).max(0.0));
        for p in &report.passes {
            if let Some(ms) = p.gpu_ms {
                passes.entry(p.name.clone()).or_default().push(ms);
            }
        }
    }
    let adapter = renderer.gpu.adapter_name();
    let gpu_median = median(gpu);
    let cpu_median = median(cpu);
    let pass_medians: BTreeMap<String, Option<f64>> =
        passes.into_iter().map(|(k, v)| (k, median(v))).collect();
    if args.json {
        let line = serde_json::json!({
            "patch": args.patch.display().to_string(),
            "size": format!("{}x{}", args.size.0, args.size.1),
            "sets": args.sets,
            "adapter": adapter,
            "frames": args.frames,
            "gpu_ms_median": gpu_median,
            "cpu_ms_median": cpu_median,
            "passes": pass_medians,
        });
        println!("{line}");
    } else {
        println!(
            "{} at {}x{} on {adapter}, median of {} frames",
            args.patch.display(),
            args.size.0,
            args.size.1,
            args.frames
        );
        let show =
            |v: Option<f64>| v.map_or("n/a (no timestamps)".to_owned(), |ms| format!("{ms:.3} ms"));
        println!("  GPU frame  {}", show(gpu_median));
        println!("  CPU frame  {}", show(cpu_median));
        for (name, ms) in &pass_medians {
            println!("  {name:<40} {}", show(*ms));
        }
    }
    Ok(ExitCode::SUCCESS)
}
