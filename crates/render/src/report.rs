//! What a frame did: the frame graph's statistics, kept by the renderer as
//! its last report and read by the CLI (`stats`, `bench`), the editor and tests.

use std::collections::BTreeMap;

/// One executed pass in the frame report.
#[derive(Clone, Debug, serde::Serialize)]
pub struct PassReport {
    pub name: String,
    pub owner: Option<u32>,
    /// Another node whose pass the frame graph ran inside this one
    /// (frame_graph/merge.rs: Fog and a Sky over it): the pass is both
    /// nodes' work, and its errors are reported to each.
    pub partner: Option<u32>,
    /// GPU time from timestamp queries, when the adapter has them.
    pub gpu_ms: Option<f64>,
    /// GPU time idle before this pass: from the end of the previous timed
    /// pass to this one's start, plus any gaps between its own timed parts.
    /// Over a frame these add up to the span minus the passes' sum. Between
    /// passes that share a compute pass (frame_graph/compute_pass.rs) the
    /// barriers a dispatch needs fall after its pass's first timestamp, so
    /// they count in `gpu_ms`, not here; a boundary that costs more than
    /// others shows here where a compute pass ends (a render pass, a copy).
    pub idle_ms: Option<f64>,
    pub draws: u64,
}

/// What a frame did: the frame graph's statistics.
#[derive(Clone, Debug, Default, serde::Serialize)]
pub struct FrameReport {
    pub adapter: String,
    pub passes: Vec<PassReport>,
    pub culled: Vec<String>,
    pub pipelines_compiled: u64,
    pub draws: u64,
    pub textures_created: u64,
    /// Errors of passes that failed (validation or their own); those passes' work was dropped.
    pub errors: Vec<(Option<u32>, String)>,
    /// Sum of the passes' GPU times.
    pub gpu_ms: Option<f64>,
    /// GPU time from the first pass's start to the last pass's end.
    pub gpu_frame_ms: Option<f64>,
    /// CPU time spent recording and submitting the frame.
    pub record_ms: f64,
    /// Time spent waiting for the GPU to finish (to read the timestamps).
    pub wait_ms: f64,
    /// Decisions passes counted (`PassContext::count`), e.g. "shadow maps reused".
    pub counters: BTreeMap<String, u64>,
}

impl FrameReport {
    /// A counter's value; 0 when no pass counted it.
    pub fn counter(&self, name: &str) -> u64 {
        self.counters.get(name).copied().unwrap_or(0)
    }
}
