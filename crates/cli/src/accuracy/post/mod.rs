//! Post effects: GPU time against error for each quality setting, versus a
//! reference made by brute force from the same renderer (no shortcuts the
//! effect could share), over the G-buffer's albedo of coloured balls on a
//! floor (the image every effect starts from):
//! - `dof`: the average of many views from points spread over the lens's
//!   aperture, each re-aimed at the focus plane (an off-axis projection):
//!   the thin lens, exactly, in the limit of many views;
//! - `motion-blur`: the average of many sub-frame renders across the open
//!   shutter, the moving ball where it is at each instant;
//! - `taa` and `fxaa`: one frame rendered 8x8 larger and box-downsampled
//!   (64 samples a pixel). TAA is measured after `--taa-frames` jittered
//!   frames of the still scene.
//!
//! Error: RMSE and SSIM over RGB (metrics.rs); time: the effect's passes at
//! `--time-size` (median of `--frames` after `--warmup`). DOF is measured at
//! every `--resolutions` (Half: the blur for one pixel in four, upsampled
//! with depth awareness; its rows' setting ends in ", half").
//!
//! One file per effect's measurement (dof.rs, motion_blur.rs, taa.rs,
//! fxaa.rs) over the shared scene (scene.rs) and measurement (measure.rs);
//! this one holds the command's arguments, runs the chosen effects and
//! prints their rows.

mod dof;
mod fxaa;
mod measure;
mod motion_blur;
mod scene;
mod taa;

use std::process::ExitCode;

use anyhow::Context;
use spreadlight_render::Renderer;
use spreadlight_render::resolution::Resolution;

use super::ms;
use super::plot::Series;
use crate::session::parse_size;
use dof::{F_STOP, FOCAL_MM, FOCUS};
use motion_blur::SHUTTER;

#[derive(clap::Args)]
pub struct PostArgs {
    #[command(flatten)]
    common: super::Common,
    /// Which effects, comma-separated: dof, motion-blur, taa, fxaa.
    #[arg(
        long,
        default_value = "dof,motion-blur,taa,fxaa",
        value_delimiter = ','
    )]
    only: Vec<Effect>,
    /// Where the error is measured (the references render many views at this size, or 8x8 larger).
    #[arg(long, default_value = "160x90", value_parser = parse_size)]
    error_size: (u32, u32),
    /// Views averaged by the DOF and motion blur references.
    #[arg(long, default_value_t = 256)]
    views: u32,
    /// Jittered frames TAA accumulates before its error is measured.
    #[arg(long, default_value_t = 32)]
    taa_frames: u64,
    /// Resolutions DOF blurs at (Full, Half), comma-separated.
    #[arg(long, default_value = "full,half", value_delimiter = ',', value_parser = super::parse_resolution)]
    resolutions: Vec<Resolution>,
}

/// How a half-resolution row's setting ends (and its plot line is named).
const HALF_SUFFIX: &str = ", half";

#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
enum Effect {
    Dof,
    MotionBlur,
    Taa,
    Fxaa,
}

impl Effect {
    fn name(self) -> &'static str {
        match self {
            Effect::Dof => "DOF",
            Effect::MotionBlur => "MotionBlur",
            Effect::Taa => "TAA",
            Effect::Fxaa => "FXAA",
        }
    }
}

/// One measured setting.
struct Row {
    effect: Effect,
    setting: String,
    ms: Option<f64>,
    rmse: f64,
    ssim: f64,
}

pub fn run_post(args: &PostArgs) -> anyhow::Result<ExitCode> {
    let renderer = Renderer::headless().context("cannot open a GPU")?;
    let adapter = renderer.gpu.adapter_name();
    let mut rows = Vec::new();
    if args.only.contains(&Effect::Dof) {
        dof::measure(&renderer, args, &mut rows)?;
    }
    if args.only.contains(&Effect::MotionBlur) {
        motion_blur::measure(&renderer, args, &mut rows)?;
    }
    if args.only.contains(&Effect::Taa) || args.only.contains(&Effect::Fxaa) {
        let layer = scene::scene(&renderer, 0.0, false)?;
        eprintln!("TAA/FXAA reference: 64 samples a pixel ...");
        let truth = measure::supersampled(&renderer, &layer, args.error_size)?;
        if args.only.contains(&Effect::Taa) {
            taa::measure(&renderer, args, &truth, &layer, &mut rows)?;
        }
        if args.only.contains(&Effect::Fxaa) {
            fxaa::measure(&renderer, args, &truth, &layer, &mut rows)?;
        }
    }
    let (tw, th) = args.common.time_size;
    let (ew, eh) = args.error_size;
    if args.common.json {
        for r in &rows {
            println!(
                "{}",
                serde_json::json!({
                    "effect": r.effect.name(), "setting": r.setting, "adapter": adapter,
                    "time_size": format!("{tw}x{th}"), "error_size": format!("{ew}x{eh}"),
                    "ms": r.ms, "rmse": r.rmse, "ssim": r.ssim,
                })
            );
        }
        return Ok(ExitCode::SUCCESS);
    }
    let mut table = format!(
        "Post effects on {adapter}: GPU ms of the effect's passes at {tw}x{th} (median of {} frames after {}), error at \
         {ew}x{eh} over the albedo of coloured balls on a floor (RMSE and SSIM over RGB) against: DOF, {} views over a \
         {FOCAL_MM} mm f/{F_STOP} lens focused at {FOCUS}; MotionBlur, {} sub-frames across a {SHUTTER} degree shutter; \
         TAA (after {} jittered frames) and FXAA, the frame rendered 8x8 larger and box-downsampled.\n\n\
         | effect | setting | ms | RMSE | SSIM |\n|---|---|---|---|---|\n",
        args.common.frames, args.common.warmup, args.views, args.views, args.taa_frames
    );
    for r in &rows {
        table.push_str(&format!(
            "| {} | {} | {} | {:.4} | {:.4} |\n",
            r.effect.name(),
            r.setting,
            ms(r.ms),
            r.rmse,
            r.ssim
        ));
    }
    args.common.publish(
        &table,
        &format!("Post effects on {adapter}: ms at {tw}x{th} against RMSE"),
        "RMSE (RGB)",
        || {
            Series::group(rows.iter().filter(|r| r.ms.is_some()).map(|r| {
                let half = r.setting.ends_with(HALF_SUFFIX);
                (
                    format!("{}{}", r.effect.name(), if half { " half" } else { "" }),
                    (r.ms.unwrap_or(0.0), r.rmse, r.setting.clone()),
                )
            }))
        },
    )
}
