//! What a kept plan's dispatches resolved last frame: each one's pipeline
//! and bind groups, kept so that a pass binding the same resources again
//! costs a few comparisons instead of the shader cache's look-ups (issue 33:
//! a permutation's key hashed for its pipeline and again for its
//! reflection, each variable name hashed to match it, each bind group's
//! resources hashed to find it, every dispatch of every frame).
//!
//! A call is found by its pass and its place among that pass's calls (the
//! n-th pipeline asked for, the n-th set of bind groups). What it was
//! resolved from is compared in full, never by hash: the permutation, its
//! entry points, the pipeline by identity, each resource by its variable
//! name and by identity (a held clone: no id is reused while it is held),
//! the groups made elsewhere, and the shader cache's sources (live editing
//! replaces them). Any difference resolves through the shader cache again
//! and keeps the new result in place, so a pass that changes what it binds
//! from frame to frame (a recipe made again with new buffers) pays what it
//! paid before and no more.
//!
//! A call keeps what it bound in the last two frames that bound something
//! new: a temporal pass binds its history and the history's twin in turns.
//! The executor holds the calls of the plans frames took lately: a host
//! running a few graphs in turns keeps each one's, and the views and
//! buffers held for a plan no frame took in the last 8 (and the textures
//! behind them) are let go.
//!
//! Counted in the frame report (`spreadlight stats`, `bench --json`) as
//! `pipelines kept` and `bind groups kept`; a kept group counts as reused
//! too (`bind groups reused`: not made again), kept ones being those
//! reused without a look-up.

use smallvec::SmallVec;

use crate::shaders::{BindGroups, INLINE_BINDINGS, PipelineRef, ShaderKey};
// Graph runs (`begin`s) a plan's calls are kept while no run takes it: a
// host running a few graphs in turns (a patch with two Outputs) keeps each
// one's, and the calls of a plan left behind (a resized output) let go of
// what they hold soon after. The views and textures they bind are kept as long.
use crate::texture_pool::IDLE_GRAPHS;

/// Frame report counters: pipelines and bind groups a dispatch took from
/// what it resolved last frame.
pub const PIPELINES_KEPT: &str = "pipelines kept";
pub const BIND_GROUPS_KEPT: &str = "bind groups kept";

/// The calls of every pass of the plans frames took lately.
pub(crate) struct KeptBindings {
    /// Whether calls are kept at all (`Executor::set_kept_bindings`).
    pub on: bool,
    /// Frames begun (what a plan's calls were last used at is counted in).
    frames: u64,
    plans: SmallVec<[PlanCalls; 2]>,
    /// The one of `plans` this frame's plan is.
    current: Option<usize>,
}

/// The calls of one plan's passes.
struct PlanCalls {
    /// The plan they are of (`Plan::id`).
    plan: u64,
    /// The shader cache's sources they were resolved under (`ShaderCache::generation`).
    generation: u64,
    /// The frame that last took the plan.
    last: u64,
    /// By the plan's pass index.
    passes: Vec<PassCalls>,
}

impl Default for KeptBindings {
    fn default() -> Self {
        KeptBindings {
            on: true,
            frames: 0,
            plans: SmallVec::new(),
            current: None,
        }
    }
}

impl KeptBindings {
    /// Ready for a frame on plan `plan` of `passes` passes under the shader
    /// cache's `generation`, `reused` when the frame took a kept plan: what
    /// other sources resolved is dropped, and so is what plans no frame took
    /// for a while resolved. Calls are kept from a plan's second frame on:
    /// a plan taken once (every plan, with plan reuse off) keeps nothing.
    pub fn begin(&mut self, plan: u64, passes: usize, generation: u64, reused: bool) {
        self.frames += 1;
        let frame = self.frames;
        self.current = None;
        if !self.on {
            self.plans.clear();
            return;
        }
        self.plans
            .retain(|p| p.generation == generation && frame - p.last <= IDLE_GRAPHS);
        if !reused {
            return;
        }
        let at = match self.plans.iter().position(|p| p.plan == plan) {
            Some(at) if self.plans[at].passes.len() == passes => at,
            found => {
                let calls = PlanCalls {
                    plan,
                    generation,
                    last: frame,
                    passes: std::iter::repeat_with(PassCalls::default)
                        .take(passes)
                        .collect(),
                };
                match found {
                    Some(at) => {
                        self.plans[at] = calls;
                        at
                    }
                    None => {
                        self.plans.push(calls);
                        self.plans.len() - 1
                    }
                }
            }
        };
        let calls = &mut self.plans[at];
        calls.last = frame;
        for pass in &mut calls.passes {
            pass.pipelines_kept = 0;
            pass.groups_kept = 0;
        }
        self.current = Some(at);
    }

