//! glTF materials: the textured floor (`models::textured_floor`, loaded
//! through the importer like any file) under one sun, seen at a grazing
//! angle. The GPU shades it as every glTF scene (the G-buffer's surface
//! resolve samples the maps, CookTorrance shades: diffuse + specular), once
//! per map filtering (`MapFiltering`: point, bilinear, trilinear,
//! trilinear + 16x anisotropic). The CPU reference
//! (`spreadlight_gltf::reference`, `spreadlight_reference::material`) shades the same floor with the same
//! BRDF and the same texels, point-sampled where each ray meets the floor:
//! one ray through the pixel's centre (what the GPU computes, texel for
//! texel, with point filtering), and --supersamples rays on a stratified
//! grid (the image without aliasing, which filtering should approach).
//!
//! Measured per filtering: the surface resolve's GPU time (where maps are
//! sampled) at --time-size, and RMSE (linear RGB) and SSIM over the floor's
//! pixels against both references at --error-size.

use std::process::ExitCode;
use std::sync::Arc;

use anyhow::Context;
use glam::{Vec3, Vec4};
use spreadlight_gltf::models::{self, FLOOR_HALF};
use spreadlight_gltf::reference::sample_material;
use spreadlight_gltf::{GltfScene, MaterialData, load_gltf_slice};
use spreadlight_reference::material::shade_sun;
use spreadlight_render::camera::{CameraInput, reverse_z};
use spreadlight_render::gbuffer::{DrawBatch, GBuffer, InstanceInput, Layer, LayerFeatures};
use spreadlight_render::lighting::{CookTorrance, LightBuffer, LightLoop, SunLight, Surfaces};
use spreadlight_render::material::{MapFiltering, Material, MaterialWorld};
use spreadlight_render::readback::{ImageF32, render_and_read};
use spreadlight_render::{FrameGraph, Recipe, Renderer, SizeRule};

use super::metrics::{self, Plane};
use super::plot::Series;
use super::{median, ms, pass_ms};
use crate::session::parse_size;

#[derive(clap::Args)]
pub struct GltfArgs {
    #[command(flatten)]
    common: super::Common,
    /// Where the error is measured (the CPU reference shades every sample of every pixel).
    #[arg(long, default_value = "320x180", value_parser = parse_size)]
    error_size: (u32, u32),
    /// Rays per pixel of the supersampled reference, on a square grid (16: 4 x 4).
    #[arg(long, default_value_t = 16)]
    supersamples: u32,
}

/// The sun: travelling down and away from the camera's right, white.
const SUN_TRAVEL: [f32; 3] = [-0.4, -1.0, -0.3];
const SUN_ILLUMINANCE: f32 = 3.0;
/// CookTorrance's Energy Compensation, on as in `view`.
const COMPENSATE: bool = true;

fn camera(size: (u32, u32)) -> CameraInput {
    super::camera_looking(Vec3::new(0.0, 1.2, 8.0), Vec3::new(0.0, 0.0, -4.0), size)
}

/// The ray through (x, y) in pixels (0.5 is a pixel's centre): (eye, unit direction).
fn ray(size: (u32, u32), x: f32, y: f32) -> (Vec3, Vec3) {
    let cam = camera(size);
    let inverse = (reverse_z(cam.projection) * cam.view).inverse();
    let at = |depth: f32| {
        let h = inverse
            * Vec4::new(
                x / size.0 as f32 * 2.0 - 1.0,
                1.0 - y / size.1 as f32 * 2.0,
                depth,
                1.0,
            );
        h.truncate() / h.w
    };
    let (near, far) = (at(1.0), at(0.01));
    (near, (far - near).normalize())
}

/// The floor's radiance towards the eye along a ray, or None where it misses the floor.
fn trace(material: &MaterialData, eye: Vec3, dir: Vec3) -> Option<Vec3> {
    if dir.y >= -1e-6 || eye.y <= 0.0 {
        return None;
    }
    let p = eye + dir * (-eye.y / dir.y);
    if p.x.abs() > FLOOR_HALF || p.z.abs() > FLOOR_HALF {
        return None;
    }
    // The floor's UVs: 0 at its -x -z corner, FLOOR_REPEAT at the other.
    let to_uv = |t: f32| (t + FLOOR_HALF) / (2.0 * FLOOR_HALF) * models::FLOOR_REPEAT;
    let uv = [to_uv(p.x), to_uv(p.z)];
    let surface = sample_material(material, [uv, uv], Vec4::ONE);
    Some(shade_sun(
        &surface,
        Vec3::Y,
        -dir,
        Vec3::from(SUN_TRAVEL).normalize(),
        Vec3::splat(SUN_ILLUMINANCE),
        COMPENSATE,
    ))
}

