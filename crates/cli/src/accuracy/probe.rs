//! Environment probes: a mirror ball beside a red box, the ball reflecting
//! a probe at its centre that sees the box and the floor. Two pins trade
//! time for accuracy:
//!
//! - resolution (cube size x samples): each setting's probe pass (six faces
//!   and the prefilter, rendered every frame to time it) against its error
//!   versus a high-resolution reference probe (`--reference-size`,
//!   `--reference-samples`);
//! - update rate (Every N Frames): the box circles the ball; each interval's
//!   probe time per frame (the renders spread over the frames) against its
//!   error, over the frames, versus a probe of the same size rendered every
//!   frame (how far the reflection lags behind the box);
//! - lights (Max Lights): `--lights` red, green and blue point lights in a
//!   ring around the ball light the probe's faces; each Max Lights setting's
//!   probe pass (rendered every frame) against its error versus the probe
//!   that adds them all (a face adds only the first Max Lights of a buffer).
//!   Max Lights 0 runs no light pass: its time is the probe without lights.
//!
//! Error: RMSE of the linear specular term over the ball's pixels, and SSIM.

use std::process::ExitCode;
use std::sync::Arc;

use anyhow::Context;
use glam::{Mat4, Vec2, Vec3};
use spreadlight_render::environment::probe::DEFAULT_MAX_LIGHTS;
use spreadlight_render::environment::{
    Environment, EnvironmentQuality, EnvironmentSource, ProbeLights, ProbeScene, ProbeSettings,
    ProbeUpdate, Reflection, ReflectionMode,
};
use spreadlight_render::gbuffer::{GBuffer, Layer};
use spreadlight_render::lighting::{LightBuffer, PointLight};
use spreadlight_render::material::{Feature, Material, MaterialWorld};
use spreadlight_render::readback::{ImageF32, render_and_read};
use spreadlight_render::scenes::{MirrorBesideBox, mirror_beside_box};
use spreadlight_render::{Renderer, SizeRule};

use super::metrics::{self, Plane};
use super::plot::Series;
use super::{median, ms, pass_ms};
use crate::session::parse_size;

#[derive(clap::Args)]
pub struct ProbeArgs {
    #[command(flatten)]
    common: super::Common,
    /// Where the error is measured (the probe's own cost does not depend on it).
    #[arg(long, default_value = "240x135", value_parser = parse_size)]
    error_size: (u32, u32),
    /// Probe cube face sizes, comma-separated.
    #[arg(long, default_value = "16,32,64,128", value_delimiter = ',')]
    cube_sizes: Vec<u32>,
    /// GGX samples per prefiltered texel, comma-separated.
    #[arg(long, default_value = "16,64", value_delimiter = ',')]
    samples: Vec<u32>,
    /// The reference probe's face size and samples.
    #[arg(long, default_value_t = 512)]
    reference_size: u32,
    #[arg(long, default_value_t = 256)]
    reference_samples: u32,
    /// Update intervals (Every N Frames), comma-separated.
    #[arg(long, default_value = "1,2,4,8", value_delimiter = ',')]
    intervals: Vec<u32>,
    /// Frames the box circles for, per interval.
    #[arg(long, default_value_t = 24)]
    update_frames: usize,
    /// The ball's roughness (0: a mirror).
    #[arg(long, default_value_t = 0.05)]
    roughness: f32,
    /// Point lights around the ball that light the probe (0: no lights method).
    #[arg(long, default_value_t = 32)]
    lights: u32,
    /// Max Lights settings, comma-separated (each against all `--lights`).
    #[arg(long, default_value = "0,1,4,16,32", value_delimiter = ',')]
    max_lights: Vec<u32>,
}

