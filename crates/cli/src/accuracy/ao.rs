//! Ambient occlusion: every estimator (Stochastic, SAO, HBAO) at several
//! sample counts, with temporal accumulation off and on, GPU time at a
//! large size against the error at a small one versus ray-cast AO
//! (spreadlight_reference::ssao: `--rays` cosine-weighted rays of the
//! same radius from every pixel's true surface point). Four balls over a
//! floor, a still camera; temporal settings are measured after `--settle`
//! frames, as a viewer would see them. Each setting at every
//! `--resolutions` (Full, and Half: the raw estimate for one pixel in four,
//! upsampled with depth awareness), so the table shows what half
//! resolution saves and what it costs in error; and at every
//! `--surface-inputs` (packed: the blurs and rays read the G-buffer's packed
//! surface, whose pass is timed with the AO's; gbuffer: depth and normals a
//! tap, the exact way), so the table shows what the packed surface saves and
//! what its 16-bit normal costs.
//!
//! SSGI is measured in the same table (estimator `SSGI`): over a lit image
//! of uniform white, with no ambient, its bounce is the share of its rays
//! that hit something within the radius, so 1 minus it is its visibility,
//! held against the same ray-cast reference. Its rows show what SSGI's
//! resolutions (the half chain: gather, temporal blend and blur at half
//! size, one upsample) cost in error.

use std::process::ExitCode;
use std::sync::Arc;

use anyhow::Context;
use glam::{Mat4, Vec3};
use spreadlight_reference::shadows::Sphere;
use spreadlight_reference::ssao::{Occluders, visibility_image};
use spreadlight_render::camera::{CameraInput, reverse_z};
use spreadlight_render::gbuffer::{GBuffer, Layer};
use spreadlight_render::lighting::{Ssgi, SsgiSettings};
use spreadlight_render::packed_surface::{PASS_STEP, Reader, SurfaceInputs, set_inputs};
use spreadlight_render::readback::{ImageF32, render_and_read};
use spreadlight_render::resolution::Resolution;
use spreadlight_render::scenes::balls_on_floor;
use spreadlight_render::ssao::{AmbientOcclusion, AoMode, AoSettings};
use spreadlight_render::static_texture::StaticTexture;
use spreadlight_render::{FrameGraph, Recipe, Renderer, SizeRule};

use super::metrics::{self, Plane};
use super::plot::Series;
use super::{median, ms, pass_ms};
use crate::session::parse_size;

#[derive(clap::Args)]
pub struct AoArgs {
    #[command(flatten)]
    common: super::Common,
    /// Where the error is measured (the reference casts rays from every pixel).
    #[arg(long, default_value = "320x180", value_parser = parse_size)]
    error_size: (u32, u32),
    /// Sample counts (rays, taps or directions), comma-separated.
    #[arg(long, default_value = "4,8,16,32", value_delimiter = ',')]
    samples: Vec<u32>,
    /// AO radius in world units.
    #[arg(long, default_value_t = 1.0)]
    radius: f32,
    /// Frames accumulated before a temporal setting's error is taken.
    #[arg(long, default_value_t = 16)]
    settle: usize,
    /// Rays per pixel in the reference.
    #[arg(long, default_value_t = 256)]
    rays: u32,
    /// The reference and each setting's AO (white = open) as PNGs, in DIR/ao/.
    #[command(flatten)]
    images: super::ImageArgs,
    /// Resolutions of the raw estimate measured (Full, Half), comma-separated.
    #[arg(long, default_value = "full,half", value_delimiter = ',', value_parser = super::parse_resolution)]
    resolutions: Vec<Resolution>,
    /// What the blurs and rays read (packed, gbuffer), comma-separated.
    #[arg(long, default_value = "gbuffer", value_delimiter = ',', value_parser = parse_inputs)]
    surface_inputs: Vec<SurfaceInputs>,
}

fn parse_inputs(s: &str) -> Result<SurfaceInputs, String> {
    SurfaceInputs::parse(s).ok_or_else(|| format!("`{s}`: packed or gbuffer"))
}