    /// Pipelines and bind groups taken from last frame's calls this frame.
    pub fn counted(&self) -> (u64, u64) {
        let Some(calls) = self.current.and_then(|at| self.plans.get(at)) else {
            return (0, 0);
        };
        calls.passes.iter().fold((0, 0), |(p, g), pass| {
            (p + pass.pipelines_kept, g + pass.groups_kept)
        })
    }

    /// Pass `p`'s calls, its cursors at its first call; None when calls are not kept.
    pub fn pass(&mut self, p: usize) -> Option<&mut PassCalls> {
        let calls = self.plans.get_mut(self.current?)?.passes.get_mut(p)?;
        calls.next_pipeline = 0;
        calls.next_groups = 0;
        Some(calls)
    }
}

/// One pass's calls, in the order it made them last frame.
#[derive(Default)]
pub(crate) struct PassCalls {
    pipelines: SmallVec<[KeptPipeline; 2]>,
    groups: SmallVec<[CallSlot; 2]>,
    next_pipeline: usize,
    next_groups: usize,
    /// Taken from last frame's calls this frame (`PIPELINES_KEPT`, `BIND_GROUPS_KEPT`).
    pipelines_kept: u64,
    groups_kept: u64,
}

struct KeptPipeline {
    key: ShaderKey,
    entry: &'static str,
    pipeline: wgpu::ComputePipeline,
}

/// A resource bound, by identity.
#[derive(PartialEq)]
pub(crate) enum Held {
    View(wgpu::TextureView),
    /// A buffer, its offset and size (None: the whole buffer).
    Buffer(wgpu::Buffer, u64, Option<u64>),
    Sampler(wgpu::Sampler),
}

/// A resource as the pass hands it over this frame, borrowed: compared
/// with a [`Held`] one without cloning it.
pub(crate) enum Given<'a> {
    View(&'a wgpu::TextureView),
    Buffer(&'a wgpu::Buffer, u64, Option<u64>),
    Sampler(&'a wgpu::Sampler),
}

impl Given<'_> {
    fn is(&self, held: &Held) -> bool {
        match (self, held) {
            (Given::View(a), Held::View(b)) => *a == b,
            (Given::Buffer(a, offset, size), Held::Buffer(b, o, s)) => {
                *a == b && offset == o && size == s
            }
            (Given::Sampler(a), Held::Sampler(b)) => *a == b,
            _ => false,
        }
    }

    fn held(&self) -> Held {
        match *self {
            Given::View(v) => Held::View(v.clone()),
            Given::Buffer(b, offset, size) => Held::Buffer(b.clone(), offset, size),
            Given::Sampler(s) => Held::Sampler(s.clone()),
        }
    }
}

/// What one call bound and the groups it got.
struct KeptGroups {
    /// None for groups a caller laid out itself (a shader node's, by its
    /// file's numbers): the pipeline, compared by identity, names its shader.
    key: Option<ShaderKey>,
    /// The entry points, each followed by a NUL (no allocation a frame: the
    /// text is refilled in place when a call changes).
    entries: String,
    pipeline: PipelineRef,
    /// Each resource's variable name, as a range of `names`, and identity.
    names: String,
    resources: SmallVec<[(u32, u32, Held); INLINE_BINDINGS]>,
    prebuilt: SmallVec<[(u32, wgpu::BindGroup); 1]>,
    groups: BindGroups,
}

/// A call of this frame, to compare with last frame's.
pub(crate) struct GroupsCall<'c, 'r> {
    pub key: Option<&'c ShaderKey>,
    pub entries: &'c [&'c str],
    pub pipeline: &'c PipelineRef,
    pub resources: &'c [(&'r str, Given<'c>)],
    pub prebuilt: &'c [(u32, wgpu::BindGroup)],
}

fn same_entries(kept: &str, entries: &[&str]) -> bool {
    let mut rest = kept;
    for entry in entries {
        match rest.strip_prefix(entry).and_then(|r| r.strip_prefix('\0')) {
            Some(r) => rest = r,
            None => return false,
        }
    }
    rest.is_empty()
}

impl KeptGroups {
    fn matches(&self, call: &GroupsCall<'_, '_>) -> bool {
        self.pipeline == *call.pipeline
            && self.key.as_ref() == call.key
            && same_entries(&self.entries, call.entries)
            && self.resources.len() == call.resources.len()
            && self
                .resources
                .iter()
                .zip(call.resources)
                .all(|((from, to, held), (name, given))| {
                    self.names.get(*from as usize..*to as usize) == Some(*name) && given.is(held)
                })
            && self.prebuilt.len() == call.prebuilt.len()
            && self
                .prebuilt
                .iter()
                .zip(call.prebuilt)
                .all(|(a, b)| a.0 == b.0 && a.1 == b.1)
    }

