//! Transmission: lit transparency's screen-space refraction against a CPU
//! ray trace (`spreadlight_reference::refraction`). A glass slab (a pane
//! turned about y, `--thickness` deep, index `--ior`) over a checkered
//! opaque wall; what the eye sees through it is traced exactly (Snell at
//! the entry, out parallel, on to the wall). Two knobs trade time for
//! accuracy:
//!
//! - depth-search steps (smooth glass): 0 samples where the slab's exit
//!   point projects (Khronos' sample viewer), each step walks the ray on to
//!   the opaque depth found under the current guess;
//! - blur taps (rough glass, `--roughness`): the reference is the same disc
//!   the shader blurs over, averaged over 1024 taps, so the error is the
//!   taps' undersampling of the kernel plus the steps' geometry (the
//!   kernel's shape is the model's, not a BTDF's);
//! - or the blur as one trilinear read of the opaque image's mip chain
//!   (`--blurs mips`; the steps rows run with each blur in `--blurs`): its
//!   error is the box-and-tent filter's difference from the disc, its cost
//!   one read plus the chain's build (a pass of its own, `mips_ms`).
//!
//! The first rows, `off`, draw the glass without transmission (blended: the
//! wall seen straight through), for the bare cost and the error refraction
//! removes: at alpha 0 every fragment is discarded (nothing covers), so a
//! second row draws it at alpha 0.01, the blend's writes included, the
//! fair baseline of what refraction adds. Error: RMSE of the linear colour
//! over the pixels that see the glass, and SSIM. GPU time: the
//! Transparency accumulation pass at `--time-size`, and the mip chain's.

use std::process::ExitCode;
use std::sync::Arc;

use anyhow::Context;
use glam::{Mat4, Vec2, Vec3};
use spreadlight_reference::refraction::{hit_plane, through_slab};
use spreadlight_render::camera::CameraInput;
use spreadlight_render::gbuffer::{DrawBatch, GBuffer, InstanceInput, Layer};
use spreadlight_render::mesh::primitives::plane;
use spreadlight_render::post::{
    RefractionBlur, TransmissionSettings, Transparency, TransparencySettings,
};
use spreadlight_render::readback::{ImageF32, render_and_read};
use spreadlight_render::static_texture::StaticTexture;
use spreadlight_render::{Renderer, SizeRule};

use super::metrics::{self, Plane};
use super::plot::Series;
use super::{median, ms, pass_ms};
use crate::session::parse_size;

#[derive(clap::Args)]
pub struct TransmissionArgs {
    #[command(flatten)]
    common: super::Common,
    /// Where the error is measured.
    #[arg(long, default_value = "320x180", value_parser = parse_size)]
    error_size: (u32, u32),
    /// Depth-search steps, comma-separated (smooth glass).
    #[arg(long, default_value = "0,1,2,4", value_delimiter = ',')]
    steps: Vec<u32>,
    /// Blur taps, comma-separated (rough glass, 2 steps).
    #[arg(long, default_value = "1,4,8,16,32", value_delimiter = ',')]
    taps: Vec<u32>,
    #[arg(long, default_value_t = 1.5)]
    ior: f32,
    /// The slab's depth (world units; the pane is 3 wide).
    #[arg(long, default_value_t = 0.5)]
    thickness: f32,
    /// The rough glass's roughness.
    #[arg(long, default_value_t = 0.3)]
    roughness: f32,
    /// Which blurs to measure, comma-separated: taps (the taps rows, and
    /// the steps rows read by hand), mips (one row of rough glass, and the
    /// steps rows through the chain).
    #[arg(long, default_value = "taps,mips", value_delimiter = ',', value_parser = parse_blur)]
    blurs: Vec<RefractionBlur>,
}

fn parse_blur(s: &str) -> Result<RefractionBlur, String> {
    match s.to_ascii_lowercase().as_str() {
        "taps" => Ok(RefractionBlur::Taps),
        "mips" => Ok(RefractionBlur::Mips),
        _ => Err(format!("`{s}` is not a refraction blur: taps or mips")),
    }
}

const EYE: Vec3 = Vec3::new(0.0, 0.0, 6.0);
/// The pane's centre, size and turn about y.
const PANE: Vec3 = Vec3::new(0.0, 0.0, 2.5);
const PANE_SIZE: f32 = 3.0;
const TILT: f32 = 0.5;
/// The checker's cell on the wall (z = 0).
const CELL: f32 = 0.25;

