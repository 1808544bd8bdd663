//! `spreadlight accuracy geometry`: what tessellation costs against how far
//! it stays from the surface it approximates. Per level, `Subdivide` (flat)
//! and `PN Triangles` (curved) of a unit icosahedron against the unit sphere
//! and of a coarse torus against the analytic torus: largest and RMS
//! distance over the output's vertices and triangle centroids. Cost: GPU ms
//! of the pass on a sphere of about `--time-triangles` triangles (median of
//! `--frames` runs after `--warmup`), and the triangles it makes.
//!
//! Adaptive `Tessellate` is flat, so on its own it never leaves the
//! icosahedron; its rows measure it followed by `Spherize` at 1 (every vertex
//! onto the sphere): the distance left is then the flat triangles' sag,
//! which Max Area bounds. Max Area is given as the input's mean triangle
//! area over a factor, so the icosahedron and the timing sphere are cut
//! alike.

use std::process::ExitCode;

use anyhow::Context;
use glam::Vec3;
use spreadlight_render::Renderer;
use spreadlight_render::geometry::analytic::{icosahedron, sphere_distance, torus_distance};
use spreadlight_render::geometry::{
    GeometryStats, SpherizeParams, pn_triangles, read_mesh, spherize, tessellate,
};
use spreadlight_render::mesh::MeshData;
use spreadlight_render::mesh::primitives::{SphereParams, TorusParams, sphere, torus};

use super::{median, ms};

#[derive(clap::Args)]
pub struct GeometryArgs {
    /// Levels (segments an edge), comma-separated.
    #[arg(long, default_value = "1,2,3,4,8,16", value_delimiter = ',')]
    levels: Vec<u32>,
    /// Triangles of the sphere the GPU time is taken on.
    #[arg(long, default_value_t = 100_000)]
    time_triangles: u32,
    #[arg(long, default_value_t = 5)]
    warmup: usize,
    #[arg(long, default_value_t = 9)]
    frames: usize,
    /// Adaptive Tessellate: Max Area = the mean triangle area over each of these.
    #[arg(long, default_value = "2,4,8,16,32", value_delimiter = ',')]
    area_factors: Vec<u32>,
    /// Also write the table to this Markdown file.
    #[arg(long)]
    out: Option<std::path::PathBuf>,
    /// Print JSON lines instead of the table.
    #[arg(long)]
    json: bool,
}

const MAJOR: f32 = 1.0;
const MINOR: f32 = 0.35;

/// Largest and RMS of `distance` over the vertices and triangle centroids of `out`.
fn spread(
    renderer: &Renderer,
    out: &spreadlight_render::mesh_arena::GpuMesh,
    distance: impl Fn(Vec3) -> f32,
) -> anyhow::Result<(f32, f32)> {
    let (vertices, indices) = read_mesh(renderer, out)?;
    let p = |k: u32| Vec3::from_slice(&vertices[k as usize].position_u);
    let samples: Vec<f32> = indices
        .chunks(3)
        .map(|t| (p(t[0]) + p(t[1]) + p(t[2])) / 3.0)
        .chain(vertices.iter().map(|v| Vec3::from_slice(&v.position_u)))
        .map(distance)
        .collect();
    let max = samples.iter().copied().fold(0.0f32, f32::max);
    let rms = (samples.iter().map(|d| d * d).sum::<f32>() / samples.len().max(1) as f32).sqrt();
    Ok((max, rms))
}

/// The mean triangle area of `mesh`.
fn mean_area(mesh: &MeshData) -> f32 {
    let p = |k: u32| Vec3::from(mesh.positions[k as usize]);
    let total: f32 = mesh
        .indices
        .chunks(3)
        .map(|t| 0.5 * (p(t[1]) - p(t[0])).cross(p(t[2]) - p(t[0])).length())
        .sum();
    total / mesh.triangle_count().max(1) as f32
}

/// (max, RMS) distance of a tessellation of `mesh` from the surface `distance` measures.
fn error(
    renderer: &Renderer,
    mesh: &MeshData,
    level: u32,
    curved: bool,
    distance: impl Fn(Vec3) -> f32,
) -> anyhow::Result<(f32, f32)> {
    let input = renderer.meshes.upload(&renderer.gpu, mesh)?;
    let out = pn_triangles(renderer, &input, None, level, curved)?;
    spread(renderer, &out, distance)
}

/// One measured setting: a uniform level, or adaptive at an area factor
/// (measured on the sphere alone).
struct Row {
    method: &'static str,
    setting: Setting,
    sphere: (f32, f32),
    torus: Option<(f32, f32)>,
    triangles: usize,
    ms: Option<f64>,
}

#[derive(Clone, Copy)]
enum Setting {
    Level(u32),
    AreaFactor(f32),
}

