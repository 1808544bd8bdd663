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

use std::process::ExitCode;
use std::sync::Arc;

use anyhow::Context;
use glam::{Mat4, Vec2, Vec3};
use spreadlight_render::camera::{CameraInput, jitter_ndc, jittered};
use spreadlight_render::gbuffer::{DrawBatch, GBuffer, InstanceInput, Layer, LayerFeatures};
use spreadlight_render::mesh::primitives::{GridParams, SphereParams, grid, sphere};
use spreadlight_render::post::{
    Dof, DofSettings, Focus, Fxaa, FxaaQuality, MotionBlur, MotionBlurSettings, Taa, TaaQuality,
    TaaSettings,
};
use spreadlight_render::readback::{ImageF32, read_texture};
use spreadlight_render::resolution::Resolution;
use spreadlight_render::{FrameGraph, Recipe, Renderer, SizeRule, TextureRef};

use super::metrics::{self, Plane};
use super::plot::{Series, write_svg};
use super::{median, ms, pass_ms};
use crate::sequence::accumulate::{Average, shutter_offset};
use crate::session::parse_size;

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

/// The lens of the DOF measurement, focused on the middle ball: a long lens
/// wide open, so the blur is several pixels even at the small error size.
const FOCAL_MM: f32 = 300.0;
const F_STOP: f32 = 1.4;
const FOCUS: f32 = 7.0;
/// The moving ball's motion per frame (world units) and the shutter.
const MOTION: Vec3 = Vec3::new(0.25, 0.0, 0.0);
const SHUTTER: f32 = 180.0;

/// Coloured balls on a floor, `at` frames on; with `moving_ball` the middle one
/// moves by `MOTION` a frame (its last frame's transform says so).
fn scene(renderer: &Renderer, at: f32, moving_ball: bool) -> anyhow::Result<Arc<Layer>> {
    let ball = renderer.meshes.upload(
        &renderer.gpu,
        &sphere(SphereParams {
            radius: 1.0,
            sectors: 48,
            stacks: 24,
        }),
    )?;
    let floor = renderer.meshes.upload(
        &renderer.gpu,
        &grid(GridParams {
            size: Vec2::splat(30.0),
            resolution_x: 1,
            resolution_y: 1,
        }),
    )?;
    let place = |c: Vec3, r: f32| Mat4::from_translation(c) * Mat4::from_scale(Vec3::splat(r));
    let instance = |t: Mat4, previous: Mat4, color: [f32; 4]| InstanceInput {
        transform: t,
        previous_transform: previous,
        color,
        material_id: 0,
        object_id: 0,
    };
    let moving = Vec3::new(0.0, 0.8, 0.0) + MOTION * at;
    let motion = if moving_ball { MOTION } else { Vec3::ZERO };
    let balls = vec![
        instance(
            place(Vec3::new(-1.8, 0.6, 2.5), 0.6),
            place(Vec3::new(-1.8, 0.6, 2.5), 0.6),
            [0.9, 0.2, 0.1, 1.0],
        ),
        instance(
            place(moving, 0.8),
            place(moving - motion, 0.8),
            [0.1, 0.7, 0.2, 1.0],
        ),
        instance(
            place(Vec3::new(2.2, 1.2, -6.0), 1.2),
            place(Vec3::new(2.2, 1.2, -6.0), 1.2),
            [0.2, 0.3, 0.9, 1.0],
        ),
        instance(
            place(Vec3::new(0.9, 0.3, 1.0), 0.3),
            place(Vec3::new(0.9, 0.3, 1.0), 0.3),
            [1.0, 0.9, 0.3, 1.0],
        ),
    ];
    let batches = vec![
        DrawBatch {
            mesh: ball,
            instances: balls,
        },
        DrawBatch {
            mesh: floor,
            instances: vec![instance(
                Mat4::IDENTITY,
                Mat4::IDENTITY,
                [0.5, 0.5, 0.5, 1.0],
            )],
        },
    ];
    Ok(Arc::new(Layer::new(
        None,
        batches,
        LayerFeatures::default(),
        None,
    )?))
}