fn camera(size: (u32, u32)) -> CameraInput {
    super::camera_looking(EYE, Vec3::ZERO, size)
}

fn pane_normal() -> Vec3 {
    Mat4::from_rotation_y(TILT).transform_vector3(Vec3::Z)
}

/// The wall's colour at world point `p` (z = 0): a two-tone checker.
fn checker(p: Vec3) -> Vec3 {
    let cell = (p.x / CELL).floor() as i64 + (p.y / CELL).floor() as i64;
    if cell.rem_euclid(2) == 0 {
        Vec3::new(0.9, 0.8, 0.3)
    } else {
        Vec3::new(0.1, 0.2, 0.5)
    }
}

/// The unit ray from the eye through screen point `uv` (0..1, y down).
fn ray(inverse: Mat4, uv: Vec2) -> Vec3 {
    let ndc = Vec2::new(uv.x * 2.0 - 1.0, 1.0 - uv.y * 2.0);
    let far = inverse.project_point3(ndc.extend(0.5));
    (far - EYE).normalize_or(Vec3::NEG_Z)
}

/// The opaque image: the wall where each pixel's ray meets it.
fn wall_at(inverse: Mat4, uv: Vec2) -> Vec3 {
    hit_plane(EYE, ray(inverse, uv), Vec3::ZERO, Vec3::Z).map_or(Vec3::ZERO, checker)
}

/// Where `p` is on screen (uv).
fn to_uv(view_projection: Mat4, p: Vec3) -> Vec2 {
    let ndc = view_projection.project_point3(p);
    Vec2::new(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5)
}

/// Per pixel: the wall seen through the slab (the reference's sample
/// point on screen) when the pixel sees the pane.
fn reference_uvs(size: (u32, u32), ior: f32, thickness: f32) -> Vec<Option<Vec2>> {
    let c = camera(size);
    let view_projection = c.projection * c.view;
    let inverse = view_projection.inverse();
    let n = pane_normal();
    let across = n.cross(Vec3::Y).normalize();
    (0..size.0 * size.1)
        .map(|i| {
            let uv = Vec2::new((i % size.0) as f32 + 0.5, (i / size.0) as f32 + 0.5)
                / Vec2::new(size.0 as f32, size.1 as f32);
            let d = ray(inverse, uv);
            let entry = hit_plane(EYE, d, PANE, n)?;
            let local = entry - PANE;
            let half = PANE_SIZE * 0.5;
            if local.dot(across).abs() > half || local.y.abs() > half {
                return None;
            }
            let (back, _) = through_slab(entry, d, n, ior, thickness, Vec3::ZERO, Vec3::Z)?;
            Some(to_uv(view_projection, back))
        })
        .collect()
}

/// The reference image: the wall at each pixel's reference point, averaged
/// over the shader's blur disc (1024 taps) when `radius` (uv, as the
/// shader's: 0.1 x roughness x clamp(2 ior - 2, 0, 1)) is not 0.
fn reference(size: (u32, u32), uvs: &[Option<Vec2>], radius: f32) -> Vec<Option<Vec3>> {
    let c = camera(size);
    let inverse = (c.projection * c.view).inverse();
    let aspect = Vec2::new(size.1 as f32 / size.0 as f32, 1.0);
    let taps = if radius > 0.0 { 1024 } else { 1 };
    uvs.iter()
        .map(|uv| {
            let uv = (*uv)?;
            let sum: Vec3 = (0..taps)
                .map(|i| {
                    let rho = (i as f32 / taps as f32).sqrt() * radius;
                    let theta = i as f32 * 2.399_963_2;
                    let at =
                        (uv + Vec2::from_angle(theta) * rho * aspect).clamp(Vec2::ZERO, Vec2::ONE);
                    wall_at(inverse, at)
                })
                .sum();
            Some(sum / taps as f32)
        })
        .collect()
}

/// A pane or the wall: `plane()` turned to face +z, scaled and placed.
fn quad(renderer: &Renderer, transform: Mat4, color: [f32; 4]) -> anyhow::Result<Arc<Layer>> {
    let mesh = renderer.meshes.upload(&renderer.gpu, &plane())?;
    let t = transform * Mat4::from_rotation_x(std::f32::consts::FRAC_PI_2);
    Ok(Arc::new(Layer::plain(vec![DrawBatch {
        mesh,
        instances: vec![InstanceInput {
            transform: t,
            previous_transform: t,
            color,
            material_id: 0,
            object_id: 0,
        }],
    }])))
}

