//! What a frame did: the frame graph's statistics, kept by the renderer as
//! its last report and read by the CLI (`stats`, `bench`), the editor and tests.

use std::borrow::Cow;
use std::collections::BTreeMap;

/// What a pass is, as fields: the effect it belongs to (`kind`, the node
/// type: "SSAO", "CookTorrance") and, for an effect of several passes, which
/// `step` ("blur x", "shade"). Reports, `stats`, `bench` and the accuracy
/// commands match on these fields, never on the text: "SAO" is not a
/// substring match away from "SSAO".
#[derive(Clone, Debug, PartialEq, Eq, Hash, serde::Serialize)]
pub struct PassName {
    pub kind: Cow<'static, str>,
    pub step: Option<Cow<'static, str>>,
}

impl PassName {
    pub fn new(kind: impl Into<Cow<'static, str>>) -> Self {
        PassName {
            kind: kind.into(),
            step: None,
        }
    }

    /// One step of an effect of several passes.
    pub fn step(mut self, step: impl Into<Cow<'static, str>>) -> Self {
        self.step = Some(step.into());
        self
    }

    /// Whether this is `kind`'s pass named `step` (any step when `None`).
    pub fn is(&self, kind: &str, step: Option<&str>) -> bool {
        is_pass(&self.kind, self.step.as_deref(), kind, step)
    }

    /// The pass's name in reports and captures: the kind, the node id when
    /// there is one ("Tonemap #12") and the step ("SSAO #4: blur x"). Built
    /// into one allocation: re-made recipes name their passes every frame.
    pub fn text(&self, owner: Option<u32>) -> String {
        use std::fmt::Write;
        let step = self.step.as_deref();
        let mut name =
            String::with_capacity(self.kind.len() + 12 + step.map_or(0, |w| w.len() + 2));
        name.push_str(&self.kind);
        if let Some(id) = owner {
            let _ = write!(name, " #{id}");
        }
        if let Some(step) = step {
            name.push_str(": ");
            name.push_str(step);
        }
        name
    }
}

/// Whether a pass of `(has_kind, has_step)` is `kind`'s pass `step` (any
/// step when `None`): the one match [`PassName`] and [`PassReport`] share.
fn is_pass(has_kind: &str, has_step: Option<&str>, kind: &str, step: Option<&str>) -> bool {
    has_kind == kind && step.is_none_or(|s| has_step == Some(s))
}

impl From<&'static str> for PassName {
    fn from(kind: &'static str) -> Self {
        PassName::new(kind)
    }
}

/// One executed pass in the frame report.
#[derive(Clone, Debug, serde::Serialize)]
pub struct PassReport {
    /// For people: [`PassName::text`] with the owner.
    pub name: String,
    /// The effect: the node type that declared the pass ([`PassName::kind`]).
    pub kind: Cow<'static, str>,
    /// Which pass of the effect, for an effect of several ([`PassName::step`]).
    pub step: Option<Cow<'static, str>>,
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
    /// CPU time recording this pass: its textures taken from the pool, its
    /// `run` (pipelines, bind groups, uniform writes, commands) and the
    /// graph's bookkeeping after it. What issue 33's "CPU per pass" is
    /// about, per pass rather than as the frame's sum.
    pub cpu_ms: f64,
    /// Heap allocations the recording thread made for this pass (the same
    /// span as `cpu_ms`), when the host counts them (allocation_count.rs).
    pub allocations: Option<u64>,
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
    /// Of `record_ms`, the part after the last pass recorded: finishing the
    /// command encoders (waiting for the finisher thread), resolving the
    /// timestamps and the submission to the queue.
    pub submit_ms: f64,
    /// Of `submit_ms`, the queue's `submit` alone (wgpu's tracking and the
    /// driver's submission).
    pub queue_submit_ms: f64,
    /// Time spent waiting for the GPU to finish (to read the timestamps).
    /// With a submission thread, a timed frame's wait for its own
    /// submission is part of it.
    pub wait_ms: f64,
    /// With a submission thread (`SPREADLIGHT_SUBMIT=thread`,
    /// frame_graph/submitter.rs): the time the recording thread waited for
    /// the frame before's submission since that frame returned (the next
    /// frame's first use of the queue waits for it, frame_queue.rs). Not
    /// CPU work; part of the critical path when it is not zero.
    pub submission_wait_ms: f64,
    /// With a submission thread: the CPU time it spent on a frame
    /// (collecting and finishing the encoders, the queue's submit). This
    /// frame's where the frame waited for its own submission (its
    /// timestamps are read back), else the frame before's, which this
    /// frame's first use of the queue waited for. None when submitted inline.
    pub submission_thread_ms: Option<f64>,
    /// Heap allocations the recording thread made before the first pass
    /// (culling, the frame's maps) and after the last one (finishing the
    /// encoders, the submission, the textures handed back: the tail), when
    /// the host counts them (allocation_count.rs).
    pub allocations_before_passes: Option<u64>,
    pub allocations_after_passes: Option<u64>,
    /// Decisions passes counted (`PassContext::count`), e.g. "shadow maps
    /// reused". Names are the passes' own `'static` ones, borrowed: a frame
    /// allocated a String for every counter it reported.
    pub counters: BTreeMap<Cow<'static, str>, u64>,
}