/// `count` point lights in a ring around the ball, red, green and blue in
/// turn, at heights 0.2..1.2, each reaching the floor and the box.
fn ring_of_lights(count: u32) -> Vec<PointLight> {
    (0..count)
        .map(|i| {
            let t = i as f32 / count.max(1) as f32;
            let at =
                Vec2::from_angle(t * std::f32::consts::TAU * 3.0).rotate(Vec2::new(1.2 + t, 0.0));
            let mut color = Vec3::splat(0.05);
            color[(i % 3) as usize] = 1.0;
            PointLight {
                position: Vec3::new(at.x, 0.2 + (i % 5) as f32 * 0.25, at.y),
                color,
                intensity: 2.0,
                range: 3.0,
                shadow: None,
            }
        })
        .collect()
}

const BALL: Vec3 = Vec3::new(0.0, 0.6, 0.0);
const RADIUS: f32 = 0.6;
const BOX_DISTANCE: f32 = 1.6;
const BOX_SIZE: f32 = 0.8;
/// The box's angle around the ball each frame (radians).
const BOX_SPEED: f32 = 0.12;

struct Scene {
    scene: MirrorBesideBox,
    materials: Arc<MaterialWorld>,
}

/// The surroundings with the box turned `angle` around the ball.
fn box_at(s: &MirrorBesideBox, angle: f32) -> Arc<Layer> {
    let mut layer = Layer::clone(&s.surroundings);
    let at = Vec2::from_angle(angle).rotate(Vec2::new(BOX_DISTANCE, 0.0));
    layer.batches[0].instances[0].transform =
        Mat4::from_translation(Vec3::new(at.x, BOX_SIZE * 0.5 + 0.002, at.y))
            * Mat4::from_scale(Vec3::splat(BOX_SIZE));
    Arc::new(layer)
}

/// The warm-up frames and then the timed ones of `render` (a probe
/// rendered every frame): the last image and the timed frames' GPU times.
fn timed(
    common: &super::Common,
    mut render: impl FnMut() -> anyhow::Result<(ImageF32, Option<f64>)>,
) -> anyhow::Result<(ImageF32, Vec<f64>)> {
    let mut times = Vec::new();
    let mut last = None;
    for i in 0..common.warmup + common.frames.max(1) {
        let (image, ms) = render()?;
        if i >= common.warmup {
            times.extend(ms);
        }
        last = Some(image);
    }
    Ok((last.context("a frame")?, times))
}

/// One frame: the ball's specular from a probe of `surroundings` (lit by
/// `lights`' buffers, at most their `.1` first lights each), and the probe
/// pass's GPU ms.
#[allow(clippy::too_many_arguments)]
fn frame(
    renderer: &Renderer,
    s: &Scene,
    surroundings: &Arc<Layer>,
    size: (u32, u32),
    owner: u32,
    quality: EnvironmentQuality,
    update: ProbeUpdate,
    lights: (&[ProbeLights], u32),
) -> anyhow::Result<(ImageF32, Option<f64>)> {
    let g = GBuffer::new(
        renderer,
        None,
        vec![s.scene.ball.clone(), surroundings.clone()],
        super::camera_looking(Vec3::new(0.0, 1.2, 4.0), BALL, size),
        None,
        SizeRule::Relative(1.0),
    );
    let settings = ProbeSettings {
        position: BALL,
        update,
        ..Default::default()
    };
    let probe = ProbeScene::new(vec![surroundings.clone()], settings)?
        .with_lights(lights.0.to_vec(), lights.1)?;
    let env = Environment::new(
        renderer,
        Some(owner),
        EnvironmentSource::Probe(Arc::new(probe)),
        quality,
    );
    let r = Reflection::new(
        renderer,
        None,
        g,
        s.materials.clone(),
        env,
        ReflectionMode::Reflect,
    );
    let (report, images) = render_and_read(renderer, r.as_ref(), size, &[&r.specular])?;
    if let Some((_, e)) = report.errors.first() {
        anyhow::bail!("the frame failed: {e}");
    }
    let image = images.into_iter().next().context("the specular image")?;
    Ok((image, pass_ms(&report, "EnvironmentProbe", None)))
}

