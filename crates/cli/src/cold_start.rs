//! A fresh process's cold start, by step: what an artist opening a patch
//! and a farm worker starting a chunk both pay before the first frame.
//! `spreadlight bench --json` reports it as `cold_start`, `spreadlight
//! render` in its `done` line (and on stderr with `--timings`).

use std::sync::OnceLock;
use std::time::Instant;

use serde_json::{Value, json};
use spreadlight_render::context::OpenTimes;
use spreadlight_render::pipelines_ahead::AheadStats;
use spreadlight_render::shaders::CompileTimes;

use crate::session::{Opened, Session};

static PROCESS_STARTED: OnceLock<Instant> = OnceLock::new();

/// Note when the process started (the first thing `main` does).
pub fn mark_process_start() {
    PROCESS_STARTED.get_or_init(Instant::now);
}

/// Seconds since [`mark_process_start`].
fn since_start() -> f64 {
    PROCESS_STARTED
        .get()
        .map_or(0.0, |started| started.elapsed().as_secs_f64())
}

/// Where a process's time went up to the end of its first frame.
#[derive(Clone, Debug)]
pub struct ColdStart {
    /// Process start to the end of the first frame's evaluation.
    pub total: f64,
    /// Opening the session, by step.
    pub opened: Opened,
    /// Of `opened.gpu`: the driver's steps (the rest is the renderer's setup).
    pub open_times: OpenTimes,
    /// The first frame's evaluation (every sub-frame), of which `compile` was
    /// making shaders and pipelines; the rest is uploads, recording and the GPU.
    pub first_frame: f64,
    pub compile: CompileTimes,
    /// Pipelines the first frame needed, and of them those it made itself
    /// (the rest were made on threads ahead of it).
    pub pipelines: u64,
    pub pipelines_at_frame: u64,
    /// Those it made itself, by label (permutation and entry point, or a
    /// render pipeline's variant): what no list or announcement covered.
    pub made_at_frame: Vec<String>,
    /// The pipeline cache file, the bytes read from it and the driver's
    /// bytes once made from them (None: the device keeps none, pipeline_cache.rs).
    pub pipeline_cache: Option<(std::path::PathBuf, usize, usize)>,
    /// What creating the last run's pipelines ahead did (None: no list, or
    /// `SPREADLIGHT_PIPELINES_AHEAD=off`).
    pub ahead: Option<AheadStats>,
    /// What the threads making the pipelines frames announced did (None:
    /// none announced one the cache lacked: `frame_graph/gather.rs`).
    pub gathered: Option<AheadStats>,
}

impl ColdStart {
    /// Measured now, just after the first frame, which took `first_frame` seconds.
    pub fn now(session: &Session, first_frame: f64) -> ColdStart {
        let (compile, pipelines, at_frame, ahead, gathered, made_at_frame) =
            session.renderer.as_ref().map_or_else(
                || (CompileTimes::default(), 0, 0, None, None, Vec::new()),
                |r| {
                    let shaders = r.shaders();
                    (
                        shaders.compile_times,
                        shaders.pipelines_compiled,
                        shaders.pipelines_compiled - shaders.pipelines_taken_ahead,
                        shaders.pipelines_ahead(),
                        shaders.pipelines_gathered(),
                        shaders.made_here.clone(),
                    )
                },
            );
        let pipeline_cache = session
            .renderer
            .as_ref()
            .and_then(|r| r.gpu.disk_pipeline_cache())
            .map(|c| (c.path().to_path_buf(), c.loaded_bytes(), c.accepted_bytes()));
        ColdStart {
            pipeline_cache,
            total: since_start(),
            opened: session.opened,
            open_times: session
                .renderer
                .as_ref()
                .map_or_else(OpenTimes::default, |r| r.gpu.open_times),
            first_frame,
            compile,
            pipelines,
            pipelines_at_frame: at_frame,
            made_at_frame,
            ahead,
            gathered,
        }
    }