const BALLS: [([f32; 3], f32); 4] = [
    ([0.0, 0.8, 0.0], 0.8),
    ([-1.8, 0.5, 0.6], 0.5),
    ([1.6, 0.3, -0.4], 0.3),
    ([0.7, 1.9, 1.3], 0.35),
];
const FLOOR: f32 = 30.0;

fn camera(size: (u32, u32)) -> CameraInput {
    super::camera_looking(Vec3::new(0.0, 3.5, 6.0), Vec3::new(0.0, 0.6, 0.0), size)
}

/// What a row measures: an AO estimator, or SSGI's gathered share.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Estimator {
    Ao(AoMode),
    Ssgi,
}

impl Estimator {
    fn name(self) -> &'static str {
        match self {
            Estimator::Ao(mode) => mode_name(mode),
            Estimator::Ssgi => "SSGI",
        }
    }

    /// The pass name every pass of the effect has.
    fn kind(self) -> &'static str {
        match self {
            Estimator::Ao(AoMode::Stochastic) => "SSAO",
            Estimator::Ao(AoMode::Sao) => "SAO",
            Estimator::Ao(AoMode::Hbao) => "HBAO",
            Estimator::Ssgi => "SSGI",
        }
    }
}

/// One measured setting.
struct Row {
    mode: Estimator,
    samples: u32,
    temporal: bool,
    resolution: Resolution,
    inputs: SurfaceInputs,
    ms: Option<f64>,
    error: metrics::Error,
}

fn settings(mode: AoMode, samples: u32, temporal: bool, radius: f32) -> AoSettings {
    AoSettings {
        mode,
        radius,
        samples,
        steps: 8,
        intensity: 1.0,
        temporal_blend: if temporal { 0.9 } else { 0.0 },
        blur_radius: 4,
        reset: false,
        ..Default::default()
    }
}

fn mode_name(mode: AoMode) -> &'static str {
    match mode {
        AoMode::Stochastic => "Stochastic",
        AoMode::Sao => "SAO",
        AoMode::Hbao => "HBAO",
    }
}

/// SSGI's settings for an AO row's: the same radius, samples (32 at
/// most), steps, temporal blend, blur and resolution.
fn ssgi_settings(s: AoSettings) -> SsgiSettings {
    SsgiSettings {
        radius: s.radius,
        samples: s.samples.min(32),
        steps: s.steps,
        intensity: 1.0,
        temporal_blend: s.temporal_blend,
        blur_radius: s.blur_radius,
        reset: s.reset,
        resolution: s.resolution,
    }
}

/// A white image to light SSGI's rays: its bounce is then the share of
/// rays that hit.
fn white(renderer: &Renderer, size: (u32, u32)) -> Arc<StaticTexture> {
    let pixels = vec![[1.0, 1.0, 1.0, 1.0]; (size.0 * size.1) as usize];
    StaticTexture::from_rgba32f(&renderer.gpu, size.0, size.1, &pixels, "white")
}

/// A frame of `estimator`: the recipe and its output's name. SSGI reads
/// `white`, a texture of the frame's size.
fn effect(
    renderer: &Renderer,
    layer: &Arc<Layer>,
    size: (u32, u32),
    estimator: Estimator,
    settings: AoSettings,
    owner: u32,
    white: &Arc<StaticTexture>,
) -> (Arc<GBuffer>, Arc<dyn Recipe>, String) {
    let (g, ao) = frame(renderer, layer, size, settings, owner);
    match estimator {
        Estimator::Ao(_) => {
            let output = ao.output.clone();
            (g, ao, output)
        }
        Estimator::Ssgi => {
            let gi = Ssgi::new(
                renderer,
                Some(owner),
                g.clone(),
                white.texture_ref(),
                None,
                ssgi_settings(settings),
            );
            let output = gi.output.clone();
            (g, gi, output)
        }
    }
}

