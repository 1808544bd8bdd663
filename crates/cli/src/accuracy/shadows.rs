//! Shadows: balls over a floor lit by one spot light of radius
//! `LIGHT_RADIUS`; the reference ray-casts the light's disk from every
//! pixel's surface point (spreadlight_reference::shadows), so soft shadows are
//! the truth and hard filters pay for their hard edges. Each filter is
//! measured at each map resolution; the error is the RMSE of the light's
//! visibility (shadowed over unshadowed lighting) over the pixels the spot
//! lights, and the share of those pixels off by more than 0.1.

use std::process::ExitCode;
use std::sync::Arc;

use anyhow::Context;
use glam::{Vec3, Vec4};
use spreadlight_reference::shadows::{DiskLight, Sphere, disk_samples, visibility};
use spreadlight_render::camera::{CameraInput, reverse_z};
use spreadlight_render::gbuffer::{GBuffer, Layer, RasterChoice};
use spreadlight_render::lighting::{CookTorrance, LightBuffer, LightLoop, SpotLight, Surfaces};
use spreadlight_render::readback::{ImageF32, render_and_read};
use spreadlight_render::scenes::balls_on_floor;
use spreadlight_render::shadows::{ShadowFilter, ShadowLights, ShadowMaps, ShadowSettings};
use spreadlight_render::{Recipe, Renderer, SizeRule};

use super::metrics::{self, Plane};
use super::plot::Series;
use super::{median, ms, pass_ms};
use crate::session::parse_size;

#[derive(clap::Args)]
pub struct ShadowArgs {
    #[command(flatten)]
    common: super::Common,
    /// Where the error is measured (the CPU reference casts rays from every pixel).
    #[arg(long, default_value = "320x180", value_parser = parse_size)]
    error_size: (u32, u32),
    /// Shadow-map resolutions, comma-separated.
    #[arg(long, default_value = "512,1024,2048,4096", value_delimiter = ',')]
    resolutions: Vec<u32>,
    /// Which rasterizer draws the maps.
    #[arg(long, value_enum, default_value = "auto")]
    raster: Raster,
    /// Rays per pixel in the reference.
    #[arg(long, default_value_t = 256)]
    rays: u32,
    /// Each setting's error image (|GPU - reference| visibility, white = 1), in DIR/shadows/.
    #[command(flatten)]
    images: super::ImageArgs,
}

#[derive(Clone, Copy, clap::ValueEnum)]
enum Raster {
    /// Compute where the adapter has 64-bit atomics, else the hardware.
    Auto,
    Compute,
    Hardware,
}

impl Raster {
    fn choice(self) -> RasterChoice {
        match self {
            Raster::Auto => RasterChoice::Auto,
            Raster::Compute => RasterChoice::Compute,
            Raster::Hardware => RasterChoice::Hardware,
        }
    }
}

/// The light's radius, for the reference's disk and PCSS's light size.
const LIGHT_RADIUS: f32 = 0.25;

/// The scene: (centre, radius) of each ball.
const BALLS: [([f32; 3], f32); 4] = [
    ([0.0, 0.8, 0.0], 0.8),
    ([-1.8, 0.5, 0.6], 0.5),
    ([1.6, 0.3, -0.4], 0.3),
    ([0.7, 1.9, 1.3], 0.35),
];

fn spot() -> SpotLight {
    SpotLight {
        shadow: Some(0),
        ..SpotLight::cone(
            Vec3::new(3.0, 7.0, 2.0),
            Vec3::new(-3.0, -7.0, -2.0),
            20.0,
            0.4,
            0.5,
        )
        .with_light(Vec3::ONE, 400.0)
    }
}

fn camera(size: (u32, u32)) -> CameraInput {
    super::camera_looking(Vec3::new(0.0, 6.0, 9.0), Vec3::new(0.0, 0.5, 0.0), size)
}

fn scene(renderer: &Renderer) -> anyhow::Result<Vec<Arc<Layer>>> {
    let balls: Vec<(Vec3, f32)> = BALLS.iter().map(|(c, r)| (Vec3::from(*c), *r)).collect();
    Ok(vec![balls_on_floor(renderer, &balls, 30.0, 96)?])
}