fn camera(size: (u32, u32)) -> CameraInput {
    CameraInput {
        view: glam::camera::rh::view::look_at_mat4(
            Vec3::new(0.0, 2.0, 6.8),
            Vec3::new(0.0, 0.8, 0.0),
            Vec3::Y,
        ),
        projection: glam::camera::rh::proj::directx::perspective(
            0.8,
            size.0 as f32 / size.1.max(1) as f32,
            0.1,
            100.0,
        ),
    }
}

fn gbuffer(
    renderer: &Renderer,
    layer: Arc<Layer>,
    camera: CameraInput,
    previous: Option<Mat4>,
) -> Arc<GBuffer> {
    GBuffer::new(
        renderer,
        None,
        vec![layer],
        camera,
        previous,
        SizeRule::Relative(1.0),
    )
}

fn albedo(g: &Arc<GBuffer>) -> TextureRef {
    TextureRef {
        recipe: g.clone(),
        name: g.targets.color.clone(),
    }
}

/// Run `recipe` at `size`; read `name` back when `read`. Returns the report and the image.
fn run(
    renderer: &Renderer,
    recipe: &dyn Recipe,
    name: &str,
    size: (u32, u32),
    read: bool,
) -> anyhow::Result<(spreadlight_render::FrameReport, Option<ImageF32>)> {
    let mut graph = FrameGraph::new(size);
    recipe.declare(renderer, &mut graph);
    graph.request(name);
    let (report, outputs) = graph.execute(renderer)?;
    if let Some((_, e)) = report.errors.first() {
        anyhow::bail!("the frame failed: {e}");
    }
    let image = if read {
        Some(read_texture(
            &renderer.gpu,
            outputs.get(name).context("no output")?,
        )?)
    } else {
        None
    };
    Ok((report, image))
}

/// Points spread evenly over the unit disk (a golden-angle spiral).
fn disk(n: u32) -> Vec<Vec2> {
    (0..n)
        .map(|i| {
            let r = ((i as f32 + 0.5) / n as f32).sqrt();
            let a = i as f32 * 2.399_963;
            Vec2::new(a.cos(), a.sin()) * r
        })
        .collect()
}

fn error(approx: &ImageF32, truth: &ImageF32) -> (f64, f64) {
    let channel =
        |image: &ImageF32, c: usize| -> Vec<f32> { image.pixels.iter().map(|p| p[c]).collect() };
    let (a, t): (Vec<Vec<f32>>, Vec<Vec<f32>>) = (
        (0..3).map(|c| channel(approx, c)).collect(),
        (0..3).map(|c| channel(truth, c)).collect(),
    );
    let (approx, truth) = (planes(&a, truth), planes(&t, truth));
    let e = metrics::Error::of(&approx, &truth);
    (e.rmse, e.ssim)
}

fn planes<'a>(channels: &'a [Vec<f32>], like: &ImageF32) -> Vec<Plane<'a>> {
    channels
        .iter()
        .map(|values| Plane {
            width: like.width,
            height: like.height,
            values,
            mask: None,
        })
        .collect()
}

/// Median GPU time of the passes named `what` over frames made by `make`.
fn time(
    renderer: &Renderer,
    args: &PostArgs,
    what: &str,
    mut make: impl FnMut(u64) -> anyhow::Result<(Arc<dyn Recipe>, String)>,
) -> anyhow::Result<Option<f64>> {
    let mut times = Vec::new();
    for i in 0..(args.common.warmup + args.common.frames.max(1)) {
        let (recipe, name) = make(i as u64)?;
        let (report, _) = run(
            renderer,
            recipe.as_ref(),
            &name,
            args.common.time_size,
            false,
        )?;
        if i >= args.common.warmup {
            times.extend(pass_ms(&report, what));
        }
    }
    Ok(median(times))
}

