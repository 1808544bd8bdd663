//! Reflections: balls over a floor, all metals (albedo 0.8, F0 0.8), the
//! balls nearly mirrors (roughness BALL_ROUGHNESS), the floor glossy
//! (--floor-roughness), under the procedural sky. The reference
//! (spreadlight_reference::reflection) ray-traces the specular reflection term
//! per pixel with many GGX-sampled rays that see the other balls and the
//! floor as well as the sky; the GPU's prefiltered environment
//! (`Reflection`) sees only the sky, SSR sees what is on screen.
//!
//! Reflected surfaces shine with a stand-in radiance both sides share
//! (`surface_radiance`: albedo times the sky's colour towards their normal),
//! which is also the lit image SSR reads, so SSR's error is its own
//! (screen-space limits, steps, noise), not a lighting mismatch.
//!
//! Measured: the environment at each cube size x samples (its one-off build
//! time and the per-frame Reflection pass), and SSR at each max steps x rays
//! with temporal accumulation off and on (after --temporal-frames frames),
//! at every `--resolutions` (Half: rays traced for one pixel in four,
//! upsampled with depth awareness; the "SSR half" rows).
//! Error: RMSE of the specular term (linear RGB) and SSIM, over the surface pixels.

use std::process::ExitCode;
use std::sync::Arc;

use anyhow::Context;
use glam::{Vec3, Vec4};
use spreadlight_reference::reflection::{
    BallsScene, CpuEnvironment, CpuSky, Hit, SpecularSurface, Surface, specular_reflection,
};
use spreadlight_reference::shadows::Sphere;
use spreadlight_render::camera::{CameraInput, reverse_z};
use spreadlight_render::environment::{
    Environment, EnvironmentQuality, EnvironmentSource, Reflection, ReflectionMode, SkySettings,
    Ssr, SsrSettings,
};
use spreadlight_render::gbuffer::{GBuffer, Layer};
use spreadlight_render::material::{Feature, Material, MaterialWorld};
use spreadlight_render::readback::{ImageF32, render_and_read};
use spreadlight_render::scenes::{balls_on_floor, with_materials};
use spreadlight_render::static_texture::StaticTexture;
use spreadlight_render::{FrameGraph, Recipe, Renderer, SizeRule};

use super::metrics::{self, Plane};
use super::plot::Series;
use super::{median, ms, pass_ms};
use crate::session::parse_size;

#[derive(clap::Args)]
pub struct ReflectionArgs {
    #[command(flatten)]
    common: super::Common,
    /// Where the error is measured (the CPU reference traces rays from every pixel).
    #[arg(long, default_value = "240x135", value_parser = parse_size)]
    error_size: (u32, u32),
    /// Environment cube face sizes, comma-separated.
    #[arg(long, default_value = "32,128", value_delimiter = ',')]
    cube_sizes: Vec<u32>,
    /// GGX samples per prefiltered texel, comma-separated.
    #[arg(long, default_value = "16,128", value_delimiter = ',')]
    samples: Vec<u32>,
    /// SSR max steps, comma-separated.
    #[arg(long, default_value = "16,64", value_delimiter = ',')]
    steps: Vec<u32>,
    /// SSR rays per pixel, comma-separated.
    #[arg(long, default_value = "1,4", value_delimiter = ',')]
    ssr_rays: Vec<u32>,
    /// Frames accumulated before SSR's temporal error is measured.
    #[arg(long, default_value_t = 8)]
    temporal_frames: usize,
    /// The floor's roughness (the balls': 0.05).
    #[arg(long, default_value_t = 0.3)]
    floor_roughness: f32,
    /// Rays per pixel in the reference.
    #[arg(long, default_value_t = 256)]
    rays: u32,
    /// Resolutions SSR traces at (Full, Half), comma-separated.
    #[arg(long, default_value = "full,half", value_delimiter = ',', value_parser = super::parse_resolution)]
    resolutions: Vec<spreadlight_render::resolution::Resolution>,
}

const BALL_ROUGHNESS: f32 = 0.05;
const ALBEDO: f32 = 0.8;
const FLOOR: f32 = 30.0;
/// The scene: (centre, radius) of each ball.
const BALLS: [([f32; 3], f32); 4] = [
    ([0.0, 0.8, 0.0], 0.8),
    ([-1.8, 0.5, 0.6], 0.5),
    ([1.6, 0.3, -0.4], 0.3),
    ([0.7, 1.9, 1.3], 0.35),
];
/// The node ids the measured environment and SSR history are kept under.
const ENV_OWNER: u32 = 1;
const SSR_OWNER: u32 = 2;
/// The fallback SSR blends to: a well-filtered environment.
const FALLBACK: EnvironmentQuality = EnvironmentQuality {
    cube_size: 128,
    samples: 256,
};