/// A labelled filter setting.
fn settings() -> Vec<(String, ShadowFilter)> {
    let mut s = vec![("Raw".to_owned(), ShadowFilter::Raw)];
    for k in [3, 5, 7] {
        s.push((format!("PCF {k}x{k}"), ShadowFilter::Pcf { kernel: k }));
    }
    for n in [8, 16, 32, 64] {
        s.push((
            format!("PCSS {n}"),
            ShadowFilter::Pcss {
                light_size: LIGHT_RADIUS,
                samples: n,
            },
        ));
    }
    s.push((
        "VSM".to_owned(),
        ShadowFilter::Vsm {
            bleeding: 0.3,
            blur: 2,
        },
    ));
    s
}

struct Frame {
    diffuse: ImageF32,
    depth: ImageF32,
    shadow_ms: Option<f64>,
    shade_ms: Option<f64>,
}

/// The node id the measured maps are kept under: one store, reused from frame to frame.
const MAPS_OWNER: u32 = 1;

/// One frame of the scene at `size`, with shadows of `filter` at `resolution` (None: unshadowed).
fn frame(
    renderer: &Renderer,
    layers: &[Arc<Layer>],
    size: (u32, u32),
    shadows: Option<(ShadowFilter, u32, RasterChoice)>,
    read: bool,
) -> anyhow::Result<Frame> {
    // New casters (the same geometry) every frame, so the maps are rendered
    // each time into the kept store, as for a scene that moves, rather than
    // reused or allocated anew.
    let layers: Vec<Arc<Layer>> = layers.iter().map(|l| Arc::new(Layer::clone(l))).collect();
    let spot = spot();
    let cam = camera(size);
    let lights = LightBuffer::spots(renderer, &[spot], None)?;
    let maps = match shadows {
        Some((filter, resolution, raster)) => Some(ShadowMaps::new(
            renderer,
            Some(MAPS_OWNER),
            &ShadowLights::Spot(vec![(0, spot.view, spot.projection)]),
            layers.clone(),
            &cam,
            ShadowSettings {
                resolution,
                filter,
                raster,
                ..Default::default()
            },
        )?),
        None => None,
    };
    let g = GBuffer::new(
        renderer,
        None,
        layers.to_vec(),
        cam,
        None,
        SizeRule::Relative(1.0),
    );
    let ct = CookTorrance::with_shadows(
        renderer,
        None,
        g.clone(),
        lights,
        LightLoop::Naive,
        true,
        Surfaces::PerMaterialId(vec![(0.8, 0.0)]),
        maps,
    );
    if !read {
        // Timing: run the frame and read nothing back, so the GPU never idles
        // waiting for the CPU (an idle GPU clocks down and times slow).
        let mut graph = spreadlight_render::FrameGraph::new(size);
        ct.declare(renderer, &mut graph);
        graph.request(&ct.diffuse);
        let (report, _) = graph.execute(renderer)?;
        if let Some((_, e)) = report.errors.first() {
            anyhow::bail!("the frame failed: {e}");
        }
        let empty = || ImageF32 {
            width: 0,
            height: 0,
            pixels: Vec::new(),
        };
        return Ok(Frame {
            diffuse: empty(),
            depth: empty(),
            shadow_ms: pass_ms(&report, "ShadowMap", None),
            shade_ms: pass_ms(&report, "CookTorrance", Some("shade")),
        });
    }
    let (report, images) = render_and_read(
        renderer,
        ct.as_ref(),
        size,
        &[&ct.diffuse, &g.targets.depth],
    )?;
    if let Some((_, e)) = report.errors.first() {
        anyhow::bail!("the frame failed: {e}");
    }
    let sum = |kind: &str, step| pass_ms(&report, kind, step);
    let mut images = images.into_iter();
    Ok(Frame {
        diffuse: images.next().context("diffuse")?,
        depth: images.next().context("depth")?,
        shadow_ms: sum("ShadowMap", None),
        shade_ms: sum("CookTorrance", Some("shade")),
    })
}

/// Median shadow-map and shading times over `frames` frames after a warm-up.
fn time(
    renderer: &Renderer,
    layers: &[Arc<Layer>],
    size: (u32, u32),
    (warmup, frames): (usize, usize),
    shadows: Option<(ShadowFilter, u32, RasterChoice)>,
) -> anyhow::Result<(Option<f64>, Option<f64>)> {
    for _ in 0..warmup {
        frame(renderer, layers, size, shadows, false)?;
    }
    let mut maps = Vec::new();
    let mut shade = Vec::new();
    for _ in 0..frames.max(1) {
        let f = frame(renderer, layers, size, shadows, false)?;
        maps.extend(f.shadow_ms);
        shade.extend(f.shade_ms);
    }
    Ok((median(maps), median(shade)))
}