fn dof_settings(samples: u32, resolution: Resolution) -> DofSettings {
    DofSettings {
        focal_length_mm: FOCAL_MM,
        f_stop: F_STOP,
        samples,
        max_radius: 32.0,
        resolution,
    }
}

fn measure_dof(renderer: &Renderer, args: &PostArgs, rows: &mut Vec<Row>) -> anyhow::Result<()> {
    let size = args.error_size;
    let layer = scene(renderer, 0.0, false)?;
    let base = camera(size);
    let aperture = dof_settings(1, Resolution::Full).aperture();
    eprintln!(
        "DOF reference: {} views over a {aperture:.4} aperture ...",
        args.views
    );
    let mut average = Average::new((size.0 * size.1) as usize);
    let (p00, p11) = (base.projection.x_axis.x, base.projection.y_axis.y);
    for lens in disk(args.views) {
        let d = lens * aperture / 2.0;
        // Moved across the lens and re-aimed so the focus plane projects where it did.
        let cam = CameraInput {
            view: Mat4::from_translation(Vec3::new(-d.x, -d.y, 0.0)) * base.view,
            projection: jittered(
                base.projection,
                Vec2::new(p00 * d.x / FOCUS, p11 * d.y / FOCUS),
            ),
        };
        let g = gbuffer(renderer, layer.clone(), cam, None);
        let (_, image) = run(renderer, g.as_ref(), &g.targets.color, size, true)?;
        average.add(&image.context("image")?);
    }
    let truth = average.image(size);
    let settings = [8, 16, 32, 64]
        .into_iter()
        .flat_map(|s| args.resolutions.iter().map(move |r| (s, *r)));
    for (samples, resolution) in settings {
        eprintln!("DOF {samples} samples {resolution}");
        let g = gbuffer(renderer, layer.clone(), base, None);
        let dof = Dof::new(
            renderer,
            None,
            albedo(&g),
            g,
            Focus::Distance(FOCUS),
            None,
            dof_settings(samples, resolution),
        );
        let (_, image) = run(renderer, dof.as_ref(), &dof.output, size, true)?;
        let (rmse, ssim) = error(&image.context("image")?, &truth);
        let timed = camera(args.common.time_size);
        let ms = time(renderer, args, "DOF", |_| {
            let g = gbuffer(renderer, layer.clone(), timed, None);
            let dof = Dof::new(
                renderer,
                None,
                albedo(&g),
                g,
                Focus::Distance(FOCUS),
                None,
                dof_settings(samples, resolution),
            );
            let name = dof.output.clone();
            Ok((dof as Arc<dyn Recipe>, name))
        })?;
        rows.push(Row {
            effect: Effect::Dof,
            setting: format!(
                "{samples} samples{}",
                if resolution.is_half() {
                    HALF_SUFFIX
                } else {
                    ""
                }
            ),
            ms,
            rmse,
            ssim,
        });
    }
    Ok(())
}

fn blur_settings(samples: u32) -> MotionBlurSettings {
    MotionBlurSettings {
        shutter_angle: SHUTTER,
        samples,
        ..Default::default()
    }
}