    /// In milliseconds (`cold_start` of `bench --json` and of `render`'s `done` line).
    pub fn json(&self) -> Value {
        let ms = |s: f64| (s * 1e6).round() / 1e3;
        let c = self.compile;
        let (opened, gpu) = (&self.opened, &self.open_times);
        let compiling = (c.compose + c.libraries + c.modules + c.pipelines).as_secs_f64();
        let driver = (gpu.adapter + gpu.device + gpu.pipeline_cache).as_secs_f64();
        // The start's own time: where the GPU opened on a thread, only the wait for it.
        let steps = opened.registry + opened.network + opened.gpu_waited + opened.load;
        let precompose = opened.precompose.map(|p| {
            json!({
                "listed": p.listed,
                "composed": p.composed,
                "threads": p.threads,
                "wall_ms": ms(p.wall.as_secs_f64()),
                "waited_ms": ms(p.waited.as_secs_f64()),
            })
        });
        // Pipelines made on threads, from the last run's list (`ahead`) or
        // announced by the first frame's passes (`gathered`): `created` by
        // them, of which the frame `taken` ready or `waited` for; those the
        // frame asked for before a thread began them it made itself
        // (`claimed`, counted in `pipelines_at_frame`).
        let counts = |a: AheadStats| {
            json!({
                "listed": a.listed,
                "threads": a.threads,
                "created": a.created,
                "failed": a.failed,
                "taken": a.taken,
                "waited": a.waited,
                "waited_ms": ms(a.wait.as_secs_f64()),
                "claimed": a.claimed,
                "busy_ms": ms(a.busy.as_secs_f64()),
                "modules_ms": ms(a.modules.as_secs_f64()),
                "longest_ms": ms(a.longest.as_secs_f64()),
                "wall_ms": (a.wall > std::time::Duration::ZERO).then(|| ms(a.wall.as_secs_f64())),
            })
        };
        json!({
            "total_ms": ms(self.total),
            "registry_ms": ms(opened.registry),
            "registry_nodes_ms": ms(opened.registry_nodes),
            "shader_folders_ms": ms(opened.registry - opened.registry_nodes),
            "network_ms": ms(opened.network),
            "open_gpu_ms": ms(opened.gpu),
            "gpu_waited_ms": ms(opened.gpu_waited),
            "gpu_adapter_ms": ms(gpu.adapter.as_secs_f64()),
            "gpu_device_ms": ms(gpu.device.as_secs_f64()),
            "gpu_pipeline_cache_ms": ms(gpu.pipeline_cache.as_secs_f64()),
            "renderer_setup_ms": ms((opened.gpu - driver).max(0.0)),
            "load_patch_ms": ms(opened.load),
            "precompose": precompose,
            "before_first_frame_ms": ms((self.total - self.first_frame - steps).max(0.0)),
            "first_frame_ms": ms(self.first_frame),
            "compose_ms": ms(c.compose.as_secs_f64()),
            "shader_libraries_ms": ms(c.libraries.as_secs_f64()),
            "permutations_composed": c.composed,
            "permutations_ready": c.ready,
            "shader_modules_ms": ms(c.modules.as_secs_f64()),
            "pipelines_ms": ms(c.pipelines.as_secs_f64()),
            "first_frame_other_ms": ms((self.first_frame - compiling).max(0.0)),
            "pipelines_compiled": self.pipelines,
            "pipelines_at_frame": self.pipelines_at_frame,
            "made_at_frame": self.made_at_frame,
            "pipelines_ahead": self.ahead.map(counts),
            "pipelines_gathered": self.gathered.map(counts),
            "pipeline_cache": self.pipeline_cache.as_ref().map(|(path, bytes, accepted)| json!({
                "path": path.display().to_string(),
                "loaded_bytes": bytes,
                "accepted_bytes": accepted,
                "driver_disk_cache_off": spreadlight_render::pipeline_cache::driver_disk_cache_turned_off(),
            })),
        })
    }

    /// One line for people.
    pub fn line(&self) -> String {
        let c = self.compile;
        let ms = |s: f64| format!("{:.0} ms", s * 1e3);
        let ahead = self.opened.precompose.map_or(String::new(), |p| {
            format!(
                "; {} of {} permutations composed ahead on {} thread{}, waited {}",
                p.composed,
                p.listed,
                p.threads,
                if p.threads == 1 { "" } else { "s" },
                ms(p.waited.as_secs_f64())
            )
        });
        let threads = |n: usize| format!("{n} thread{}", if n == 1 { "" } else { "s" });
        let pipelines_ahead = self.ahead.map_or(String::new(), |a| {
            format!(
                "; {} of {} pipelines created ahead on {} ({} ready, {} waited for {})",
                a.created,
                a.listed,
                threads(a.threads),
                a.taken,
                a.waited,
                ms(a.wait.as_secs_f64())
            )
        });
        let gathered = self.gathered.map_or(String::new(), |a| {
            format!(
                "; {} of {} pipelines the frame announced created on {}",
                a.created,
                a.listed,
                threads(a.threads)
            )
        });
        format!(
            "cold start {}: registry {}, GPU {} (adapter {}, device {}), patch {}, first frame {} \
             (composing shaders {}, shader modules {}, {} pipelines made in it {}){ahead}{pipelines_ahead}{gathered}",
            ms(self.total),
            ms(self.opened.registry),
            ms(self.opened.gpu),
            ms(self.open_times.adapter.as_secs_f64()),
            ms(self.open_times.device.as_secs_f64()),
            ms(self.opened.load),
            ms(self.first_frame),
            ms(c.compose.as_secs_f64()),
            ms(c.modules.as_secs_f64()),
            self.pipelines_at_frame,
            ms(c.pipelines.as_secs_f64()),
        )
    }
}