fn sky() -> SkySettings {
    SkySettings {
        sun_radius: 0.03,
        sun_color: Vec3::new(20.0, 18.0, 15.0),
        ..Default::default()
    }
}

fn camera(size: (u32, u32)) -> CameraInput {
    super::camera_looking(Vec3::new(0.0, 3.0, 8.0), Vec3::new(0.0, 0.6, 0.0), size)
}

fn scene() -> BallsScene {
    BallsScene {
        balls: BALLS
            .iter()
            .map(|(c, r)| Sphere {
                center: Vec3::from(*c),
                radius: *r,
            })
            .collect(),
        floor: FLOOR,
    }
}

/// What a reflected surface shines with: albedo times the sky's colour towards its normal.
fn surface_radiance(normal: Vec3) -> Vec3 {
    let s = sky();
    let up = normal.y;
    let ambient = if up >= 0.0 {
        s.horizon.lerp(s.zenith, up)
    } else {
        s.horizon.lerp(s.ground, -up)
    };
    ambient * ALBEDO
}

fn roughness_of(surface: Surface, floor: f32) -> f32 {
    match surface {
        Surface::Ball(_) => BALL_ROUGHNESS,
        Surface::Floor => floor,
    }
}

/// The primary ray through pixel (x, y) at `size`: (eye, unit direction).
fn primary(size: (u32, u32), x: u32, y: u32) -> (Vec3, Vec3) {
    let cam = camera(size);
    let inverse = (reverse_z(cam.projection) * cam.view).inverse();
    let ndc = |d: f32| {
        let h = inverse
            * Vec4::new(
                (x as f32 + 0.5) / size.0 as f32 * 2.0 - 1.0,
                1.0 - (y as f32 + 0.5) / size.1 as f32 * 2.0,
                d,
                1.0,
            );
        h.truncate() / h.w
    };
    let (near, far) = (ndc(1.0), ndc(0.01));
    (near, (far - near).normalize())
}

/// The lit image SSR reads, traced on the CPU: surfaces' stand-in radiance, the sky elsewhere.
fn lit_image(size: (u32, u32)) -> Vec<[f32; 4]> {
    let (scene, sky) = (scene(), CpuSky::from(&sky()));
    (0..size.0 * size.1)
        .map(|i| {
            let (o, d) = primary(size, i % size.0, i / size.0);
            let c = match scene.trace(o, d) {
                Some(hit) => surface_radiance(hit.normal),
                None => sky.radiance(d),
            };
            [c.x, c.y, c.z, 1.0]
        })
        .collect()
}

/// The reference specular term per pixel (None where the camera sees the sky).
fn reference(size: (u32, u32), rays: u32, floor: f32) -> Vec<Option<Vec3>> {
    let (scene, sky) = (scene(), CpuSky::from(&sky()));
    let env = CpuEnvironment::Sky(sky);
    let radiance = |hit: &Hit| surface_radiance(hit.normal);
    (0..size.0 * size.1)
        .map(|i| {
            let (o, d) = primary(size, i % size.0, i / size.0);
            let hit = scene.trace(o, d)?;
            let s = SpecularSurface {
                point: hit.point,
                normal: hit.normal,
                view: -d,
                roughness: roughness_of(hit.surface, floor),
                f0: Vec3::splat(ALBEDO),
            };
            // A golden-ratio rotation per pixel decorrelates neighbours' patterns.
            let rotation = (i as f32 * 0.618_034).fract();
            Some(specular_reflection(
                &scene, &env, &radiance, &s, rays, rotation,
            ))
        })
        .collect()
}

struct Scene {
    layers: Vec<Arc<Layer>>,
    materials: Arc<MaterialWorld>,
}

fn gpu_scene(renderer: &Renderer, floor: f32) -> anyhow::Result<Scene> {
    let balls: Vec<(Vec3, f32)> = BALLS.iter().map(|(c, r)| (Vec3::from(*c), *r)).collect();
    let layer = balls_on_floor(renderer, &balls, FLOOR, 96)?;
    let metal = |r: f32| -> anyhow::Result<Material> {
        Ok(Material::new()
            .with(Feature::CookTorrance, &[[r, 1.0, 0.04, 0.0]])?
            .with(Feature::Reflection, &[[1.0, 0.0, 0.0, 0.0]])?)
    };
    Ok(Scene {
        layers: vec![with_materials(&layer, 0, 1)],
        materials: MaterialWorld::new(renderer, vec![metal(BALL_ROUGHNESS)?, metal(floor)?]),
    })
}

#[derive(Clone, Copy, Debug)]
enum Method {
    Environment(EnvironmentQuality),
    Ssr(SsrSettings),
}

impl Method {
    fn family(&self) -> String {
        match self {
            Method::Environment(_) => "Environment".to_owned(),
            Method::Ssr(s) => format!(
                "SSR{}{}",
                if s.resolution.is_half() { " half" } else { "" },
                if s.temporal { " temporal" } else { "" }
            ),
        }
    }