/// The reference visibility of the spot's disk from every pixel the spot lights (None elsewhere).
fn reference(lit: &Frame, size: (u32, u32), rays: u32) -> Vec<Option<f32>> {
    let spot = spot();
    let inverse = (reverse_z(camera(size).projection) * camera(size).view).inverse();
    let light = DiskLight {
        center: spot.view.inverse().w_axis.truncate(),
        normal: spot.view.inverse().transform_vector3(Vec3::NEG_Z),
        radius: LIGHT_RADIUS,
    };
    let balls: Vec<Sphere> = BALLS
        .iter()
        .map(|(c, r)| Sphere {
            center: Vec3::from(*c),
            radius: *r,
        })
        .collect();
    let samples = disk_samples(rays);
    (0..size.0 * size.1)
        .map(|i| {
            let (x, y) = (i % size.0, i / size.0);
            let unshadowed = lit.diffuse.pixels[i as usize][0];
            let d = lit.depth.pixels[i as usize][0];
            if unshadowed <= 1e-3 || d <= 0.0 {
                return None;
            }
            let ndc = Vec4::new(
                (x as f32 + 0.5) / size.0 as f32 * 2.0 - 1.0,
                1.0 - (y as f32 + 0.5) / size.1 as f32 * 2.0,
                d,
                1.0,
            );
            let h = inverse * ndc;
            let p = h.truncate() / h.w;
            // Onto the true sphere's surface when on a ball (the mesh's facets
            // lie just inside it), then just off it along the normal, so a
            // grazing ray does not clip the ball it starts on.
            let p = match balls
                .iter()
                .find(|b| p.distance(b.center) < b.radius * 1.02)
            {
                Some(b) => b.center + (p - b.center).normalize_or_zero() * (b.radius + 2e-3),
                None => p + Vec3::Y * 2e-3,
            };
            Some(visibility(p, &light, &balls, &samples))
        })
        .collect()
}

/// The GPU's visibility of the light per pixel: shadowed over unshadowed lighting.
fn gpu_visibility(shadowed: &Frame, lit: &Frame, i: usize) -> f32 {
    (shadowed.diffuse.pixels[i][0] / lit.diffuse.pixels[i][0]).clamp(0.0, 1.0)
}

/// RMSE and the share of pixels off by more than 0.1, of the GPU's visibility against the reference.
/// SSIM of the GPU's visibility against the reference, over the lit pixels.
fn ssim(shadowed: &Frame, lit: &Frame, truth: &[Option<f32>], size: (u32, u32)) -> f64 {
    let mask: Vec<bool> = truth.iter().map(Option::is_some).collect();
    let gpu: Vec<f32> = (0..truth.len())
        .map(|i| {
            if mask[i] {
                gpu_visibility(shadowed, lit, i)
            } else {
                0.0
            }
        })
        .collect();
    let reference: Vec<f32> = truth.iter().map(|t| t.unwrap_or(0.0)).collect();
    let plane = |values| Plane {
        width: size.0,
        height: size.1,
        values,
        mask: Some(&mask),
    };
    metrics::Error::of(&[plane(&gpu)], &[plane(&reference)]).ssim
}

fn error(shadowed: &Frame, lit: &Frame, truth: &[Option<f32>]) -> (f64, f64) {
    let mut sum = 0.0;
    let mut off = 0usize;
    let mut n = 0usize;
    for (i, t) in truth.iter().enumerate() {
        let Some(t) = t else { continue };
        let v = gpu_visibility(shadowed, lit, i);
        let e = f64::from(v - t);
        sum += e * e;
        off += usize::from(e.abs() > 0.1);
        n += 1;
    }
    let n = n.max(1) as f64;
    ((sum / n).sqrt(), off as f64 / n)
}

/// |GPU - reference| visibility per pixel (`None` where the spot does not light).
fn error_values(shadowed: &Frame, lit: &Frame, truth: &[Option<f32>]) -> Vec<Option<f32>> {
    truth
        .iter()
        .enumerate()
        .map(|(i, t)| t.map(|t| (gpu_visibility(shadowed, lit, i) - t).abs()))
        .collect()
}

