//! `spreadlight accuracy`: what accuracy costs. For an approximating
//! effect, every quality setting's GPU time at a large size against its
//! error, at a small size, versus a CPU reference of the same scene. Prints
//! a Markdown table (and JSON lines with `--json`); `--out` writes the table
//! to a file. Later effects add themselves as subcommands.
//!

mod ao;
mod geometry;
mod gltf;
mod lights;
pub(crate) mod metrics;
mod particles;
pub(crate) mod plot;
mod post;
mod probe;
mod reflection;
mod shadows;
mod transmission;

use std::path::PathBuf;

use anyhow::Context;
use std::process::ExitCode;

use crate::session::parse_size;

/// What every effect's measurement shares: where and how long GPU time is
/// taken, and where the table and plot go.
#[derive(clap::Args)]
pub struct Common {
    /// Where GPU time is measured.
    #[arg(long, default_value = "1920x1080", value_parser = parse_size)]
    pub time_size: (u32, u32),
    /// Frames run before timing each setting, back to back (pipelines compile, the GPU clocks up).
    #[arg(long, default_value_t = 10)]
    pub warmup: usize,
    /// Timed frames per setting; the median is reported.
    #[arg(long, default_value_t = 9)]
    pub frames: usize,
    /// Also write the table to this Markdown file.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Also plot GPU time against RMSE, a line per method, to this SVG file.
    #[arg(long)]
    pub plot: Option<PathBuf>,
    /// Print JSON lines instead of the table.
    #[arg(long)]
    pub json: bool,
}

impl Common {
    /// Every effect's table ends the same way: printed, plotted (GPU time
    /// against error, the series made only when `--plot` asks) and written
    /// to `--out`.
    pub(crate) fn publish(
        &self,
        table: &str,
        title: &str,
        y_label: &str,
        series: impl FnOnce() -> Vec<plot::Series>,
    ) -> anyhow::Result<ExitCode> {
        print!("{table}");
        if let Some(file) = &self.plot {
            plot::write_svg(file, title, y_label, &series())?;
        }
        if let Some(out) = &self.out {
            std::fs::write(out, table)
                .with_context(|| format!("cannot write {}", out.display()))?;
        }
        Ok(ExitCode::SUCCESS)
    }
}

/// Where an effect writes its images (`--images`): always a folder named
/// for the effect (`shadows/`, `ao/`) inside the one given, or inside
/// `accuracy-images/` (ignored by git) when none is given, so images of two
/// effects never mix and a stray value cannot scatter files at the root of
/// the tree, as `--images 1` once did (85 images committed in `1/`).
#[derive(clap::Args)]
pub struct ImageArgs {
    /// Write images into DIR/EFFECT/ (DIR: accuracy-images when left out).
    #[arg(long, value_name = "DIR", num_args = 0..=1, default_missing_value = IMAGES_DIR, alias = "error-images")]
    images: Option<PathBuf>,
}

/// Where `--images` without a folder writes (in .gitignore).
pub const IMAGES_DIR: &str = "accuracy-images";

impl ImageArgs {
    /// The folder `effect`'s images go into, when images are asked for.
    pub(crate) fn folder(&self, effect: &str) -> Option<PathBuf> {
        self.images.as_ref().map(|dir| dir.join(effect))
    }
}

/// Write `values` (row by row, `size`) as a grey PNG named `name` into
/// `dir`: a value as its grey level, `None` (a pixel the measurement leaves
/// out: the sky, what the light does not reach) dark blue.
pub(crate) fn write_grey(
    dir: &std::path::Path,
    name: &str,
    values: &[Option<f32>],
    size: (u32, u32),
) -> anyhow::Result<()> {
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    let image = spreadlight_render::readback::ImageF32 {
        width: size.0,
        height: size.1,
        pixels: values
            .iter()
            .map(|v| v.map_or([0.0, 0.0, 0.05, 1.0], |v| [v, v, v, 1.0]))
            .collect(),
    };
    let file = dir.join(format!("{}.png", name.replace(' ', "-")));
    spreadlight_render::image_io::write_image(
        &image,
        &file,
        spreadlight_render::image_io::Encoding::Linear,
    )
    .with_context(|| format!("cannot write {}", file.display()))
}

#[derive(clap::Args)]
pub struct Args {
    #[command(subcommand)]
    what: What,
}