    fn setting(&self) -> String {
        match self {
            Method::Environment(q) => format!("cube {} x {} samples", q.cube_size, q.samples),
            Method::Ssr(s) => format!("{} steps x {} rays", s.max_steps, s.rays),
        }
    }
}

struct Frame {
    image: Option<ImageF32>,
    depth: Option<ImageF32>,
    build_ms: Option<f64>,
    frame_ms: Option<f64>,
}

/// One frame of `method` at `size`; `fresh_environment` builds the environment anew (to time the build).
fn frame(
    renderer: &Renderer,
    scene: &Scene,
    lit: &Arc<StaticTexture>,
    size: (u32, u32),
    method: Method,
    fresh_environment: bool,
    read: bool,
) -> anyhow::Result<Frame> {
    let g = GBuffer::new(
        renderer,
        None,
        scene.layers.clone(),
        camera(size),
        None,
        SizeRule::Relative(1.0),
    );
    let quality = match method {
        Method::Environment(q) => q,
        Method::Ssr(_) => FALLBACK,
    };
    let owner =
        (!fresh_environment).then_some(ENV_OWNER + quality.cube_size * 10_000 + quality.samples);
    let env = Environment::new(renderer, owner, EnvironmentSource::Sky(sky()), quality);
    let reflection = Reflection::new(
        renderer,
        None,
        g.clone(),
        scene.materials.clone(),
        env,
        ReflectionMode::Reflect,
    );
    let (recipe, output): (Arc<dyn Recipe>, String) = match method {
        Method::Environment(_) => (reflection.clone(), reflection.specular.clone()),
        Method::Ssr(settings) => {
            let ssr = Ssr::new(
                renderer,
                Some(SSR_OWNER),
                g.clone(),
                scene.materials.clone(),
                lit.texture_ref(),
                reflection.specular_texture(),
                settings,
            );
            let name = ssr.output.clone();
            (ssr, name)
        }
    };
    let (report, images) = if read {
        let (report, images) = render_and_read(
            renderer,
            recipe.as_ref(),
            size,
            &[&output, &g.targets.depth],
        )?;
        (report, Some(images))
    } else {
        let mut graph = FrameGraph::new(size);
        recipe.declare(renderer, &mut graph);
        graph.request(&output);
        let (report, _) = graph.execute(renderer)?;
        (report, None)
    };
    if let Some((_, e)) = report.errors.first() {
        anyhow::bail!("the frame failed: {e}");
    }
    let frame_ms = match method {
        Method::Environment(_) => pass_ms(&report, "Reflection", None),
        Method::Ssr(_) => pass_ms(&report, "SSR", None),
    };
    let mut images = images.map(Vec::into_iter);
    Ok(Frame {
        image: images.as_mut().and_then(Iterator::next),
        depth: images.as_mut().and_then(Iterator::next),
        build_ms: pass_ms(&report, "Environment", None),
        frame_ms,
    })
}

fn upload_lit(renderer: &Renderer, size: (u32, u32)) -> Arc<StaticTexture> {
    StaticTexture::from_rgba32f(
        &renderer.gpu,
        size.0,
        size.1,
        &lit_image(size),
        "reference lit image",
    )
}

fn error(
    image: &ImageF32,
    depth: &ImageF32,
    truth: &[Option<Vec3>],
    size: (u32, u32),
) -> metrics::Error {
    let mask: Vec<bool> = truth
        .iter()
        .zip(&depth.pixels)
        .map(|(t, d)| t.is_some() && d[0] > 0.0)
        .collect();
    let channel = |c: usize| -> (Vec<f32>, Vec<f32>) {
        let gpu = image.pixels.iter().map(|p| p[c]).collect();
        let reference = truth.iter().map(|t| t.map_or(0.0, |v| v[c])).collect();
        (gpu, reference)
    };
    let channels: Vec<(Vec<f32>, Vec<f32>)> = (0..3).map(channel).collect();
    let plane = |values| Plane {
        width: size.0,
        height: size.1,
        values,
        mask: Some(&mask),
    };
    let gpu: Vec<Plane<'_>> = channels.iter().map(|(g, _)| plane(g)).collect();
    let reference: Vec<Plane<'_>> = channels.iter().map(|(_, r)| plane(r)).collect();
    metrics::Error::of(&gpu, &reference)
}

fn methods(args: &ReflectionArgs) -> Vec<Method> {
    let mut m = Vec::new();
    for &cube_size in &args.cube_sizes {
        for &samples in &args.samples {
            m.push(Method::Environment(EnvironmentQuality {
                cube_size,
                samples,
            }));
        }
    }
    for temporal in [false, true] {
        for &resolution in &args.resolutions {
            for &max_steps in &args.steps {
                for &rays in &args.ssr_rays {
                    m.push(Method::Ssr(SsrSettings {
                        max_steps,
                        rays,
                        temporal,
                        resolution,
                        ..Default::default()
                    }));
                }
            }
        }
    }
    m
}