/// The median GPU ms of `make` over `frames` runs after `warmup` (None
/// without timestamps), and the triangles its last run made.
fn time(
    renderer: &Renderer,
    (warmup, frames): (usize, usize),
    mut make: impl FnMut() -> anyhow::Result<std::sync::Arc<spreadlight_render::mesh_arena::GpuMesh>>,
) -> anyhow::Result<(Option<f64>, usize)> {
    let stats = GeometryStats::of(renderer);
    let mut times = Vec::new();
    let mut made = 0;
    for k in 0..warmup + frames.max(1) {
        stats.take_gpu_ms(&renderer.gpu)?;
        made = make()?.indices.len() / 3;
        let ms = stats.take_gpu_ms(&renderer.gpu)?;
        if k >= warmup && renderer.gpu.has_timestamps() {
            times.push(ms);
        }
    }
    Ok((median(times), made))
}

pub fn run_geometry(args: &GeometryArgs) -> anyhow::Result<ExitCode> {
    let renderer = Renderer::headless().context("cannot open a GPU")?;
    let adapter = renderer.gpu.adapter_name();
    GeometryStats::of(&renderer).set_timing(true);
    let runs = (args.warmup, args.frames);
    // A UV sphere has 2 x sectors x (stacks - 1) triangles; sectors = 2 x stacks.
    let stacks = ((f64::from(args.time_triangles) / 4.0).sqrt().ceil() as u32).max(3);
    let big = sphere(SphereParams {
        radius: 1.0,
        sectors: stacks * 2,
        stacks,
    });
    let big_input = renderer.meshes.upload(&renderer.gpu, &big)?;
    let ring = torus(TorusParams {
        major_radius: MAJOR,
        minor_radius: MINOR,
        major_segments: 16,
        minor_segments: 8,
    });
    let ico = icosahedron();
    let mut rows = Vec::new();
    for (method, curved) in [("Subdivide (flat)", false), ("PN Triangles", true)] {
        for &level in &args.levels {
            let sphere = error(&renderer, &ico, level, curved, sphere_distance)?;
            let torus = error(&renderer, &ring, level, curved, |p| {
                torus_distance(p, MAJOR, MINOR)
            })?;
            let (ms, triangles) = time(&renderer, runs, || {
                Ok(pn_triangles(&renderer, &big_input, None, level, curved)?)
            })?;
            rows.push(Row {
                method,
                setting: Setting::Level(level),
                sphere,
                torus: Some(torus),
                triangles,
                ms,
            });
        }
    }
    let onto_sphere = SpherizeParams {
        center: Vec3::ZERO,
        radius: 1.0,
        amount: 1.0,
    };
    let ico_input = renderer.meshes.upload(&renderer.gpu, &ico)?;
    for &factor in &args.area_factors {
        let factor = factor.max(1) as f32;
        let fine = tessellate(&renderer, &ico_input, None, mean_area(&ico) / factor, 64)?;
        let round = spherize(&renderer, &fine, None, onto_sphere)?;
        let sphere = spread(&renderer, &round, sphere_distance)?;
        let (ms, triangles) = time(&renderer, runs, || {
            Ok(tessellate(
                &renderer,
                &big_input,
                None,
                mean_area(&big) / factor,
                64,
            )?)
        })?;
        rows.push(Row {
            method: "Tessellate (adaptive) + Spherize",
            setting: Setting::AreaFactor(factor),
            sphere,
            torus: None,
            triangles,
            ms,
        });
    }
    if args.json {
        for r in &rows {
            let (level, area_factor) = match r.setting {
                Setting::Level(l) => (Some(l), None),
                Setting::AreaFactor(f) => (None, Some(f)),
            };
            println!(
                "{}",
                serde_json::json!({
                    "effect": "geometry", "method": r.method, "level": level,
                    "area_factor": area_factor, "adapter": adapter,
                    "time_triangles": big.triangle_count(),
                    "sphere_max": r.sphere.0, "sphere_rms": r.sphere.1,
                    "torus_max": r.torus.map(|t| t.0), "torus_rms": r.torus.map(|t| t.1),
                    "triangles": r.triangles, "ms": r.ms,
                })
            );
        }
        return Ok(ExitCode::SUCCESS);
    }
    let mut table = format!(
        "Tessellation on {adapter}: error (largest and RMS distance over vertices and triangle centroids) of a unit \
         icosahedron against the unit sphere and of a 16x8 torus (R {MAJOR}, r {MINOR}) against the analytic \
         torus; GPU ms of the pass on a {}-triangle sphere (median of {} after {}).\n\n\
         | method | level | sphere max | sphere RMS | torus max | torus RMS | triangles out | GPU ms |\n\
         |---|---|---|---|---|---|---|---|\n",
        big.triangle_count(),
        args.frames,
        args.warmup
    );
    for r in &rows {
        let (smax, srms) = r.sphere;
        let setting = match r.setting {
            Setting::Level(l) => l.to_string(),
            Setting::AreaFactor(f) => format!("mean area / {f}"),
        };
        let torus = match r.torus {
            Some((tmax, trms)) => format!("{tmax:.5} | {trms:.5}"),
            None => "- | -".to_owned(),
        };
        table.push_str(&format!(
            "| {} | {setting} | {smax:.5} | {srms:.5} | {torus} | {} | {} |\n",
            r.method,
            r.triangles,
            ms(r.ms)
        ));
    }
    print!("{table}");
    if let Some(file) = &args.out {
        std::fs::write(file, &table).with_context(|| format!("writing {}", file.display()))?;
    }
    Ok(ExitCode::SUCCESS)
}