#[derive(clap::Subcommand)]
enum What {
    /// Shadow filters (Raw, PCF, PCSS, VSM) by map resolution: GPU time against error versus ray-cast soft shadows.
    Shadows(shadows::ShadowArgs),
    /// Ambient occlusion (Stochastic, SAO, HBAO) by samples, temporal off and on: GPU time against error versus ray-cast AO.
    Ao(ao::AoArgs),
    /// Prefiltered environment (cube size x samples) and SSR (steps x rays, temporal off and on): GPU time against error versus ray-traced reflections.
    Reflection(reflection::ReflectionArgs),
    /// Environment probes by cube size x samples and by update interval: probe GPU ms against error versus a high-resolution probe and an every-frame probe.
    Probe(probe::ProbeArgs),
    /// Post effects (DOF, MotionBlur, TAA, FXAA) by quality: GPU time against error versus brute-force references.
    Post(post::PostArgs),
    /// Particle integrators (explicit Euler vs exponential) per time step: error against a small-step reference, GPU ms a step.
    Particles(particles::ParticleArgs),
    /// Tessellation (Subdivide, PN Triangles) by level: error against the analytic sphere and torus, GPU ms on a 100k-triangle mesh.
    Geometry(geometry::GeometryArgs),
    /// glTF material maps by filtering (point, bilinear, trilinear, anisotropic): GPU time against error versus a CPU reference, 1 and 16 rays per pixel.
    Gltf(gltf::GltfArgs),
    /// CookTorrance's Light Cutoff by light count: GPU time against error versus no cutoff (exact).
    Lights(lights::LightArgs),
    /// Lit transparency's screen-space refraction by depth-search steps (smooth glass) and blur taps (rough glass): GPU time against error versus a CPU ray trace through a slab.
    Transmission(transmission::TransmissionArgs),
}

pub fn run(args: &Args) -> anyhow::Result<ExitCode> {
    match &args.what {
        What::Shadows(a) => shadows::run(a),
        What::Ao(a) => ao::run(a),
        What::Reflection(a) => reflection::run(a),
        What::Probe(a) => probe::run(a),
        What::Post(a) => post::run_post(a),
        What::Particles(a) => particles::run_particles(a),
        What::Geometry(a) => geometry::run_geometry(a),
        What::Gltf(a) => gltf::run(a),
        What::Transmission(a) => transmission::run(a),
        What::Lights(a) => lights::run(a),
    }
}

/// The accuracy scenes' camera: from `eye` towards `target`, a 0.8 rad
/// vertical field of view at `size`'s aspect, near 0.1 and far 100.
pub(crate) fn camera_looking(
    eye: glam::Vec3,
    target: glam::Vec3,
    size: (u32, u32),
) -> spreadlight_render::camera::CameraInput {
    spreadlight_render::camera::CameraInput {
        view: glam::camera::rh::view::look_at_mat4(eye, target, glam::Vec3::Y),
        projection: glam::camera::rh::proj::directx::perspective(
            0.8,
            size.0 as f32 / size.1.max(1) as f32,
            0.1,
            100.0,
        ),
    }
}

/// The summed GPU time of `kind`'s passes (only those of `step`, when given):
/// matched by the report's fields, so "SAO" never counts an "SSAO" pass.
pub(crate) fn pass_ms(
    report: &spreadlight_render::FrameReport,
    kind: &str,
    step: Option<&str>,
) -> Option<f64> {
    let times: Vec<f64> = report
        .passes_of(kind, step)
        .filter_map(|p| p.gpu_ms)
        .collect();
    (!times.is_empty()).then(|| times.iter().sum())
}

pub(crate) fn median(mut v: Vec<f64>) -> Option<f64> {
    if v.is_empty() {
        return None;
    }
    v.sort_by(f64::total_cmp);
    Some(v[v.len() / 2])
}

/// A `--resolutions` value: Full, Half or Auto (any case; Auto resolves by the size measured).
pub(crate) fn parse_resolution(
    s: &str,
) -> Result<spreadlight_render::resolution::Resolution, String> {
    spreadlight_render::resolution::Resolution::parse(s)
        .ok_or_else(|| format!("`{s}` is not a resolution: full, half or auto"))
}

pub(crate) fn ms(v: Option<f64>) -> String {
    v.map_or("-".to_owned(), |v| format!("{v:.3}"))
}
