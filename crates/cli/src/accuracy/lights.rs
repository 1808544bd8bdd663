//! `spreadlight accuracy lights`: CookTorrance's Light Cutoff and Light
//! Merge, GPU time against error. The scene is a light benchmark patch
//! (`patches/bench-lights.ron` unless `--patch` names another): every
//! `BenchLights` node's Count is set to each of `--counts`, every
//! CookTorrance node's Light Cutoff to each of `--cutoffs` (no merge), then
//! its Light Merge to each of `--merges` (with `--merge-cutoff`, 0: none). The reference is the
//! same patch with neither (0), which is exact: the froxel walks
//! equal the naive loop, and the naive loop the CPU reference BRDF (the
//! lighting tests). Error: RMSE and SSIM of the patch's Output (what a
//! viewer sees, tonemapped) at `--size`; time: the CookTorrance passes'
//! GPU ms (light assignment and shade, medians) and the whole frame's, at
//! `--time-size`.

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::{Context, bail};
use spreadlight_graph::{Patch, Spread};

use super::metrics::{Error, Plane};
use super::{Common, median, ms, pass_ms};
use crate::session::{Session, parse_size};

#[derive(clap::Args)]
pub struct LightArgs {
    /// The light benchmark patch: a BenchLights node (its Count is set) and CookTorrance nodes (their Light Cutoff and Light Merge are set).
    #[arg(long, default_value = "patches/bench-lights.ron")]
    patch: PathBuf,
    /// Light counts, comma-separated.
    #[arg(long, default_value = "1000,10000,100000", value_delimiter = ',')]
    counts: Vec<i64>,
    /// Light cutoffs (illuminance; 0: exact, the reference), comma-separated.
    #[arg(long, default_value = "0,1,3,10,30,100", value_delimiter = ',')]
    cutoffs: Vec<f32>,
    /// Light merge distances (world units; 0: exact), comma-separated: each with `--merge-cutoff`.
    #[arg(long, default_value = "1,2,4", value_delimiter = ',')]
    merges: Vec<f32>,
    /// The light cutoff the merges run with (0: none), to see the two knobs together.
    #[arg(long, default_value_t = 0.0)]
    merge_cutoff: f32,
    /// Where the error is measured.
    #[arg(long, default_value = "320x180", value_parser = parse_size)]
    size: (u32, u32),
    #[command(flatten)]
    common: Common,
}

/// One cutoff or merge at one count: its error against neither, its GPU time.
struct Row {
    count: i64,
    cutoff: f32,
    merge: f32,
    error: Error,
    /// The CookTorrance passes' GPU ms (assignment and shade).
    lighting_ms: Option<f64>,
    /// Of which the shade pass.
    shade_ms: Option<f64>,
    frame_ms: Option<f64>,
}

/// `patch` with every BenchLights node's Count and every CookTorrance node's Light Cutoff and Light Merge set.
fn with_settings(patch: &Patch, count: i64, (cutoff, merge): (f32, f32)) -> Patch {
    let mut set = patch.clone();
    for node in &mut set.nodes {
        match node.type_name.as_str() {
            "BenchLights" => {
                node.values
                    .insert("Count".to_owned(), Spread::Int(vec![count]));
            }
            "CookTorrance" => {
                node.values
                    .insert("Light Cutoff".to_owned(), Spread::Float(vec![cutoff]));
                node.values
                    .insert("Light Merge".to_owned(), Spread::Float(vec![merge]));
            }
            _ => {}
        }
    }
    set
}

/// A session of `patch` at `size` (capturing its Output images when `capture`).
fn open(
    args: &LightArgs,
    patch: &Patch,
    size: (u32, u32),
    capture: bool,
) -> anyhow::Result<Session> {
    let session = Session::build(patch, &args.patch, true, Some(size), capture, false)?;
    if session.load_errors {
        bail!("{} has errors (above)", args.patch.display());
    }
    Ok(session)
}

/// Evaluate `settings` in `session` for `frames` frames; the last frame's report.
fn run_frames(
    session: &mut Session,
    args: &LightArgs,
    settings: &Patch,
    frames: usize,
) -> anyhow::Result<Vec<spreadlight_render::FrameReport>> {
    // The same patch but for two values: it loaded without problems before,
    // and only the changed nodes evaluate again.
    for problem in session.runtime.load(settings) {
        let (_, line) = crate::session::headless_problem(problem, &args.patch, false);
        eprintln!("{line}");
    }
    let renderer = session.renderer.clone().context("no renderer")?;
    let mut reported = Default::default();
    let mut reports = Vec::new();
    for frame in 0..frames.max(1) as u64 {
        session.runtime.invalidate_sinks();
        if session.step(frame, 60.0, &args.patch, &mut reported) {
            bail!("frame {frame} failed (errors above)");
        }
        reports.push(renderer.last_report());
    }
    Ok(reports)
}

/// The first Output's image, as one plane of values per channel.
fn output_channels(session: &Session) -> anyhow::Result<Vec<Vec<f32>>> {
    let name = session
        .images
        .names()
        .into_iter()
        .next()
        .context("the patch has no Output to compare")?;
    let (image, _) = session
        .images
        .get(&name)
        .context("the Output rendered no image")?;
    Ok((0..3)
        .map(|c| image.pixels.iter().map(|p| p[c]).collect())
        .collect())
}