pub fn run(args: &ShadowArgs) -> anyhow::Result<ExitCode> {
    let renderer = Renderer::headless().context("cannot open a GPU")?;
    let adapter = renderer.gpu.adapter_name();
    let layers = scene(&renderer)?;
    eprintln!(
        "reference: {} rays per pixel at {}x{} ...",
        args.rays, args.error_size.0, args.error_size.1
    );
    let lit = frame(&renderer, &layers, args.error_size, None, true)?;
    let truth = reference(&lit, args.error_size, args.rays);
    let (_, base_shade) = time(
        &renderer,
        &layers,
        args.common.time_size,
        (args.common.warmup, args.common.frames),
        None,
    )?;
    let mut rows = Vec::new();
    let settings = settings();
    let total = settings.len() * args.resolutions.len();
    for (k, (name, filter)) in settings.iter().enumerate() {
        for (j, &res) in args.resolutions.iter().enumerate() {
            eprintln!(
                "[{}/{total}] {name} at {res}",
                k * args.resolutions.len() + j + 1
            );
            let setting = Some((*filter, res, args.raster.choice()));
            let shadowed = frame(&renderer, &layers, args.error_size, setting, true)?;
            let (rmse, off) = error(&shadowed, &lit, &truth);
            let ssim = ssim(&shadowed, &lit, &truth, args.error_size);
            if let Some(dir) = args.images.folder("shadows") {
                super::write_grey(
                    &dir,
                    &format!("{name} {res}"),
                    &error_values(&shadowed, &lit, &truth),
                    args.error_size,
                )?;
            }
            let (maps, shade) = time(
                &renderer,
                &layers,
                args.common.time_size,
                (args.common.warmup, args.common.frames),
                setting,
            )?;
            rows.push((name.clone(), res, maps, shade, rmse, off, ssim));
        }
    }
    let (tw, th) = args.common.time_size;
    let (ew, eh) = args.error_size;
    if args.common.json {
        for (name, res, maps, shade, rmse, off, ssim) in &rows {
            println!(
                "{}",
                serde_json::json!({
                    "effect": "shadows", "filter": name, "resolution": res, "adapter": adapter,
                    "time_size": format!("{tw}x{th}"), "error_size": format!("{ew}x{eh}"),
                    "shadow_map_ms": maps, "shade_ms": shade, "shade_unshadowed_ms": base_shade,
                    "rmse": rmse, "pixels_off_0_1": off, "ssim": ssim,
                })
            );
        }
        return Ok(ExitCode::SUCCESS);
    }
    let mut table = format!(
        "Shadow filters on {adapter} ({} raster): GPU ms at {tw}x{th} (median of {} frames after {}, back to back; the map pass renders \
         every frame here, no reuse), error at {ew}x{eh} against {} ray-cast samples of a spot light of radius {LIGHT_RADIUS} \
         (RMSE of visibility over the lit pixels; share of pixels off by more than 0.1). Shading without shadows: {} ms.\n\n\
         | filter | map | shadow map ms | shade ms | RMSE | off > 0.1 | SSIM |\n|---|---|---|---|---|---|---|\n",
        match args.raster {
            Raster::Auto => "automatic",
            Raster::Compute => "compute",
            Raster::Hardware => "hardware",
        },
        args.common.frames,
        args.common.warmup,
        args.rays,
        ms(base_shade)
    );
    for (name, res, maps, shade, rmse, off, ssim) in &rows {
        table.push_str(&format!(
            "| {name} | {res} | {} | {} | {rmse:.4} | {:.1}% | {ssim:.4} |\n",
            ms(*maps),
            ms(*shade),
            off * 100.0
        ));
    }
    args.common.publish(
        &table,
        &format!("Shadow filters on {adapter}: map + shade ms at {tw}x{th} against RMSE"),
        "RMSE of visibility",
        || {
            // One line per filter family and kernel: the points are map resolutions.
            Series::group(rows.iter().map(|(name, res, maps, shade, rmse, _, _)| {
                (
                    name.clone(),
                    (
                        maps.unwrap_or(0.0) + shade.unwrap_or(0.0),
                        *rmse,
                        res.to_string(),
                    ),
                )
            }))
        },
    )
}