fn measure_motion_blur(
    renderer: &Renderer,
    args: &PostArgs,
    rows: &mut Vec<Row>,
) -> anyhow::Result<()> {
    let size = args.error_size;
    let cam = camera(size);
    eprintln!("MotionBlur reference: {} sub-frames ...", args.views);
    let mut average = Average::new((size.0 * size.1) as usize);
    let open = SHUTTER / 360.0;
    for i in 0..args.views {
        // The shutter is open for `open` of a frame, centred on the frame.
        let t = shutter_offset(i, args.views, f64::from(open)) as f32;
        let g = gbuffer(renderer, scene(renderer, t, false)?, cam, None);
        let (_, image) = run(renderer, g.as_ref(), &g.targets.color, size, true)?;
        average.add(&image.context("image")?);
    }
    let truth = average.image(size);
    let layer = scene(renderer, 0.0, true)?;
    for samples in [5, 9, 15, 25] {
        eprintln!("MotionBlur {samples} samples");
        let g = gbuffer(renderer, layer.clone(), cam, None);
        let blur = MotionBlur::new(renderer, None, albedo(&g), g, blur_settings(samples));
        let (_, image) = run(renderer, blur.as_ref(), &blur.output, size, true)?;
        let (rmse, ssim) = error(&image.context("image")?, &truth);
        let timed = camera(args.common.time_size);
        let ms = time(renderer, args, "MotionBlur", |_| {
            let g = gbuffer(renderer, layer.clone(), timed, None);
            let blur = MotionBlur::new(renderer, None, albedo(&g), g, blur_settings(samples));
            let name = blur.output.clone();
            Ok((blur as Arc<dyn Recipe>, name))
        })?;
        rows.push(Row {
            effect: Effect::MotionBlur,
            setting: format!("{samples} samples"),
            ms,
            rmse,
            ssim,
        });
    }
    Ok(())
}

/// The still scene's albedo 8x8 larger, box-downsampled: 64 samples a pixel.
fn supersampled(
    renderer: &Renderer,
    layer: &Arc<Layer>,
    size: (u32, u32),
) -> anyhow::Result<ImageF32> {
    let big = (size.0 * 8, size.1 * 8);
    let g = gbuffer(renderer, layer.clone(), camera(size), None);
    let (_, image) = run(renderer, g.as_ref(), &g.targets.color, big, true)?;
    let mut average = Average::new((size.0 * size.1) as usize);
    average.add_downsampled(&image.context("image")?, 8);
    Ok(average.image(size))
}

/// Frame `n` of TAA on the still scene with a jittered camera, for a target of `size`.
struct TaaRun {
    history: String,
    previous: Option<(Mat4, Vec2)>,
}

impl TaaRun {
    fn frame(
        &mut self,
        renderer: &Renderer,
        layer: &Arc<Layer>,
        n: u64,
        size: (u32, u32),
        quality: TaaQuality,
    ) -> Arc<Taa> {
        let jitter = jitter_ndc(n, size);
        let base = camera(size);
        let cam = CameraInput {
            projection: jittered(base.projection, jitter),
            ..base
        };
        let g = gbuffer(renderer, layer.clone(), cam, self.previous.map(|p| p.0));
        let settings = TaaSettings {
            quality,
            jitter,
            previous_jitter: self.previous.map_or(jitter, |p| p.1),
            ..Default::default()
        };
        self.previous = Some((cam.view_projection(), jitter));
        Taa::new(
            renderer,
            None,
            albedo(&g),
            g,
            settings,
            Some(self.history.clone()),
        )
    }
}

fn measure_taa(
    renderer: &Renderer,
    args: &PostArgs,
    truth: &ImageF32,
    layer: &Arc<Layer>,
    rows: &mut Vec<Row>,
) -> anyhow::Result<()> {
    for (name, quality) in [
        ("Low", TaaQuality::Low),
        ("Medium", TaaQuality::Medium),
        ("High", TaaQuality::High),
    ] {
        eprintln!("TAA {name}");
        let mut taa = TaaRun {
            history: format!("accuracy taa {name}"),
            previous: None,
        };
        let mut last = None;
        for n in 0..args.taa_frames.max(1) {
            let t = taa.frame(renderer, layer, n, args.error_size, quality);
            let read = n + 1 == args.taa_frames.max(1);
            last = run(renderer, t.as_ref(), &t.output, args.error_size, read)?.1;
        }
        let (rmse, ssim) = error(&last.context("image")?, truth);
        let mut timed = TaaRun {
            history: format!("accuracy taa time {name}"),
            previous: None,
        };
        let ms = time(renderer, args, "TAA", |n| {
            let t = timed.frame(renderer, layer, n, args.common.time_size, quality);
            let name = t.output.clone();
            Ok((t as Arc<dyn Recipe>, name))
        })?;
        rows.push(Row {
            effect: Effect::Taa,
            setting: format!("{name}, {} frames", args.taa_frames),
            ms,
            rmse,
            ssim,
        });
    }
    Ok(())
}