pub fn run(args: &LightArgs) -> anyhow::Result<ExitCode> {
    let patch = spreadlight_graph::format::load(&args.patch)?;
    if !patch.nodes.iter().any(|n| n.type_name == "BenchLights")
        || !patch.nodes.iter().any(|n| n.type_name == "CookTorrance")
    {
        bail!(
            "{} has no BenchLights or no CookTorrance node to set",
            args.patch.display()
        );
    }
    if let Some(bad) = args.cutoffs.iter().find(|c| !(c.is_finite() && **c >= 0.0)) {
        bail!("--cutoffs: {bad} is not a light cutoff (0 or more)");
    }
    if let Some(bad) = args.merges.iter().find(|m| !(m.is_finite() && **m >= 0.0)) {
        bail!("--merges: {bad} is not a light merge distance (0 or more)");
    }
    if !(args.merge_cutoff.is_finite() && args.merge_cutoff >= 0.0) {
        bail!(
            "--merge-cutoff: {} is not a light cutoff (0 or more)",
            args.merge_cutoff
        );
    }
    // Each cutoff without merging, then each merge with `--merge-cutoff`
    // (the exact setting, both 0, once).
    let settings: Vec<(f32, f32)> = args
        .cutoffs
        .iter()
        .map(|&c| (c, 0.0))
        .chain(
            args.merges
                .iter()
                .filter(|&&m| m > 0.0)
                .map(|&m| (args.merge_cutoff, m)),
        )
        .collect();
    let first = with_settings(
        &patch,
        args.counts.first().copied().unwrap_or(1000),
        (0.0, 0.0),
    );
    let mut small = open(args, &first, args.size, true)?;
    let mut large = open(args, &first, args.common.time_size, false)?;
    let adapter = small
        .renderer
        .as_ref()
        .map_or_else(String::new, |r| r.gpu.adapter_name());
    let mut rows = Vec::new();
    for &count in &args.counts {
        // The reference: no cutoff, no merge. Two frames, so every pass has run once before the read.
        run_frames(
            &mut small,
            args,
            &with_settings(&patch, count, (0.0, 0.0)),
            2,
        )?;
        let truth = output_channels(&small)?;
        for &(cutoff, merge) in &settings {
            let settings = with_settings(&patch, count, (cutoff, merge));
            run_frames(&mut small, args, &settings, 2)?;
            let approx = output_channels(&small)?;
            let error = Error::of(
                &Plane::channels(&approx, None, args.size),
                &Plane::channels(&truth, None, args.size),
            );
            let reports = run_frames(
                &mut large,
                args,
                &settings,
                args.common.warmup + args.common.frames.max(1),
            )?;
            let timed = &reports[args.common.warmup.min(reports.len() - 1)..];
            let of = |step: Option<&str>| {
                median(
                    timed
                        .iter()
                        .filter_map(|r| pass_ms(r, "CookTorrance", step))
                        .collect(),
                )
            };
            rows.push(Row {
                count,
                cutoff,
                merge,
                error,
                lighting_ms: of(None),
                shade_ms: of(Some("shade")),
                frame_ms: median(timed.iter().filter_map(|r| r.gpu_frame_ms).collect()),
            });
        }
    }
    if args.common.json {
        for r in &rows {
            println!(
                "{}",
                serde_json::json!({
                    "effect": "lights", "adapter": adapter, "patch": args.patch.display().to_string(),
                    "lights": r.count, "cutoff": r.cutoff, "merge": r.merge,
                    "error_size": [args.size.0, args.size.1],
                    "time_size": [args.common.time_size.0, args.common.time_size.1],
                    "rmse": r.error.rmse, "ssim": r.error.ssim,
                    "lighting_ms": r.lighting_ms, "shade_ms": r.shade_ms, "frame_ms": r.frame_ms,
                })
            );
        }
        return Ok(ExitCode::SUCCESS);
    }
    let mut table = format!(
        "CookTorrance's Light Cutoff and Light Merge on {adapter}: {}, GPU ms at {}x{} (medians of {} frames), error of the Output at {}x{} against neither (exact).\n\n\
         | lights | cutoff | merge | CookTorrance ms | of which shade | frame ms | RMSE | SSIM |\n|---:|---:|---:|---:|---:|---:|---:|---:|\n",
        args.patch.display(),
        args.common.time_size.0,
        args.common.time_size.1,
        args.common.frames.max(1),
        args.size.0,
        args.size.1,
    );
    for r in &rows {
        table.push_str(&format!(
            "| {} | {} | {} | {} | {} | {} | {:.5} | {:.4} |\n",
            r.count,
            r.cutoff,
            r.merge,
            ms(r.lighting_ms),
            ms(r.shade_ms),
            ms(r.frame_ms),
            r.error.rmse,
            r.error.ssim
        ));
    }
    args.common.publish(
        &table,
        "Light Cutoff and Light Merge",
        "RMSE of the Output",
        || {
            super::plot::Series::group(rows.iter().map(|r| {
                (
                    format!("{} lights", r.count),
                    (
                        r.lighting_ms.unwrap_or(0.0),
                        r.error.rmse,
                        if r.merge > 0.0 {
                            format!("merge {}", r.merge)
                        } else {
                            format!("cutoff {}", r.cutoff)
                        },
                    ),
                )
            }))
        },
    )
}