/// An AO node's frame: the same node id every frame, so temporal history carries over.
fn frame(
    renderer: &Renderer,
    layer: &Arc<Layer>,
    size: (u32, u32),
    settings: AoSettings,
    owner: u32,
) -> (Arc<GBuffer>, Arc<AmbientOcclusion>) {
    let cam = camera(size);
    let previous: Mat4 = cam.view_projection();
    let g = GBuffer::new(
        renderer,
        None,
        vec![layer.clone()],
        cam,
        Some(previous),
        SizeRule::Relative(1.0),
    );
    let ao = AmbientOcclusion::new(renderer, Some(owner), g.clone(), settings, None);
    (g, ao)
}

/// The AO after `frames` frames, and the depth under it.
fn measure(
    renderer: &Renderer,
    layer: &Arc<Layer>,
    size: (u32, u32),
    settings: AoSettings,
    frames: usize,
    owner: u32,
) -> anyhow::Result<(ImageF32, ImageF32)> {
    let mode = Estimator::Ao(settings.mode);
    measure_estimator(renderer, layer, size, mode, settings, frames, owner, None)
}

/// [`measure`] of any estimator; SSGI's visibility is 1 minus its bounce
/// under `white` (needed for SSGI).
#[allow(clippy::too_many_arguments)]
fn measure_estimator(
    renderer: &Renderer,
    layer: &Arc<Layer>,
    size: (u32, u32),
    estimator: Estimator,
    settings: AoSettings,
    frames: usize,
    owner: u32,
    white: Option<&Arc<StaticTexture>>,
) -> anyhow::Result<(ImageF32, ImageF32)> {
    let white = match white {
        Some(w) => w.clone(),
        None => self::white(renderer, (1, 1)),
    };
    let mut last = None;
    for _ in 0..frames.max(1) {
        let (g, recipe, output) = effect(renderer, layer, size, estimator, settings, owner, &white);
        let (report, images) = render_and_read(
            renderer,
            recipe.as_ref(),
            size,
            &[&output, &g.targets.depth],
        )?;
        if let Some((_, e)) = report.errors.first() {
            anyhow::bail!("the frame failed: {e}");
        }
        last = Some(images);
    }
    let mut images = last.context("no frame")?.into_iter();
    let mut ao = images.next().context("ao")?;
    if estimator == Estimator::Ssgi {
        for p in &mut ao.pixels {
            *p = [1.0 - p[0].clamp(0.0, 1.0); 4];
        }
    }
    Ok((ao, images.next().context("depth")?))
}

/// Median GPU time of the AO passes, frames back to back (no readback between them).
fn time(
    renderer: &Renderer,
    layer: &Arc<Layer>,
    args: &AoArgs,
    (estimator, settings): (Estimator, AoSettings),
    owner: u32,
    white: &Arc<StaticTexture>,
) -> anyhow::Result<Option<f64>> {
    let mut times = Vec::new();
    for k in 0..args.common.warmup + args.common.frames.max(1) {
        let size = args.common.time_size;
        let (g, recipe, output) = effect(renderer, layer, size, estimator, settings, owner, white);
        let mut graph = FrameGraph::new(args.common.time_size);
        recipe.declare(renderer, &mut graph);
        graph.request(&output);
        let (report, _) = graph.execute(renderer)?;
        if let Some((_, e)) = report.errors.first() {
            anyhow::bail!("the frame failed: {e}");
        }
        drop(g);
        if k >= args.common.warmup {
            // Every pass is of its estimator's kind ("SSAO", "SAO", "HBAO", "SSGI").
            let kind = estimator.kind();
            // The packed surface's pass serves every blur of a frame; here it
            // is this AO's alone, so its time is the AO's.
            let packed = pass_ms(&report, "MRE", Some(PASS_STEP)).unwrap_or(0.0);
            times.extend(pass_ms(&report, kind, None).map(|t| t + packed));
        }
    }
    Ok(median(times))
}