fn measure_fxaa(
    renderer: &Renderer,
    args: &PostArgs,
    truth: &ImageF32,
    layer: &Arc<Layer>,
    rows: &mut Vec<Row>,
) -> anyhow::Result<()> {
    let g = gbuffer(renderer, layer.clone(), camera(args.error_size), None);
    let (_, aliased) = run(
        renderer,
        g.as_ref(),
        &g.targets.color,
        args.error_size,
        true,
    )?;
    let (rmse, ssim) = error(&aliased.context("image")?, truth);
    rows.push(Row {
        effect: Effect::Fxaa,
        setting: "off (one sample)".to_owned(),
        ms: Some(0.0),
        rmse,
        ssim,
    });
    for (name, quality) in [
        ("Low", FxaaQuality::Low),
        ("Medium", FxaaQuality::Medium),
        ("High", FxaaQuality::High),
    ] {
        eprintln!("FXAA {name}");
        let g = gbuffer(renderer, layer.clone(), camera(args.error_size), None);
        let fxaa = Fxaa::new(renderer, None, albedo(&g), quality, 0.75);
        let (_, image) = run(renderer, fxaa.as_ref(), &fxaa.output, args.error_size, true)?;
        let (rmse, ssim) = error(&image.context("image")?, truth);
        let timed = camera(args.common.time_size);
        let ms = time(renderer, args, "FXAA", |_| {
            let g = gbuffer(renderer, layer.clone(), timed, None);
            let fxaa = Fxaa::new(renderer, None, albedo(&g), quality, 0.75);
            let name = fxaa.output.clone();
            Ok((fxaa as Arc<dyn Recipe>, name))
        })?;
        rows.push(Row {
            effect: Effect::Fxaa,
            setting: name.to_owned(),
            ms,
            rmse,
            ssim,
        });
    }
    Ok(())
}

pub fn run_post(args: &PostArgs) -> anyhow::Result<ExitCode> {
    let renderer = Renderer::headless().context("cannot open a GPU")?;
    let adapter = renderer.gpu.adapter_name();
    let mut rows = Vec::new();
    if args.only.contains(&Effect::Dof) {
        measure_dof(&renderer, args, &mut rows)?;
    }
    if args.only.contains(&Effect::MotionBlur) {
        measure_motion_blur(&renderer, args, &mut rows)?;
    }
    if args.only.contains(&Effect::Taa) || args.only.contains(&Effect::Fxaa) {
        let layer = scene(&renderer, 0.0, false)?;
        eprintln!("TAA/FXAA reference: 64 samples a pixel ...");
        let truth = supersampled(&renderer, &layer, args.error_size)?;
        if args.only.contains(&Effect::Taa) {
            measure_taa(&renderer, args, &truth, &layer, &mut rows)?;
        }
        if args.only.contains(&Effect::Fxaa) {
            measure_fxaa(&renderer, args, &truth, &layer, &mut rows)?;
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
    print!("{table}");
    if let Some(file) = &args.common.plot {
        let series = Series::group(rows.iter().filter(|r| r.ms.is_some()).map(|r| {
            let half = r.setting.ends_with(HALF_SUFFIX);
            (
                format!("{}{}", r.effect.name(), if half { " half" } else { "" }),
                (r.ms.unwrap_or(0.0), r.rmse, r.setting.clone()),
            )
        }));
        write_svg(
            file,
            &format!("Post effects on {adapter}: ms at {tw}x{th} against RMSE"),
            "RMSE (RGB)",
            &series,
        )?;
    }
    if let Some(out) = &args.common.out {
        std::fs::write(out, &table).with_context(|| format!("cannot write {}", out.display()))?;
    }
    Ok(ExitCode::SUCCESS)
}
