//! `spreadlight stats`: what a frame of a patch did — the runtime's counts
//! and the frame graph's passes, culls, compiles, draws and GPU times.

use std::collections::BTreeSet;
use std::path::PathBuf;
use std::process::ExitCode;

use crate::session::{Session, parse_size};

#[derive(clap::Args)]
pub struct Args {
    patch: PathBuf,
    /// Frames to evaluate first; the statistics are the last frame's.
    #[arg(long, default_value_t = 1)]
    frames: u64,
    #[arg(long, default_value = "640x360", value_parser = parse_size)]
    size: (u32, u32),
    /// Print JSON instead of text.
    #[arg(long)]
    json: bool,
    /// Run a patch even though an unknown node type (misspelled, or a shader
    /// or subpatch file that is missing) feeds its Output or a Probe: that
    /// node's work is left out. Without it such a patch is an error.
    #[arg(long)]
    pub allow_unknown: bool,
}

pub fn run(args: &Args) -> anyhow::Result<ExitCode> {
    let mut session = Session::open(&args.patch, false, Some(args.size), args.allow_unknown)?;
    let mut reported = BTreeSet::new();
    let mut failed = session.load_errors;
    for frame in 0..args.frames.max(1) {
        failed |= session.step(frame, 60.0, &args.patch, &mut reported);
    }
    let runtime = session.runtime.stats();
    let render = session.renderer.as_ref().map(|r| r.last_report());
    if args.json {
        let json = serde_json::json!({ "runtime": runtime, "render": render });
        println!("{}", serde_json::to_string_pretty(&json)?);
    } else {
        println!(
            "runtime: {} evaluated, {} reused, {} skipped, {} failed, {:.3} ms CPU",
            runtime.evaluated,
            runtime.reused,
            runtime.skipped,
            runtime.failed,
            runtime.cpu_ns as f64 / 1e6
        );
        // Decoding and analysis are CPU work of their nodes: shown per node.
        let registry = session.runtime.registry();
        for n in runtime.nodes.iter().filter(|n| {
            n.run != spreadlight_graph::NodeRun::Skipped
                && registry
                    .get(&n.type_name)
                    .is_some_and(|d| &*d.category == "Media")
        }) {
            println!(
                "  media: {} {}: {:.3} ms CPU",
                n.type_name,
                n.id,
                n.cpu_ns as f64 / 1e6
            );
        }
        if let Some(r) = render {
            println!(
                "render on {}: {} passes, {} culled, {} pipelines compiled, {} draws",
                r.adapter,
                r.passes.len(),
                r.culled.len(),
                r.pipelines_compiled,
                r.draws
            );
            for p in &r.passes {
                let ms = p.gpu_ms.map_or("-".to_owned(), |ms| format!("{ms:.3} ms"));
                println!("  {:<40} {ms:>10}  {} draws", p.name, p.draws);
            }
            for c in &r.culled {
                println!("  {c:<40} culled");
            }
            for (name, n) in &r.counters {
                println!("  {name}: {n}");
            }
        }
    }
    Ok(if failed {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    })
}