/// A frame's GPU ms: the accumulation pass and the mip chain's build.
#[derive(Clone, Copy, Default)]
struct Times {
    accumulate: Option<f64>,
    mips: Option<f64>,
}

/// One frame at `size` with the pane's alpha: the composite and its times.
fn frame(
    renderer: &Renderer,
    size: (u32, u32),
    transmission: TransmissionSettings,
    roughness: f32,
    alpha: f32,
) -> anyhow::Result<(ImageF32, Times)> {
    let c = camera(size);
    let inverse = (c.projection * c.view).inverse();
    let pixels: Vec<[f32; 4]> = (0..size.0 * size.1)
        .map(|i| {
            let uv = Vec2::new((i % size.0) as f32 + 0.5, (i / size.0) as f32 + 0.5)
                / Vec2::new(size.0 as f32, size.1 as f32);
            wall_at(inverse, uv).extend(1.0).to_array()
        })
        .collect();
    let lit =
        StaticTexture::from_rgba32f(&renderer.gpu, size.0, size.1, &pixels, "transmission wall");
    let wall = quad(renderer, Mat4::from_scale(Vec3::splat(40.0)), [1.0; 4])?;
    let g = GBuffer::new(renderer, None, vec![wall], c, None, SizeRule::Relative(1.0));
    let pane = quad(
        renderer,
        Mat4::from_translation(PANE)
            * Mat4::from_rotation_y(TILT)
            * Mat4::from_scale(Vec3::splat(PANE_SIZE)),
        [1.0, 1.0, 1.0, alpha],
    )?;
    let settings = TransparencySettings {
        ambient: Vec3::ONE,
        light_color: Vec3::ZERO,
        roughness,
        transmission,
        ..Default::default()
    };
    let pass = Transparency::new(renderer, None, lit.texture_ref(), g, vec![pane], settings);
    let (report, images) = render_and_read(renderer, pass.as_ref(), size, &[&pass.output])?;
    if let Some((_, e)) = report.errors.first() {
        anyhow::bail!("the frame failed: {e}");
    }
    let image = images.into_iter().next().context("the composite")?;
    let times = Times {
        accumulate: pass_ms(&report, "Transparency", Some("accumulate")),
        mips: pass_ms(&report, "Transparency", Some("refraction mips")),
    };
    Ok((image, times))
}

/// RMSE and SSIM over the pixels that see the glass.
fn error(image: &ImageF32, truth: &[Option<Vec3>], size: (u32, u32)) -> metrics::Error {
    let mask: Vec<bool> = truth.iter().map(Option::is_some).collect();
    let channel = |c: usize| -> (Vec<f32>, Vec<f32>) {
        image
            .pixels
            .iter()
            .zip(truth)
            .map(|(p, t)| (p[c], t.map_or(p[c], |t| t[c])))
            .unzip()
    };
    let (approx, reference): (Vec<Vec<f32>>, Vec<Vec<f32>>) = (0..3).map(channel).unzip();
    metrics::Error::of(
        &Plane::channels(&approx, Some(&mask), size),
        &Plane::channels(&reference, Some(&mask), size),
    )
}

struct Row {
    family: &'static str,
    setting: String,
    ms: Option<f64>,
    /// The mip chain's build (rows that blur by it).
    mips_ms: Option<f64>,
    e: metrics::Error,
}

impl Row {
    /// What the row costs: the accumulation and the chain's build.
    fn total(&self) -> Option<f64> {
        self.ms.map(|a| a + self.mips_ms.unwrap_or(0.0))
    }
}

