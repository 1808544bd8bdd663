//! `spreadlight eval`: evaluate a patch headless at a fixed frame rate.
//! Deterministic: frame n runs at time n / fps exactly.

use std::collections::BTreeSet;
use std::path::PathBuf;
use std::process::ExitCode;

use serde::Serialize;
use spreadlight_graph::{FrameStats, Spread};

use crate::session::Session;

#[derive(clap::Args)]
pub struct Args {
    /// The patch to evaluate.
    patch: PathBuf,
    /// How many frames to evaluate.
    #[arg(long, default_value_t = 1)]
    frames: u64,
    /// Frames per second of the headless clock.
    #[arg(long, default_value_t = 60.0, value_parser = positive_fps)]
    fps: f64,
    /// Print only these probes (by their Name); all probes when not given.
    #[arg(long = "probe", value_name = "NAME")]
    probes: Vec<String>,
    /// Print one JSON document instead of text: per frame, the probed values and the runtime statistics.
    #[arg(long)]
    stats: bool,
    /// How many slices of each spread the text output shows.
    #[arg(long, default_value_t = 8)]
    slices: usize,
    /// Run a patch even though an unknown node type (misspelled, or a shader
    /// or subpatch file that is missing) feeds its Output or a Probe: that
    /// node's work is left out. Without it such a patch is an error.
    #[arg(long)]
    pub allow_unknown: bool,
}

fn positive_fps(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(v) if v.is_finite() && v > 0.0 => Ok(v),
        _ => Err(format!("`{s}` is not a positive frame rate")),
    }
}

#[derive(Serialize)]
struct FrameReport<'a> {
    frame: u64,
    time: f64,
    probes: Vec<(&'a str, &'a Spread)>,
    stats: &'a FrameStats,
}

pub fn run(args: &Args) -> anyhow::Result<ExitCode> {
    let mut session = Session::open(&args.patch, false, None, args.allow_unknown)?;
    let mut failed = session.load_errors;
    let wanted: BTreeSet<&str> = args.probes.iter().map(String::as_str).collect();
    // Errors are reported when they appear, not on every frame they persist.
    let mut reported = BTreeSet::new();
    let mut json_frames = Vec::new();
    for frame in 0..args.frames {
        failed |= session.step(frame, args.fps, &args.patch, &mut reported);
        let runtime = &session.runtime;
        let probes: Vec<(&str, &Spread)> = runtime
            .probes()
            .iter()
            .filter(|(name, _)| wanted.is_empty() || wanted.contains(name.as_str()))
            .map(|(name, value)| (name.as_str(), &**value))
            .collect();
        let stats = runtime.stats();
        if args.stats {
            json_frames.push(serde_json::to_value(FrameReport {
                frame,
                time: stats.time,
                probes,
                stats,
            })?);
        } else {
            let values: Vec<String> = probes
                .iter()
                .map(|(name, value)| format!("{name} = {}", value.preview(args.slices)))
                .collect();
            let shown = if values.is_empty() {
                "(no probes: add a Probe node to see values)".to_owned()
            } else {
                values.join("  ")
            };
            println!("frame {frame} t={:.4}  {shown}", stats.time);
        }
    }
    for name in &wanted {
        if !session.runtime.probes().contains_key(*name) {
            eprintln!(
                "error: {}: no probe named `{name}` recorded anything",
                args.patch.display()
            );
            failed = true;
        }
    }
    if args.stats {
        println!(
            "{}",
            serde_json::to_string_pretty(&serde_json::json!({ "frames": json_frames }))?
        );
    }
    Ok(if failed {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    })
}
