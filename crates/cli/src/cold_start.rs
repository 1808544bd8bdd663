//! A fresh process's cold start, by step: what an artist opening a patch
//! and a farm worker starting a chunk both pay before the first frame.
//! `spreadlight bench --json` reports it as `cold_start`, `spreadlight
//! render` in its `done` line (and on stderr with `--timings`).

use std::sync::OnceLock;
use std::time::Instant;

use serde_json::{Value, json};
use spreadlight_render::shaders::CompileTimes;

use crate::session::Session;

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
    pub registry: f64,
    pub gpu: f64,
    pub load: f64,
    /// The first frame's evaluation (every sub-frame), of which `compile` was
    /// making shaders and pipelines; the rest is uploads, recording and the GPU.
    pub first_frame: f64,
    pub compile: CompileTimes,
    pub pipelines: u64,
    /// The pipeline cache file and the bytes read from it (None: the device
    /// keeps none, pipeline_cache.rs).
    pub pipeline_cache: Option<(std::path::PathBuf, usize)>,
}

impl ColdStart {
    /// Measured now, just after the first frame, which took `first_frame` seconds.
    pub fn now(session: &Session, first_frame: f64) -> ColdStart {
        let (compile, pipelines) = session.renderer.as_ref().map_or_else(
            || (CompileTimes::default(), 0),
            |r| {
                let shaders = r.shaders();
                (shaders.compile_times, shaders.pipelines_compiled)
            },
        );
        let pipeline_cache = session
            .renderer
            .as_ref()
            .and_then(|r| r.gpu.disk_pipeline_cache())
            .map(|c| (c.path().to_path_buf(), c.loaded_bytes()));
        ColdStart {
            pipeline_cache,
            total: since_start(),
            registry: session.opened.registry,
            gpu: session.opened.gpu,
            load: session.opened.load,
            first_frame,
            compile,
            pipelines,
        }
    }

    /// In milliseconds (`cold_start` of `bench --json` and of `render`'s `done` line).
    pub fn json(&self) -> Value {
        let ms = |s: f64| (s * 1e6).round() / 1e3;
        let c = self.compile;
        let compiling = (c.compose + c.modules + c.pipelines).as_secs_f64();
        json!({
            "total_ms": ms(self.total),
            "registry_ms": ms(self.registry),
            "open_gpu_ms": ms(self.gpu),
            "load_patch_ms": ms(self.load),
            "first_frame_ms": ms(self.first_frame),
            "compose_ms": ms(c.compose.as_secs_f64()),
            "shader_modules_ms": ms(c.modules.as_secs_f64()),
            "pipelines_ms": ms(c.pipelines.as_secs_f64()),
            "first_frame_other_ms": ms((self.first_frame - compiling).max(0.0)),
            "pipelines_compiled": self.pipelines,
            "pipeline_cache": self.pipeline_cache.as_ref().map(|(path, bytes)| json!({
                "path": path.display().to_string(),
                "loaded_bytes": bytes,
            })),
        })
    }

    /// One line for people.
    pub fn line(&self) -> String {
        let c = self.compile;
        let ms = |s: f64| format!("{:.0} ms", s * 1e3);
        format!(
            "cold start {}: registry {}, GPU {}, patch {}, first frame {} (composing shaders {}, \
             shader modules {}, {} pipelines {})",
            ms(self.total),
            ms(self.registry),
            ms(self.gpu),
            ms(self.load),
            ms(self.first_frame),
            ms(c.compose.as_secs_f64()),
            ms(c.modules.as_secs_f64()),
            self.pipelines,
            ms(c.pipelines.as_secs_f64()),
        )
    }
}
