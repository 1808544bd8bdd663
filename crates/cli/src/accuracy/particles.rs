//! `spreadlight accuracy particles`: the particle integrators' error per
//! time step against a small-step reference, and their GPU cost.
//!
//! Every run starts from the same state: `--count` particles emitted in one
//! step of 1 µs (the same seed, so the same positions and velocities), then
//! stepped for `--seconds` under gravity, drag and a curl-noise field, with
//! no collisions or deaths. The reference is the
//! exponential integrator at `--reference-steps` steps a second (both schemes
//! converge to the same solution as the step shrinks). Error: RMS and
//! largest distance of the particles' positions from the reference's; cost:
//! GPU ms a step (timestamps, median).

use std::process::ExitCode;

use anyhow::Context;
use glam::Vec3;
use spreadlight_render::Renderer;
use spreadlight_render::geometry::GeometryStats;
use spreadlight_render::particles::{
    EmitterShape, Field, Integrator, Particle, ParticleSettings, ParticleSystem,
};

use super::{median, ms};

#[derive(clap::Args)]
pub struct ParticleArgs {
    /// Particles simulated.
    #[arg(long, default_value_t = 65_536)]
    count: u32,
    /// Simulated time, seconds.
    #[arg(long, default_value_t = 2.0)]
    seconds: f32,
    /// Steps a second of the runs compared, comma-separated.
    #[arg(long, default_value = "15,30,60,120,240", value_delimiter = ',')]
    rates: Vec<u32>,
    /// Steps a second of the reference.
    #[arg(long, default_value_t = 3840)]
    reference_steps: u32,
    /// Also write the table to this Markdown file.
    #[arg(long)]
    out: Option<std::path::PathBuf>,
    /// Print JSON lines instead of the table.
    #[arg(long)]
    json: bool,
}

const SEED: u32 = 17;

fn scene(integrator: Integrator) -> ParticleSettings {
    ParticleSettings {
        shape: EmitterShape::Sphere(0.5),
        rate: 0.0,
        lifetime: 1.0e6,
        lifetime_spread: 0.0,
        velocity: Vec3::new(0.0, 3.0, 0.0),
        velocity_spread: 2.0,
        gravity: Vec3::new(0.0, -9.81, 0.0),
        drag: 2.0,
        field: Field::Curl {
            frequency: 0.8,
            strength: 3.0,
        },
        // No attractor: close passes by its softened centre are chaotic, and
        // chaos, not the integrator, would then set the error.
        attractors: Vec::new(),
        world_radius: 1.0e4,
        integrator,
        ..Default::default()
    }
}

/// Positions after `seconds` at `rate` steps a second, and the GPU ms of each step.
fn run(
    renderer: &Renderer,
    args: &ParticleArgs,
    integrator: Integrator,
    rate: u32,
) -> anyhow::Result<(Vec<Particle>, Vec<f64>)> {
    let mut system = ParticleSystem::new(renderer, args.count, SEED)?;
    let settings = scene(integrator);
    // Everything born at once, in a step too short to move anything.
    let birth = ParticleSettings {
        rate: 1.0e12,
        ..settings.clone()
    };
    system.step(renderer, &birth, 1.0e-6)?;
    let stats = GeometryStats::of(renderer);
    stats.take_gpu_ms(&renderer.gpu)?;
    let steps = (args.seconds * rate as f32).round() as u32;
    let mut times = Vec::new();
    for _ in 0..steps {
        system.step(renderer, &settings, 1.0 / rate as f32)?;
        let ms = stats.take_gpu_ms(&renderer.gpu)?;
        // Without timestamps nothing is timed: no row claims 0 ms.
        if renderer.gpu.has_timestamps() {
            times.push(ms);
        }
    }
    Ok((system.read(renderer)?, times))
}

/// One compared run: its integrator and rate, its error against the reference, its GPU time.
struct Row {
    integrator: Integrator,
    rate: u32,
    rms: f64,
    max: f64,
    ms: Option<f64>,
}

fn integrator_name(integrator: Integrator) -> &'static str {
    match integrator {
        Integrator::ExplicitEuler => "explicit Euler",
        Integrator::Exponential => "exponential (exact drag)",
    }
}

pub fn run_particles(args: &ParticleArgs) -> anyhow::Result<ExitCode> {
    let renderer = Renderer::headless().context("cannot open a GPU")?;
    let stats = GeometryStats::of(&renderer);
    let adapter = renderer.gpu.adapter_name();
    eprintln!("reference: {} steps a second ...", args.reference_steps);
    // The reference is not timed: a timed step waits for its result, which
    // would only slow its thousands of steps.
    stats.set_timing(false);
    let (truth, _) = run(
        &renderer,
        args,
        Integrator::Exponential,
        args.reference_steps,
    )?;
    stats.set_timing(true);
    let mut rows = Vec::new();
    for integrator in [Integrator::ExplicitEuler, Integrator::Exponential] {
        for &rate in &args.rates {
            let (particles, times) = run(&renderer, args, integrator, rate.max(1))?;
            let distances: Vec<f64> = particles
                .iter()
                .zip(&truth)
                .map(|(p, t)| f64::from((Vec3::from(p.position) - Vec3::from(t.position)).length()))
                .collect();
            let n = distances.len().max(1) as f64;
            rows.push(Row {
                integrator,
                rate,
                rms: (distances.iter().map(|d| d * d).sum::<f64>() / n).sqrt(),
                max: distances.iter().copied().fold(0.0, f64::max),
                ms: median(times),
            });
        }
    }
    if args.json {
        for r in &rows {
            println!(
                "{}",
                serde_json::json!({
                    "effect": "particles", "integrator": integrator_name(r.integrator),
                    "steps_per_second": r.rate, "adapter": adapter, "count": args.count,
                    "seconds": args.seconds, "reference_steps": args.reference_steps,
                    "rms_error": r.rms, "max_error": r.max, "ms_per_step": r.ms,
                })
            );
        }
        return Ok(ExitCode::SUCCESS);
    }
    let mut table = format!(
        "Particle integration on {adapter}: {} particles for {} s under gravity, drag 2/s and curl noise; error against the exponential integrator at {} steps a second; GPU ms a step (median).\n\n\
         | integrator | steps/s | RMS error (m) | max error (m) | GPU ms/step |\n|---|---|---|---|---|\n",
        args.count, args.seconds, args.reference_steps
    );
    for r in &rows {
        table.push_str(&format!(
            "| {} | {} | {:.5} | {:.5} | {} |\n",
            integrator_name(r.integrator),
            r.rate,
            r.rms,
            r.max,
            ms(r.ms)
        ));
    }
    print!("{table}");
    if let Some(file) = &args.out {
        std::fs::write(file, &table).with_context(|| format!("writing {}", file.display()))?;
    }
    Ok(ExitCode::SUCCESS)
}