/// RMSE and SSIM over the pixels the reference reflects on.
fn error(image: &ImageF32, truth: &ImageF32) -> metrics::Error {
    let mask: Vec<bool> = truth
        .pixels
        .iter()
        .map(|p| p[..3].iter().any(|c| *c > 0.0))
        .collect();
    let channel =
        |img: &ImageF32, c: usize| -> Vec<f32> { img.pixels.iter().map(|p| p[c]).collect() };
    let (approx, reference): (Vec<Vec<f32>>, Vec<Vec<f32>>) = (0..3)
        .map(|c| (channel(image, c), channel(truth, c)))
        .unzip();
    let a = Plane::channels(&approx, Some(&mask), (truth.width, truth.height));
    let t = Plane::channels(&reference, Some(&mask), (truth.width, truth.height));
    metrics::Error::of(&a, &t)
}

struct Row {
    family: &'static str,
    setting: String,
    ms: Option<f64>,
    renders: usize,
    e: metrics::Error,
}

pub fn run(args: &ProbeArgs) -> anyhow::Result<ExitCode> {
    let renderer = Renderer::headless().context("cannot open a GPU")?;
    let adapter = renderer.gpu.adapter_name();
    let size = args.error_size;
    let mirror = Material::new()
        .with(Feature::CookTorrance, &[[args.roughness, 1.0, 0.04, 0.0]])?
        .with(Feature::Reflection, &[[1.0, 0.0, 0.0, 0.0]])?;
    let scene = mirror_beside_box(
        &renderer,
        (BALL, RADIUS),
        Vec2::new(BOX_DISTANCE, 0.0),
        BOX_SIZE,
        8.0,
    )?;
    let s = Scene {
        materials: MaterialWorld::new(&renderer, vec![mirror, Material::default_material()]),
        scene,
    };
    let still = s.scene.surroundings.clone();
    let reference_quality = EnvironmentQuality {
        cube_size: args.reference_size,
        samples: args.reference_samples,
    };
    eprintln!(
        "reference probe: cube {} x {} samples ...",
        args.reference_size, args.reference_samples
    );
    let (truth, _) = frame(
        &renderer,
        &s,
        &still,
        size,
        1,
        reference_quality,
        ProbeUpdate::OnChange,
        (&[], DEFAULT_MAX_LIGHTS),
    )?;
    let mut rows = Vec::new();
    let mut owner = 10;
    for &cube_size in &args.cube_sizes {
        for &samples in &args.samples {
            let quality = EnvironmentQuality { cube_size, samples };
            owner += 1;
            // Rendered every frame, so every frame times the whole probe.
            let (image, times) = timed(&args.common, || {
                frame(
                    &renderer,
                    &s,
                    &still,
                    size,
                    owner,
                    quality,
                    ProbeUpdate::EveryNFrames(1),
                    (&[], DEFAULT_MAX_LIGHTS),
                )
            })?;
            rows.push(Row {
                family: "resolution",
                setting: format!("cube {cube_size} x {samples} samples"),
                ms: median(times),
                renders: 1,
                e: error(&image, &truth),
            });
        }
    }
    // Update rate at the default probe quality, the box circling.
    let quality = EnvironmentQuality {
        cube_size: 64,
        samples: 32,
    };
    owner += 1;
    let every_frame = owner;
    let moving: Vec<Arc<Layer>> = (0..args.update_frames)
        .map(|f| box_at(&s.scene, f as f32 * BOX_SPEED))
        .collect();
    let mut references = Vec::new();
    for layer in &moving {
        references.push(
            frame(
                &renderer,
                &s,
                layer,
                size,
                every_frame,
                quality,
                ProbeUpdate::OnChange,
                (&[], DEFAULT_MAX_LIGHTS),
            )?
            .0,
        );
    }
    for &n in &args.intervals {
        owner += 1;
        let (mut total_ms, mut renders, mut sum, mut ssim) = (0.0, 0usize, 0.0, 0.0f64);
        for (layer, truth) in moving.iter().zip(&references) {
            let (image, ms) = frame(
                &renderer,
                &s,
                layer,
                size,
                owner,
                quality,
                ProbeUpdate::EveryNFrames(n.max(1)),
                (&[], DEFAULT_MAX_LIGHTS),
            )?;
            if let Some(ms) = ms {
                total_ms += ms;
                renders += 1;
            }
            let e = error(&image, truth);
            sum += e.rmse * e.rmse;
            ssim += e.ssim;
        }
        let frames = moving.len().max(1) as f64;
        rows.push(Row {
            family: "update rate",
            setting: format!("every {n} frames"),
            ms: Some(total_ms / frames),
            renders,
            e: metrics::Error {
                rmse: (sum / frames).sqrt(),
                ssim: ssim / frames,
            },
        });
    }
    // Max Lights at the default probe quality, the box still.
    if args.lights > 0 {
        let lights = vec![ProbeLights {
            lights: LightBuffer::points(&renderer, &ring_of_lights(args.lights)),
            shadows: None,
        }];
        owner += 1;
        let (all, _) = frame(
            &renderer,
            &s,
            &still,
            size,
            owner,
            quality,
            ProbeUpdate::OnChange,
            (&lights, args.lights),
        )?;
        for &max in &args.max_lights {
            owner += 1;
            let (image, times) = timed(&args.common, || {
                frame(
                    &renderer,
                    &s,
                    &still,
                    size,
                    owner,
                    quality,
                    ProbeUpdate::EveryNFrames(1),
                    (&lights, max),
                )
            })?;
            rows.push(Row {
                family: "lights",
                setting: format!("max {max} of {} point lights", args.lights),
                ms: median(times),
                renders: 1,
                e: error(&image, &all),
            });
        }
    }
    let (ew, eh) = size;
    if args.common.json {
        for r in &rows {
            println!(
                "{}",
                serde_json::json!({
                    "effect": "probe", "method": r.family, "setting": r.setting, "adapter": adapter,
                    "error_size": format!("{ew}x{eh}"), "probe_ms": r.ms, "renders": r.renders,
                    "rmse": r.e.rmse, "ssim": r.e.ssim,
                })
            );
        }
        return Ok(ExitCode::SUCCESS);
    }
    let mut table = format!(
        "Environment probes on {adapter}: GPU ms of the EnvironmentProbe pass (six faces + prefilter; resolution: median \
         of {} frames after {}, rendered every frame; update rate: the mean per frame over {} frames of a box circling \
         the ball, {} rad a frame, cube 64 x 32 samples, renders: how many frames rendered it), error at {ew}x{eh} over \
         the ball's pixels (roughness {}; RMSE of the linear specular term, SSIM) against a cube {} x {} samples probe \
         (resolution), a probe rendered every frame (update rate) or the probe adding all {} point lights (lights: \
         Max Lights, cube 64 x 32 samples, rendered every frame).\n\n| method | setting | probe ms | renders | RMSE | SSIM |\n|---|---|---|---|---|---|\n",
        args.common.frames,
        args.common.warmup,
        args.update_frames,
        BOX_SPEED,
        args.roughness,
        args.reference_size,
        args.reference_samples,
        args.lights,
    );
    for r in &rows {
        table.push_str(&format!(
            "| {} | {} | {} | {} | {:.4} | {:.4} |\n",
            r.family,
            r.setting,
            ms(r.ms),
            r.renders,
            r.e.rmse,
            r.e.ssim
        ));
    }
    args.common.publish(
        &table,
        &format!("Environment probes on {adapter}: probe ms against RMSE"),
        "RMSE of the specular term",
        || {
            Series::group(rows.iter().map(|r| {
                (
                    r.family.to_owned(),
                    (r.ms.unwrap_or(0.0), r.e.rmse, r.setting.clone()),
                )
            }))
        },
    )
}