pub fn run(args: &TransmissionArgs) -> anyhow::Result<ExitCode> {
    let renderer = Renderer::headless().context("cannot open a GPU")?;
    let adapter = renderer.gpu.adapter_name();
    let size = args.error_size;
    let uvs = reference_uvs(size, args.ior, args.thickness);
    let radius = 0.1 * args.roughness.clamp(0.0, 1.0) * (2.0 * args.ior - 2.0).clamp(0.0, 1.0);
    let sharp = reference(size, &uvs, 0.0);
    let blurred = reference(size, &uvs, radius);
    let settings = |steps: u32, taps: u32, blur: RefractionBlur| TransmissionSettings {
        factor: 1.0,
        ior: args.ior,
        thickness: args.thickness,
        taps,
        steps,
        blur,
        ..Default::default()
    };
    let (taps, mips) = (
        args.blurs.contains(&RefractionBlur::Taps),
        args.blurs.contains(&RefractionBlur::Mips),
    );
    let mut rows = Vec::new();
    // First the baselines: no transmission, the glass blended (here fully
    // clear: the wall straight through) at alpha 0, every fragment
    // discarded, and at alpha 0.01, drawn and blended as glass is.
    let off = TransmissionSettings {
        factor: 0.0,
        ..settings(0, 1, RefractionBlur::Taps)
    };
    // Per row: its family, setting, transmission, roughness, the pane's
    // alpha and the reference it is measured against.
    let mut families = vec![
        (
            "off",
            "blended, discarded (alpha 0)".to_owned(),
            off,
            0.0,
            0.0,
            &sharp,
        ),
        (
            "off",
            "blended, drawn (alpha 0.01)".to_owned(),
            off,
            0.0,
            0.01,
            &sharp,
        ),
    ];
    for (on, family, blur) in [
        (taps, "steps (smooth, by hand)", RefractionBlur::Taps),
        (mips, "steps (smooth, mips)", RefractionBlur::Mips),
    ] {
        for &s in args.steps.iter().filter(|_| on) {
            families.push((
                family,
                format!("{s} steps"),
                settings(s, 1, blur),
                0.0,
                0.0,
                &sharp,
            ));
        }
    }
    for &t in args.taps.iter().filter(|_| taps) {
        let rough = settings(2, t, RefractionBlur::Taps);
        families.push((
            "taps (rough)",
            format!("{t} taps"),
            rough,
            args.roughness,
            0.0,
            &blurred,
        ));
    }
    if mips {
        let rough = settings(2, 1, RefractionBlur::Mips);
        families.push((
            "mips (rough)",
            "1 trilinear read".to_owned(),
            rough,
            args.roughness,
            0.0,
            &blurred,
        ));
    }
    for (family, setting, t, roughness, alpha, truth) in families {
        let (image, _) = frame(&renderer, size, t, roughness, alpha)?;
        let e = error(&image, truth, size);
        let (mut accumulate, mut chain) = (Vec::new(), Vec::new());
        for i in 0..args.common.warmup + args.common.frames.max(1) {
            let (_, times) = frame(&renderer, args.common.time_size, t, roughness, alpha)?;
            if i >= args.common.warmup {
                accumulate.extend(times.accumulate);
                chain.extend(times.mips);
            }
        }
        rows.push(Row {
            family,
            setting,
            ms: median(accumulate),
            mips_ms: median(chain),
            e,
        });
    }
    let (ew, eh) = size;
    let (tw, th) = args.common.time_size;
    if args.common.json {
        for r in &rows {
            println!(
                "{}",
                serde_json::json!({
                    "effect": "transmission", "method": r.family, "setting": r.setting, "adapter": adapter,
                    "error_size": format!("{ew}x{eh}"), "time_size": format!("{tw}x{th}"),
                    "accumulate_ms": r.ms, "mips_ms": r.mips_ms, "total_ms": r.total(),
                    "rmse": r.e.rmse, "ssim": r.e.ssim,
                })
            );
        }
        return Ok(ExitCode::SUCCESS);
    }
    let mut table = format!(
        "Transmission on {adapter}: GPU ms of the Transparency accumulation pass and of the refraction mip \
         chain at {tw}x{th} (median of {} frames after {}), error at {ew}x{eh} over the pixels that see the glass \
         (a slab {} deep, ior {}, turned {TILT} rad, over a checkered wall; RMSE of the linear colour, SSIM) \
         against a CPU ray trace (steps: smooth glass; taps and mips: roughness {}, 2 steps, against the \
         shader's blur disc averaged over 1024 taps).\n\n| method | setting | accumulate ms | mips ms | \
         RMSE | SSIM |\n|---|---|---|---|---|---|\n",
        args.common.frames, args.common.warmup, args.thickness, args.ior, args.roughness,
    );
    for r in &rows {
        table.push_str(&format!(
            "| {} | {} | {} | {} | {:.4} | {:.4} |\n",
            r.family,
            r.setting,
            ms(r.ms),
            ms(r.mips_ms),
            r.e.rmse,
            r.e.ssim
        ));
    }
    args.common.publish(
        &table,
        &format!("Transmission on {adapter}: accumulation ms against RMSE"),
        "RMSE of the colour through the glass",
        || {
            Series::group(rows.iter().map(|r| {
                (
                    r.family.to_owned(),
                    (r.total().unwrap_or(0.0), r.e.rmse, r.setting.clone()),
                )
            }))
        },
    )
}