/// Ray-cast AO under every pixel with geometry; None for the sky.
fn reference(depth: &ImageF32, size: (u32, u32), radius: f32, rays: u32) -> Vec<Option<f32>> {
    let c = camera(size);
    let occluders = Occluders {
        spheres: BALLS
            .iter()
            .map(|(c, r)| Sphere {
                center: Vec3::from(*c),
                radius: *r,
            })
            .collect(),
        floor: Some(FLOOR / 2.0),
    };
    let depths: Vec<f32> = depth.pixels.iter().map(|p| p[0]).collect();
    let inverse = (reverse_z(c.projection) * c.view).inverse();
    visibility_image(&depths, size, inverse, &occluders, radius, rays)
}

fn error(ao: &ImageF32, truth: &[Option<f32>], size: (u32, u32)) -> metrics::Error {
    let mask: Vec<bool> = truth.iter().map(Option::is_some).collect();
    let gpu: Vec<f32> = ao.pixels.iter().map(|p| p[0]).collect();
    let reference: Vec<f32> = truth.iter().map(|t| t.unwrap_or(1.0)).collect();
    let plane = |values| Plane {
        width: size.0,
        height: size.1,
        values,
        mask: Some(&mask),
    };
    metrics::Error::of(&[plane(&gpu)], &[plane(&reference)])
}

