//! The compute pipelines a frame's passes will dispatch, announced where the
//! passes are declared ([`FrameGraph::will_dispatch`]), so that a frame
//! whose pipelines are not made yet creates them on threads while it
//! records: the first frame of a first run, which has no list of the last
//! run's pipelines to create ahead (`crate::shaders::pipelines_ahead`).
//!
//! Without it each pipeline was made where its pass recorded, one after
//! another (the driver compiling each: 2.3 s for post.ron's 31 on the H200
//! host with its shader cache empty). With it the executor hands the
//! announced pipelines the shader cache lacks to threads before the first
//! pass records, and a pass's look-up takes the one made, waits for one in
//! the making, or makes one no thread began yet itself
//! (`ShaderCache::make_ahead`). A pass that announces nothing is recorded
//! as before; an announced pipeline a culled pass would have used is made
//! and not used. Nothing a pass records changes: the pipelines are those the
//! look-up would have made.
//!
//! A recipe whose passes may be culled or merged (the G-buffer's surface
//! and motion resolves, run as one when the frame reads both) announces a
//! pipeline for the pass that runs it ([`FrameGraph::will_dispatch_if_run`]):
//! handed to threads once the frame is planned, and only where a pass of
//! that name and owner runs, so a variant the frame does not record is not
//! made.
//!
//! Generated shaders (the fused light loop, [`FrameGraph::will_generate`])
//! are announced by their key, and made on a thread from it as from the
//! last run's list; render pipelines ([`FrameGraph::will_render`]) with the
//! function that builds them, which the pass's look-up uses too, so the
//! thread makes exactly the pipeline the pass would have.
//!
//! Announcing clones a key, so it is only done while frames still make
//! pipelines: the executor clears [`GATHERING`] after a frame that looked
//! none up for the first time, and sets it again when one did.

use std::sync::atomic::{AtomicBool, Ordering};

use super::FrameGraph;
use super::plan::Plan;
use crate::report::PassName;
use crate::shaders::pipelines_ahead::{Job, PipelineId, RenderBuild};
use crate::shaders::{GeneratedKey, ShaderKey};

/// A pipeline announced for the pass named so, of that owner.
pub(super) type IfRun = (PassName, Option<u32>, Job);

/// A pipeline of the pass named so, of that owner, whose entry point
/// follows which of its outputs (texture names) the frame reads.
pub(super) struct IfRead {
    pass: PassName,
    owner: Option<u32>,
    key: ShaderKey,
    outputs: smallvec::SmallVec<[String; 2]>,
    entry: fn(&[bool]) -> &'static str,
}

/// Whether frames announce their pipelines (process-wide: a hint, never a
/// correctness matter: a frame that does not announce makes its pipelines as
/// it records).
static GATHERING: AtomicBool = AtomicBool::new(true);

/// After a frame: whether it looked a compute pipeline up for the first time.
pub(super) fn frame_made_pipelines(made: bool) {
    GATHERING.store(made, Ordering::Relaxed);
}

impl FrameGraph<'_> {
    /// A pass of this frame will dispatch `entry` of `key` (to call where
    /// the pass is declared, before the frame records).
    pub fn will_dispatch(&mut self, key: &ShaderKey, entry: &'static str) {
        if GATHERING.load(Ordering::Relaxed) {
            self.pipelines.push(PipelineId::entry(key, entry).into());
        }
    }

    /// A pass of this frame will dispatch the generated shader `key`.
    pub fn will_generate(&mut self, key: GeneratedKey) {
        if GATHERING.load(Ordering::Relaxed) {
            self.pipelines.push(PipelineId::Generated(key).into());
        }
    }

    /// A pass of this frame will draw with the render pipeline of `key`
    /// named `variant`, which `build` makes (the function the pass's own
    /// look-up, `ShaderCache::render_pipeline`, builds it with).
    pub fn will_render(&mut self, key: &ShaderKey, variant: &str, build: RenderBuild) {
        if GATHERING.load(Ordering::Relaxed) {
            self.pipelines.push(Job {
                id: PipelineId::Render(key.clone(), variant.to_owned()),
                build: Some(build),
            });
        }
    }

    /// Whether announcing is on (frames still make pipelines): a pass whose
    /// keys take work to build asks first, so a warm frame builds none.
    pub fn gathers_pipelines(&self) -> bool {
        GATHERING.load(Ordering::Relaxed)
    }

    /// Like [`Self::will_dispatch`], for the pass `pass` of `owner` (the
    /// name of a merged pair's joint run where it is that run's): made
    /// ahead only where the frame's plan runs such a pass.
    pub fn will_dispatch_if_run(
        &mut self,
        pass: PassName,
        owner: Option<u32>,
        key: &ShaderKey,
        entry: &'static str,
    ) {
        if GATHERING.load(Ordering::Relaxed) {
            self.pipelines_if_run
                .push((pass, owner, PipelineId::entry(key, entry).into()));
        }
    }

    /// Like [`Self::will_dispatch_if_run`], for a pass whose entry point
    /// follows which of `outputs` (the textures it writes) the frame reads:
    /// `entry` picks it from those reads, in order, as the pass's run does.
    pub fn will_dispatch_by_reads(
        &mut self,
        pass: PassName,
        owner: Option<u32>,
        key: &ShaderKey,
        outputs: &[&str],
        entry: fn(&[bool]) -> &'static str,
    ) {
        if GATHERING.load(Ordering::Relaxed) {
            self.pipelines_if_read.push(IfRead {
                pass,
                owner,
                key: key.clone(),
                outputs: outputs.iter().map(|o| (*o).to_owned()).collect(),
                entry,
            });
        }
    }

    /// The pipelines announced by the outputs read, taken.
    pub(super) fn take_pipelines_if_read(&mut self) -> Vec<IfRead> {
        std::mem::take(&mut self.pipelines_if_read)
    }

    /// The pipelines announced, taken (the executor hands them to threads).
    pub(super) fn take_pipelines(&mut self) -> Vec<Job> {
        std::mem::take(&mut self.pipelines)
    }

    /// The pipelines announced for passes that may not run, taken.
    pub(super) fn take_pipelines_if_run(&mut self) -> Vec<IfRun> {
        std::mem::take(&mut self.pipelines_if_run)
    }
}

/// Of `announced`, those of a pass `plan` runs.
pub(super) fn run_by(plan: &Plan, announced: Vec<IfRun>) -> Vec<Job> {
    announced
        .into_iter()
        .filter(|(pass, owner, _)| {
            plan.order
                .iter()
                .any(|&p| plan.labels.get(p) == Some(pass) && plan.owners.get(p) == Some(owner))
        })
        .map(|(_, _, job)| job)
        .collect()
}

/// Of `announced`, the pipelines of the passes `plan` runs, each's entry
/// point picked by which of its outputs a later pass reads or the frame
/// requested (`PassContext::is_read`).
pub(super) fn read_by(plan: &Plan, announced: Vec<IfRead>) -> Vec<Job> {
    announced
        .into_iter()
        .filter_map(|a| {
            let step = plan.order.iter().position(|&p| {
                plan.labels.get(p) == Some(&a.pass) && plan.owners.get(p) == Some(&a.owner)
            })?;
            let reads: smallvec::SmallVec<[bool; 2]> = (a.outputs.iter())
                .map(|name| {
                    plan.requested_set.contains(name)
                        || plan.last_use.get(name).is_some_and(|&s| s > step)
                })
                .collect();
            Some(PipelineId::entry(&a.key, (a.entry)(&reads)).into())
        })
        .collect()
}