impl PassReport {
    /// Whether this is `kind`'s pass named `step` (any step when `None`).
    pub fn is(&self, kind: &str, step: Option<&str>) -> bool {
        is_pass(&self.kind, self.step.as_deref(), kind, step)
    }
}

impl FrameReport {
    /// The passes of `kind` (of step `step`, when given).
    pub fn passes_of<'r>(
        &'r self,
        kind: &'r str,
        step: Option<&'r str>,
    ) -> impl Iterator<Item = &'r PassReport> + 'r {
        self.passes.iter().filter(move |p| p.is(kind, step))
    }

    /// A counter's value; 0 when no pass counted it.
    pub fn counter(&self, name: &str) -> u64 {
        self.counters.get(name).copied().unwrap_or(0)
    }

    /// Become a copy of `from`, in the storage this report already has: the
    /// renderer keeps each frame's report, and cloning it (a String a pass
    /// and a map of counters) was a tenth of a frame's allocations.
    pub(crate) fn copy_from(&mut self, from: &FrameReport) {
        self.adapter.clone_from(&from.adapter);
        self.passes.truncate(from.passes.len());
        let kept = self.passes.len();
        for (into, pass) in self.passes.iter_mut().zip(&from.passes) {
            into.name.clone_from(&pass.name);
            into.kind.clone_from(&pass.kind);
            into.step.clone_from(&pass.step);
            into.owner = pass.owner;
            into.partner = pass.partner;
            into.gpu_ms = pass.gpu_ms;
            into.idle_ms = pass.idle_ms;
            into.draws = pass.draws;
            into.cpu_ms = pass.cpu_ms;
            into.allocations = pass.allocations;
        }
        self.passes.extend(from.passes[kept..].iter().cloned());
        self.culled.clone_from(&from.culled);
        self.errors.clone_from(&from.errors);
        // The same counters as last frame (the usual case): values only.
        if self.counters.len() == from.counters.len()
            && self.counters.keys().eq(from.counters.keys())
        {
            for (into, n) in self.counters.values_mut().zip(from.counters.values()) {
                *into = *n;
            }
        } else {
            self.counters.clone_from(&from.counters);
        }
        let FrameReport {
            adapter: _,
            passes: _,
            culled: _,
            errors: _,
            counters: _,
            pipelines_compiled,
            draws,
            textures_created,
            gpu_ms,
            gpu_frame_ms,
            record_ms,
            submit_ms,
            queue_submit_ms,
            wait_ms,
            submission_wait_ms,
            submission_thread_ms,
            allocations_before_passes,
            allocations_after_passes,
        } = from;
        self.pipelines_compiled = *pipelines_compiled;
        self.draws = *draws;
        self.textures_created = *textures_created;
        self.gpu_ms = *gpu_ms;
        self.gpu_frame_ms = *gpu_frame_ms;
        self.record_ms = *record_ms;
        self.submit_ms = *submit_ms;
        self.queue_submit_ms = *queue_submit_ms;
        self.wait_ms = *wait_ms;
        self.submission_wait_ms = *submission_wait_ms;
        self.submission_thread_ms = *submission_thread_ms;
        self.allocations_before_passes = *allocations_before_passes;
        self.allocations_after_passes = *allocations_after_passes;
    }
}