/// Per pixel, the reference with `n` x `n` rays (None where the centre ray misses the floor).
fn reference(material: &MaterialData, size: (u32, u32), n: u32) -> Vec<Option<Vec3>> {
    (0..size.0 * size.1)
        .map(|i| {
            let (px, py) = ((i % size.0) as f32, (i / size.0) as f32);
            let (eye, centre) = ray(size, px + 0.5, py + 0.5);
            trace(material, eye, centre)?;
            let (mut sum, mut hits) = (Vec3::ZERO, 0u32);
            for k in 0..n * n {
                let fx = ((k % n) as f32 + 0.5) / n as f32;
                let fy = ((k / n) as f32 + 0.5) / n as f32;
                let (eye, dir) = ray(size, px + fx, py + fy);
                if let Some(c) = trace(material, eye, dir) {
                    sum += c;
                    hits += 1;
                }
            }
            Some(sum / hits.max(1) as f32)
        })
        .collect()
}

/// The floor on the GPU: its mesh, materials (glTF's default material at
/// id 0, then the file's) and instances, as the glTF node makes them.
struct Scene {
    batches: Vec<DrawBatch>,
    materials: Vec<Material>,
}

fn gpu_scene(renderer: &Renderer, scene: &GltfScene) -> anyhow::Result<Scene> {
    let meshes = scene
        .meshes
        .iter()
        .map(|m| renderer.meshes.upload(&renderer.gpu, m))
        .collect::<Result<Vec<_>, _>>()?;
    let batches = meshes
        .iter()
        .enumerate()
        .map(|(k, mesh)| DrawBatch {
            mesh: mesh.clone(),
            instances: scene
                .instances
                .iter()
                .filter(|i| i.mesh == k)
                .map(|i| InstanceInput {
                    transform: i.transform,
                    previous_transform: i.transform,
                    color: i
                        .material
                        .and_then(|m| scene.materials.get(m))
                        .map_or([1.0; 4], |m| m.base_color),
                    material_id: i.material.map_or(0, |m| m as u32 + 1),
                    object_id: 1,
                })
                .collect(),
        })
        .collect();
    let materials = std::iter::once(MaterialData::default())
        .chain(scene.materials.iter().cloned())
        .map(|m| m.to_material())
        .collect();
    Ok(Scene { batches, materials })
}

struct Setting {
    filtering: MapFiltering,
    layer: Arc<Layer>,
    world: Arc<MaterialWorld>,
}

struct Frame {
    /// Diffuse + specular, and depth (0 where nothing was drawn).
    shaded: Option<(ImageF32, ImageF32)>,
    resolve_ms: Option<f64>,
}

