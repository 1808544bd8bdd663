//! `spreadlight accuracy`: what accuracy costs. For an approximating
//! effect, every quality setting's GPU time at a large size against its
//! error, at a small size, versus a CPU reference of the same scene. Prints
//! a Markdown table (and JSON lines with `--json`); `--out` writes the table
//! to a file. Later effects add themselves as subcommands.
//!

pub(crate) mod metrics;
pub(crate) mod plot;
mod post;
mod shadows;

use std::process::ExitCode;

#[derive(clap::Args)]
pub struct Args {
    #[command(subcommand)]
    what: What,
}

#[derive(clap::Subcommand)]
enum What {
    /// Shadow filters (Raw, PCF, PCSS, VSM) by map resolution: GPU time against error versus ray-cast soft shadows.
    Shadows(shadows::ShadowArgs),
    /// Post effects (DOF, MotionBlur, TAA, FXAA) by quality: GPU time against error versus brute-force references.
    Post(post::PostArgs),
}

pub fn run(args: &Args) -> anyhow::Result<ExitCode> {
    match &args.what {
        What::Shadows(a) => shadows::run(a),
        What::Post(a) => post::run_post(a),
    }
}

/// The summed GPU time of the passes whose name contains `what`.
pub(crate) fn pass_ms(report: &spreadlight_render::FrameReport, what: &str) -> Option<f64> {
    let times: Vec<f64> = report
        .passes
        .iter()
        .filter(|p| p.name.contains(what))
        .filter_map(|p| p.gpu_ms)
        .collect();
    (!times.is_empty()).then(|| times.iter().sum())
}

pub(crate) fn median(mut v: Vec<f64>) -> Option<f64> {
    if v.is_empty() {
        return None;
    }
    v.sort_by(f64::total_cmp);
    Some(v[v.len() / 2])
}

pub(crate) fn ms(v: Option<f64>) -> String {
    v.map_or("-".to_owned(), |v| format!("{v:.3}"))
}