pub fn run(args: &AoArgs) -> anyhow::Result<ExitCode> {
    let renderer = Renderer::headless().context("cannot open a GPU")?;
    let adapter = renderer.gpu.adapter_name();
    let balls: Vec<(Vec3, f32)> = BALLS.iter().map(|(c, r)| (Vec3::from(*c), *r)).collect();
    let layer = balls_on_floor(&renderer, &balls, FLOOR, 96)?;
    eprintln!(
        "reference: {} rays per pixel at {}x{} ...",
        args.rays, args.error_size.0, args.error_size.1
    );
    let (_, depth) = measure(
        &renderer,
        &layer,
        args.error_size,
        settings(AoMode::Stochastic, 1, false, 0.0),
        1,
        1,
    )?;
    let truth = reference(&depth, args.error_size, args.radius, args.rays);
    let images = args.images.folder("ao");
    if let Some(dir) = &images {
        super::write_grey(dir, "reference", &truth, args.error_size)?;
    }
    let none = error(
        &ImageF32 {
            pixels: vec![[1.0; 4]; truth.len()],
            ..depth.clone()
        },
        &truth,
        args.error_size,
    );
    let modes = [
        Estimator::Ao(AoMode::Stochastic),
        Estimator::Ao(AoMode::Sao),
        Estimator::Ao(AoMode::Hbao),
        Estimator::Ssgi,
    ];
    let white_error = white(&renderer, args.error_size);
    let white_time = white(&renderer, args.common.time_size);
    let total =
        modes.len() * args.samples.len() * 2 * args.resolutions.len() * args.surface_inputs.len();
    let mut rows = Vec::new();
    // A node id per setting: each its own history.
    let mut owner = 100;
    for mode in modes {
        for temporal in [false, true] {
            for ((&samples, &resolution), &inputs) in args
                .samples
                .iter()
                .flat_map(|s| args.resolutions.iter().map(move |r| (s, r)))
                .flat_map(|sr| args.surface_inputs.iter().map(move |i| (sr, i)))
            {
                owner += 1;
                eprintln!(
                    "[{}/{total}] {} {samples}{} {resolution} {}",
                    rows.len() + 1,
                    mode.name(),
                    if temporal { " temporal" } else { "" },
                    inputs.name()
                );
                set_inputs(&renderer, Reader::Blurs, inputs);
                set_inputs(&renderer, Reader::Rays, inputs);
                let ao_mode = match mode {
                    Estimator::Ao(m) => m,
                    Estimator::Ssgi => AoMode::Stochastic,
                };
                let s = AoSettings {
                    resolution,
                    ..settings(ao_mode, samples, temporal, args.radius)
                };
                let frames = if temporal { args.settle } else { 1 };
                let (ao, _) = measure_estimator(
                    &renderer,
                    &layer,
                    args.error_size,
                    mode,
                    s,
                    frames,
                    owner,
                    Some(&white_error),
                )?;
                let error = error(&ao, &truth, args.error_size);
                if let Some(dir) = &images {
                    let values: Vec<Option<f32>> = ao
                        .pixels
                        .iter()
                        .zip(&truth)
                        .map(|(p, t)| t.map(|_| p[0]))
                        .collect();
                    // The default inputs keep the names images had before
                    // there was a choice.
                    let name = format!(
                        "{} {samples}{} {resolution}{}",
                        mode.name(),
                        if temporal { " temporal" } else { "" },
                        match inputs {
                            SurfaceInputs::GBuffer => String::new(),
                            other => format!(" {}", other.name()),
                        }
                    );
                    super::write_grey(dir, &name, &values, args.error_size)?;
                }
                let ms = time(
                    &renderer,
                    &layer,
                    args,
                    (mode, s),
                    owner + 10_000,
                    &white_time,
                )?;
                rows.push(Row {
                    mode,
                    samples,
                    temporal,
                    resolution,
                    inputs,
                    ms,
                    error,
                });
            }
        }
    }
    let (tw, th) = args.common.time_size;
    let (ew, eh) = args.error_size;
    if args.common.json {
        for r in &rows {
            println!(
                "{}",
                serde_json::json!({
                    "effect": if r.mode == Estimator::Ssgi { "ssgi" } else { "ao" }, "mode": r.mode.name(), "samples": r.samples, "temporal": r.temporal,
                    "resolution": r.resolution.name(), "surface_inputs": r.inputs.name(),
                    "adapter": adapter, "time_size": format!("{tw}x{th}"), "error_size": format!("{ew}x{eh}"),
                    "ms": r.ms, "rmse": r.error.rmse, "ssim": r.error.ssim,
                    "no_ao_rmse": none.rmse, "no_ao_ssim": none.ssim,
                })
            );
        }
        return Ok(ExitCode::SUCCESS);
    }
    let mut table = format!(
        "Ambient occlusion on {adapter}: GPU ms of all AO passes at {tw}x{th} (median of {} frames after {}, back to back), \
         error at {ew}x{eh} against ray-cast AO ({} cosine-weighted rays per pixel, radius {}): RMSE and SSIM of visibility \
         over the pixels with geometry. Steps 8, blur radius 4; temporal: blend 0.9, error after {} frames of a still \
         camera. Resolution Half: the half chain (the raw estimate for one pixel in four, the temporal blend and the \
         blur at half size too, one depth-aware upsample at the end). SSGI: 1 minus its bounce over a white image (the \
         share of its rays that hit), against the same reference, its time all of its passes. \
         Surface packed: the blurs and rays read the packed surface (its pass timed with the AO's); gbuffer: \
         depth and normals a tap. No AO at all: RMSE {:.4}, SSIM {:.4}.\n\n\
         | estimator | samples | temporal | resolution | surface | GPU ms | RMSE | SSIM |\n|---|---|---|---|---|---|---|---|\n",
        args.common.frames,
        args.common.warmup,
        args.rays,
        args.radius,
        args.settle,
        none.rmse,
        none.ssim
    );
    for r in &rows {
        table.push_str(&format!(
            "| {} | {} | {} | {} | {} | {} | {:.4} | {:.4} |\n",
            r.mode.name(),
            r.samples,
            if r.temporal { "on" } else { "off" },
            r.resolution,
            r.inputs.name(),
            ms(r.ms),
            r.error.rmse,
            r.error.ssim
        ));
    }
    args.common.publish(
        &table,
        &format!("Ambient occlusion on {adapter}: GPU ms at {tw}x{th} against RMSE"),
        "RMSE of visibility",
        || {
            Series::group(rows.iter().map(|r| {
                let name = format!(
                    "{}{}{}{}",
                    r.mode.name(),
                    if r.temporal { " temporal" } else { "" },
                    if r.resolution.is_half() { " half" } else { "" },
                    if r.inputs == SurfaceInputs::GBuffer {
                        " gbuffer"
                    } else {
                        ""
                    }
                );
                (
                    name,
                    (
                        r.ms.unwrap_or(f64::NAN),
                        r.error.rmse,
                        r.samples.to_string(),
                    ),
                )
            }))
        },
    )
}