pub fn run(args: &ReflectionArgs) -> anyhow::Result<ExitCode> {
    let renderer = Renderer::headless().context("cannot open a GPU")?;
    let adapter = renderer.gpu.adapter_name();
    let scene = gpu_scene(&renderer, args.floor_roughness)?;
    eprintln!(
        "reference: {} rays per pixel at {}x{} ...",
        args.rays, args.error_size.0, args.error_size.1
    );
    let truth = reference(args.error_size, args.rays, args.floor_roughness);
    let lit_error = upload_lit(&renderer, args.error_size);
    let lit_time = upload_lit(&renderer, args.common.time_size);
    let methods = methods(args);
    let mut rows = Vec::new();
    for (k, method) in methods.iter().enumerate() {
        eprintln!(
            "[{}/{}] {} {}",
            k + 1,
            methods.len(),
            method.family(),
            method.setting()
        );
        renderer.reset_history();
        let accumulate = match method {
            Method::Ssr(s) if s.temporal => args.temporal_frames.max(1),
            _ => 1,
        };
        let mut last = None;
        for _ in 0..accumulate {
            last = Some(frame(
                &renderer,
                &scene,
                &lit_error,
                args.error_size,
                *method,
                false,
                true,
            )?);
        }
        let last = last.context("a frame")?;
        let (image, depth) = (last.image.context("image")?, last.depth.context("depth")?);
        let e = error(&image, &depth, &truth, args.error_size);
        // Timing at the large size: the build each frame (a fresh environment), then the per-frame pass.
        let mut builds = Vec::new();
        if let Method::Environment(_) = method {
            for i in 0..args.common.warmup.min(1) + args.common.frames.max(1) {
                let f = frame(
                    &renderer,
                    &scene,
                    &lit_time,
                    args.common.time_size,
                    *method,
                    true,
                    false,
                )?;
                if i >= args.common.warmup.min(1) {
                    builds.extend(f.build_ms);
                }
            }
        }
        renderer.reset_history();
        let mut times = Vec::new();
        for i in 0..args.common.warmup + args.common.frames.max(1) {
            let f = frame(
                &renderer,
                &scene,
                &lit_time,
                args.common.time_size,
                *method,
                false,
                false,
            )?;
            if i >= args.common.warmup {
                times.extend(f.frame_ms);
            }
        }
        rows.push((*method, median(builds), median(times), e));
    }
    let (tw, th) = args.common.time_size;
    let (ew, eh) = args.error_size;
    if args.common.json {
        for (method, build, time, e) in &rows {
            println!(
                "{}",
                serde_json::json!({
                    "effect": "reflection", "method": method.family(), "setting": method.setting(),
                    "adapter": adapter, "time_size": format!("{tw}x{th}"), "error_size": format!("{ew}x{eh}"),
                    "build_ms": build, "frame_ms": time, "rmse": e.rmse, "ssim": e.ssim,
                })
            );
        }
        return Ok(ExitCode::SUCCESS);
    }
    let mut table = format!(
        "Reflections on {adapter}: GPU ms at {tw}x{th} (median of {} frames after {}; build: the environment's one-off \
         prefilter, frame: the Reflection pass, or SSR's hi-z + trace (+ resolve) with its fallback environment already \
         built), error at {ew}x{eh} against {} ray-traced GGX samples per pixel (RMSE of the linear specular term over the \
         surface pixels; SSIM). Balls: roughness {BALL_ROUGHNESS}, floor: {}, all metals of F0 {ALBEDO}. SSR temporal: \
         after {} frames. SSR half: rays traced for one pixel in four, upsampled with depth awareness (+ upsample).\n\n| method | setting | build ms | frame ms | RMSE | SSIM |\n|---|---|---|---|---|---|\n",
        args.common.frames,
        args.common.warmup,
        args.rays,
        args.floor_roughness,
        args.temporal_frames
    );
    for (method, build, time, e) in &rows {
        table.push_str(&format!(
            "| {} | {} | {} | {} | {:.4} | {:.4} |\n",
            method.family(),
            method.setting(),
            ms(*build),
            ms(*time),
            e.rmse,
            e.ssim
        ));
    }
    args.common.publish(
        &table,
        &format!("Reflections on {adapter}: frame ms at {tw}x{th} against RMSE"),
        "RMSE of the specular term",
        || {
            Series::group(rows.iter().map(|(method, _, time, e)| {
                (
                    method.family(),
                    (time.unwrap_or(0.0), e.rmse, method.setting()),
                )
            }))
        },
    )
}