#[cfg(test)]
mod tests {
    use super::PassName;

    #[test]
    fn a_pass_is_named_by_its_node_and_what_it_does() {
        assert_eq!(PassName::new("Tonemap").text(Some(12)), "Tonemap #12");
        assert_eq!(
            PassName::new("SSAO").step("raw").text(Some(52)),
            "SSAO #52: raw"
        );
        assert_eq!(PassName::new("Sky").text(None), "Sky");
        assert_eq!(PassName::new("Sky").step("fog").text(None), "Sky: fog");
    }

    #[test]
    fn a_pass_is_matched_by_its_fields_not_its_text() {
        let sao = PassName::new("SAO").step("raw");
        assert!(sao.is("SAO", None) && sao.is("SAO", Some("raw")));
        assert!(!sao.is("SSAO", None), "SAO is not SSAO");
        assert!(!PassName::new("SSAO").is("SAO", None), "SSAO is not SAO");
        assert!(!sao.is("SAO", Some("blur x")));
    }
}

/// The timings of every frame graph executed since they were last taken
/// ([`crate::Renderer::take_graph_timings`]): a patch with several Outputs
/// executes a graph for each in one frame, and a host timing the frame
/// needs all of them, not the last one's ([`FrameReport`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct GraphTimings {
    /// Frame graphs executed.
    pub graphs: u32,
    /// The sums of their [`FrameReport`] fields of the same names; a time
    /// that is None in every report stays None.
    pub record_ms: f64,
    pub submit_ms: f64,
    pub queue_submit_ms: f64,
    pub wait_ms: f64,
    pub submission_wait_ms: f64,
    pub submission_thread_ms: Option<f64>,
    pub gpu_ms: Option<f64>,
    pub gpu_frame_ms: Option<f64>,
}

impl GraphTimings {
    /// Adds one executed graph's report.
    pub fn add(&mut self, report: &FrameReport) {
        fn plus(sum: Option<f64>, value: Option<f64>) -> Option<f64> {
            match (sum, value) {
                (None, None) => None,
                (a, b) => Some(a.unwrap_or(0.0) + b.unwrap_or(0.0)),
            }
        }
        // A host that never takes them (the editor) keeps adding for hours.
        self.graphs = self.graphs.saturating_add(1);
        self.record_ms += report.record_ms;
        self.submit_ms += report.submit_ms;
        self.queue_submit_ms += report.queue_submit_ms;
        self.wait_ms += report.wait_ms;
        self.submission_wait_ms += report.submission_wait_ms;
        self.submission_thread_ms = plus(self.submission_thread_ms, report.submission_thread_ms);
        self.gpu_ms = plus(self.gpu_ms, report.gpu_ms);
        self.gpu_frame_ms = plus(self.gpu_frame_ms, report.gpu_frame_ms);
    }
}

#[cfg(test)]
mod graph_timings_tests {
    use super::*;

    #[test]
    fn the_timings_of_several_graphs_add_up() {
        let report = |record_ms, wait_ms, gpu_frame_ms| FrameReport {
            record_ms,
            wait_ms,
            gpu_frame_ms,
            ..FrameReport::default()
        };
        let mut timings = GraphTimings::default();
        timings.add(&report(0.25, 1.0, Some(0.5)));
        timings.add(&report(0.5, 2.0, None));
        timings.add(&report(0.125, 0.5, Some(0.25)));
        assert_eq!(timings.graphs, 3);
        assert_eq!(timings.record_ms, 0.875);
        assert_eq!(timings.wait_ms, 3.5);
        assert_eq!(timings.gpu_frame_ms, Some(0.75));
        assert_eq!(timings.gpu_ms, None, "untimed everywhere: none");
    }
}