fn frame(
    renderer: &Renderer,
    setting: &Setting,
    size: (u32, u32),
    read: bool,
) -> anyhow::Result<Frame> {
    let g = GBuffer::new(
        renderer,
        None,
        vec![setting.layer.clone()],
        camera(size),
        None,
        SizeRule::Relative(1.0),
    );
    let sun = SunLight {
        direction: Vec3::from(SUN_TRAVEL),
        color: Vec3::ONE,
        illuminance: SUN_ILLUMINANCE,
        shadow: None,
    };
    let ct = CookTorrance::new(
        renderer,
        None,
        g.clone(),
        LightBuffer::suns(renderer, &[sun]),
        LightLoop::Naive,
        COMPENSATE,
        Surfaces::Materials(setting.world.clone()),
    );
    let (report, images) = if read {
        let (report, images) = render_and_read(
            renderer,
            ct.as_ref(),
            size,
            &[&ct.diffuse, &ct.specular, &g.targets.depth],
        )?;
        (report, Some(images))
    } else {
        // Timing: nothing read back, so the GPU never waits on the CPU.
        let mut graph = FrameGraph::new(size);
        ct.declare(renderer, &mut graph);
        graph.request(&ct.diffuse);
        graph.request(&ct.specular);
        let (report, _) = graph.execute(renderer)?;
        (report, None)
    };
    if let Some((_, e)) = report.errors.first() {
        anyhow::bail!("the frame failed: {e}");
    }
    let shaded = match images {
        Some(images) => {
            let [diffuse, specular, depth] = <[ImageF32; 3]>::try_from(images)
                .map_err(|_| anyhow::anyhow!("three images read back"))?;
            let mut sum = diffuse;
            for (d, s) in sum.pixels.iter_mut().zip(&specular.pixels) {
                for c in 0..3 {
                    d[c] += s[c];
                }
            }
            Some((sum, depth))
        }
        None => None,
    };
    Ok(Frame {
        shaded,
        // The G-buffer's resolve, merged with its motion pass when a frame needs both.
        resolve_ms: pass_ms(&report, "MRE", Some("resolve surface"))
            .or_else(|| pass_ms(&report, "MRE", Some("resolve surface and motion"))),
    })
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
    let channels: Vec<(Vec<f32>, Vec<f32>)> = (0..3)
        .map(|c| {
            let gpu = image.pixels.iter().map(|p| p[c]).collect();
            let reference = truth.iter().map(|t| t.map_or(0.0, |v| v[c])).collect();
            (gpu, reference)
        })
        .collect();
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

struct Row {
    filtering: MapFiltering,
    resolve_ms: Option<f64>,
    point: metrics::Error,
    supersampled: metrics::Error,
}

pub fn run(args: &GltfArgs) -> anyhow::Result<ExitCode> {
    let renderer = Renderer::headless().context("cannot open a GPU")?;
    let adapter = renderer.gpu.adapter_name();
    let scene =
        load_gltf_slice(&models::textured_floor(), None).context("the generated floor loads")?;
    let material = scene.materials.first().context("the floor's material")?;
    let gpu = gpu_scene(&renderer, &scene)?;
    let n = (args.supersamples.max(1) as f32).sqrt().round().max(1.0) as u32;
    let size = args.error_size;
    eprintln!(
        "reference: 1 and {} rays per pixel at {}x{} ...",
        n * n,
        size.0,
        size.1
    );
    let point_truth = reference(material, size, 1);
    let supersampled_truth = reference(material, size, n);
    let mut rows = Vec::new();
    for (k, filtering) in MapFiltering::ALL.into_iter().enumerate() {
        eprintln!(
            "[{}/{}] {}",
            k + 1,
            MapFiltering::ALL.len(),
            filtering.name()
        );
        let world = MaterialWorld::with_map_filtering(&renderer, gpu.materials.clone(), filtering);
        let layer = Arc::new(
            Layer::new(None, gpu.batches.clone(), LayerFeatures::default(), None)?
                .with_materials(Some(world.clone())),
        );
        let setting = Setting {
            filtering,
            layer,
            world,
        };
        let (image, depth) = frame(&renderer, &setting, size, true)?
            .shaded
            .context("the shaded image")?;
        let point = error(&image, &depth, &point_truth, size);
        let supersampled = error(&image, &depth, &supersampled_truth, size);
        let mut times = Vec::new();
        for i in 0..args.common.warmup + args.common.frames.max(1) {
            let f = frame(&renderer, &setting, args.common.time_size, false)?;
            if i >= args.common.warmup {
                times.extend(f.resolve_ms);
            }
        }
        rows.push(Row {
            filtering: setting.filtering,
            resolve_ms: median(times),
            point,
            supersampled,
        });
    }
    report(args, &adapter, n * n, &rows)
}

fn report(args: &GltfArgs, adapter: &str, rays: u32, rows: &[Row]) -> anyhow::Result<ExitCode> {
    let (tw, th) = args.common.time_size;
    let (ew, eh) = args.error_size;
    if args.common.json {
        for r in rows {
            println!(
                "{}",
                serde_json::json!({
                    "effect": "gltf", "filtering": r.filtering.name(), "adapter": adapter,
                    "time_size": format!("{tw}x{th}"), "error_size": format!("{ew}x{eh}"),
                    "resolve_ms": r.resolve_ms,
                    "rmse_point": r.point.rmse, "ssim_point": r.point.ssim,
                    "rmse_supersampled": r.supersampled.rmse, "ssim_supersampled": r.supersampled.ssim,
                })
            );
        }
        return Ok(ExitCode::SUCCESS);
    }
    let mut table = format!(
        "glTF material maps on {adapter}: the surface resolve's GPU ms at {tw}x{th} (where maps are sampled; median of {} \
         frames after {}), error at {ew}x{eh} of the shaded floor (diffuse + specular of one sun, linear RGB, over the \
         floor's pixels) against the CPU reference with the same BRDF and texels point-sampled where each ray meets the \
         floor: 1 ray per pixel (the material's error: what point filtering should match) and {rays} rays per pixel \
         (the image without aliasing: what filtering should approach).\n\n\
         | filtering | resolve ms | RMSE vs 1 ray | SSIM vs 1 ray | RMSE vs {rays} rays | SSIM vs {rays} rays |\n\
         |---|---|---|---|---|---|\n",
        args.common.frames, args.common.warmup,
    );
    for r in rows {
        table.push_str(&format!(
            "| {} | {} | {:.4} | {:.4} | {:.4} | {:.4} |\n",
            r.filtering.name(),
            ms(r.resolve_ms),
            r.point.rmse,
            r.point.ssim,
            r.supersampled.rmse,
            r.supersampled.ssim
        ));
    }
    args.common.publish(
        &table,
        &format!("glTF map filtering on {adapter}: resolve ms at {tw}x{th} against RMSE"),
        "RMSE of the shaded floor",
        || {
            let point = |r: &Row, e: &metrics::Error| {
                (
                    r.resolve_ms.unwrap_or(0.0),
                    e.rmse,
                    r.filtering.name().to_owned(),
                )
            };
            Series::group(rows.iter().flat_map(|r| {
                [
                    (
                        format!("vs {rays} rays (aliasing)"),
                        point(r, &r.supersampled),
                    ),
                    ("vs 1 ray (point-sampled)".to_owned(), point(r, &r.point)),
                ]
            }))
        },
    )
}