    /// This call's inputs and `groups`, written over the kept ones (their
    /// text and inline storage reused).
    fn refill(&mut self, call: &GroupsCall<'_, '_>, groups: &BindGroups) {
        if self.key.as_ref() != call.key {
            self.key = call.key.cloned();
        }
        if !same_entries(&self.entries, call.entries) {
            self.entries.clear();
            for entry in call.entries {
                self.entries.push_str(entry);
                self.entries.push('\0');
            }
        }
        self.pipeline = call.pipeline.clone();
        self.names.clear();
        self.resources.clear();
        for (name, given) in call.resources {
            let from = self.names.len() as u32;
            self.names.push_str(name);
            self.resources
                .push((from, self.names.len() as u32, given.held()));
        }
        self.prebuilt.clear();
        self.prebuilt.extend(call.prebuilt.iter().cloned());
        self.groups.clone_from(groups);
    }

    fn new(call: &GroupsCall<'_, '_>, groups: &BindGroups) -> Self {
        let mut kept = KeptGroups {
            key: call.key.cloned(),
            entries: String::new(),
            pipeline: call.pipeline.clone(),
            names: String::new(),
            resources: SmallVec::new(),
            prebuilt: SmallVec::new(),
            groups: BindGroups::new(),
        };
        kept.refill(call, groups);
        kept
    }
}

impl PassCalls {
    /// The compute pipeline this pass's next pipeline call got last frame,
    /// if it asked for the same `key` and `entry`; else `resolve`'s, kept.
    pub fn pipeline<E>(
        &mut self,
        key: &ShaderKey,
        entry: &'static str,
        resolve: impl FnOnce() -> Result<wgpu::ComputePipeline, E>,
    ) -> Result<(wgpu::ComputePipeline, bool), E> {
        let at = self.next_pipeline;
        self.next_pipeline += 1;
        if let Some(kept) = self.pipelines.get(at)
            && kept.entry == entry
            && kept.key == *key
        {
            self.pipelines_kept += 1;
            return Ok((kept.pipeline.clone(), true));
        }
        let pipeline = resolve()?;
        let kept = KeptPipeline {
            key: key.clone(),
            entry,
            pipeline: pipeline.clone(),
        };
        match self.pipelines.get_mut(at) {
            Some(slot) => *slot = kept,
            None => self.pipelines.push(kept),
        }
        Ok((pipeline, false))
    }

    /// The bind groups this pass's next bind-group call got in one of the
    /// last frames, if it bound exactly what `call` binds; else `resolve`'s, kept.
    pub fn groups<E>(
        &mut self,
        call: &GroupsCall<'_, '_>,
        resolve: impl FnOnce() -> Result<BindGroups, E>,
    ) -> Result<(BindGroups, bool), E> {
        let at = self.next_groups;
        self.next_groups += 1;
        if let Some(slot) = self.groups.get_mut(at)
            && let Some(i) = slot.kept.iter().position(|k| k.matches(call))
        {
            slot.recent = i;
            let groups = &slot.kept[i].groups;
            self.groups_kept += groups.len() as u64;
            return Ok((groups.clone(), true));
        }
        let groups = resolve()?;
        if self.groups.len() <= at {
            self.groups.push(CallSlot::default());
        }
        let slot = &mut self.groups[at];
        if slot.kept.len() < CALL_VARIANTS {
            slot.recent = slot.kept.len();
            slot.kept.push(KeptGroups::new(call, &groups));
        } else {
            // The one not bound most recently makes way.
            slot.recent = (slot.recent + 1) % CALL_VARIANTS;
            slot.kept[slot.recent].refill(call, &groups);
        }
        Ok((groups, false))
    }
}

/// What a call bound in the last frames it bound something new in: two,
/// as a temporal pass's history and its twin trade places every frame (it
/// binds A then B then A again).
const CALL_VARIANTS: usize = 2;

#[derive(Default)]
struct CallSlot {
    kept: SmallVec<[KeptGroups; CALL_VARIANTS]>,
    /// Which of `kept` was bound last.
    recent: usize,
}

#[cfg(test)]
mod tests {
    use super::same_entries;

    #[test]
    fn entries_compare_whole() {
        assert!(same_entries("vs\0fs\0", &["vs", "fs"]));
        assert!(same_entries("main\0", &["main"]));
        assert!(!same_entries("main\0", &["mai"]));
        assert!(!same_entries("vs\0fs\0", &["vs"]));
        assert!(!same_entries("vs\0", &["vs", "fs"]));
        assert!(same_entries("", &[]));
    }
}
