//! A frame graph's plan, kept across frames while what was declared stays
//! the same (issue 33: a frame's CPU).
//!
//! Recipes declare the frame graph again every frame: their runs carry this
//! frame's values (uniforms, instance counts, the recipe itself). But the
//! plan made from the declaration (which passes run, in which order, which
//! pairs merge, each output's texture key, where each texture is last used,
//! which temporaries may trade with a history, each pass's name as text)
//! depends only on what was declared, not on the runs: the output size, each
//! pass's name, owner, reads and writes (names and descriptors), the
//! requests, the watches, the imported names and the merges asked for. When
//! all of these equal a kept plan's, compared field by field (no hash, so
//! never a collision), that plan is the one planning would make again, and
//! the frame takes it: only its runs, handles, imports and counters are its
//! own. Anything else (a pin that changes a texture's format or size, a
//! resized output, a node added or removed, a merge that now applies) makes
//! a new plan.
//!
//! The one input from outside the declaration is which persistent textures
//! exist (a pass may read last frame's history, which no pass of this frame
//! writes): a kept plan lists the names it reads that way, and is taken only
//! while they all exist, so a dropped history gives the error planning gives.
//!
//! `plans reused` and `plans made` in the frame report's counters say which
//! happened; [`super::Executor::set_plan_reuse`] turns reuse off (tests
//! compare both, `spreadlight bench --no-plan-reuse` times both).

use std::collections::BTreeMap;
use std::sync::{Arc, Mutex};

use rustc_hash::{FxHashMap, FxHashSet};

use super::merge::Applied;
use super::{FrameGraph, GraphParts, Lifetime, PassFn, PassName, PassOrder, TextureDesc};
use crate::error::RenderError;
use crate::texture_pool::TextureKey;

/// Plans kept: a frame may execute several graphs (each Output, the
/// editor's viewport and its previews), each with its own plan.
const KEPT: usize = 8;

/// What a plan was made from: the declaration without its runs, with
/// textures as handles (their numbering follows the declaration, so a graph
/// declared again by re-made recipes numbers them alike).
struct Shape {
    output_size: (u32, u32),
    /// How many textures the declaration named.
    textures: usize,
    /// Textures whose names are their identity beyond this frame, by handle:
    /// persistent ones (kept under their name), imported ones and those no
    /// pass writes (persistent from last frame). The others (the
    /// temporaries and permanents a pass writes) may be named anew each
    /// frame (recipes name them after themselves, and are made again when an
    /// input changes): the plan then runs the frame under its own names for
    /// them, and hands the caller its textures under this frame's.
    fixed: Vec<(u32, String)>,
    passes: Vec<DeclaredPass>,
    requested: Vec<Named>,
    watched: Vec<Named>,
    /// The imported names (the textures themselves are each frame's), with
    /// their handles.
    imports: Vec<(String, Option<u32>)>,
    merges: Vec<DeclaredMerge>,
}

/// A texture named outside a pass's declaration (a request, a watch, a
/// merge's first pass): by handle when a pass declared it, else by name.
#[derive(PartialEq)]
enum Named {
    Handle(u32),
    Name(String),
}

impl Named {
    fn of(graph: &FrameGraph<'_>, name: &str) -> Named {
        match graph.handle_of(name) {
            Some(h) => Named::Handle(h),
            None => Named::Name(name.to_owned()),
        }
    }

    fn is(&self, graph: &FrameGraph<'_>, name: &str) -> bool {
        match self {
            Named::Handle(h) => graph.handle_of(name) == Some(*h),
            Named::Name(n) => n == name && graph.handle_of(name).is_none(),
        }
    }
}

struct DeclaredPass {
    name: PassName,
    owner: Option<u32>,
    handles: super::PassHandles,
    descs: smallvec::SmallVec<[TextureDesc; 4]>,
}

struct DeclaredMerge {
    first: Option<Named>,
    second: usize,
    chain: bool,
    name: PassName,
}

impl Shape {
    fn of(graph: &FrameGraph<'_>) -> Shape {
        let mut renamable = vec![false; graph.texture_names.len()];
        for pass in &graph.passes {
            for (&h, desc) in pass.handles.writes.iter().zip(&pass.descs) {
                if desc.lifetime != Lifetime::Persistent {
                    renamable[h as usize] = true;
                }
            }
        }
        let fixed = graph
            .texture_names
            .iter()
            .enumerate()
            .filter(|&(h, name)| !renamable[h] || graph.imports.contains_key(name))
            .map(|(h, name)| (h as u32, name.clone()))
            .collect();
        Shape {
            output_size: graph.output_size,
            textures: graph.texture_names.len(),
            fixed,
            passes: graph
                .passes
                .iter()
                .map(|p| DeclaredPass {
                    name: p.name.clone(),
                    owner: p.owner,
                    handles: p.handles.clone(),
                    descs: p.descs.clone(),
                })
                .collect(),
            requested: graph
                .requested
                .iter()
                .map(|n| Named::of(graph, n))
                .collect(),
            watched: graph.watched.iter().map(|n| Named::of(graph, n)).collect(),
            imports: graph
                .imports
                .keys()
                .map(|n| (n.clone(), graph.handle_of(n)))
                .collect(),
            merges: graph
                .merges
                .iter()
                .map(|m| {
                    let (first, second, chain, name) = m.shape();
                    DeclaredMerge {
                        first: first.map(|n| Named::of(graph, n)),
                        second,
                        chain,
                        name: name.clone(),
                    }
                })
                .collect(),
        }
    }

    /// Whether `graph` declares this again (its runs aside, its renamable
    /// textures perhaps under other names).
    fn matches(&self, graph: &FrameGraph<'_>) -> bool {
        let names = &graph.texture_names;
        self.output_size == graph.output_size
            && self.textures == names.len()
            && self.passes.len() == graph.passes.len()
            && self.requested.len() == graph.requested.len()
            && self.watched.len() == graph.watched.len()
            && self.imports.len() == graph.imports.len()
            && self.merges.len() == graph.merges.len()
            && self.passes.iter().zip(&graph.passes).all(|(s, p)| {
                s.owner == p.owner
                    && s.handles == p.handles
                    && s.name == p.name
                    && s.descs == p.descs
            })
            && self
                .fixed
                .iter()
                .all(|(h, name)| names.get(*h as usize) == Some(name))
            && self
                .requested
                .iter()
                .zip(&graph.requested)
                .all(|(s, n)| s.is(graph, n))
            && self
                .watched
                .iter()
                .zip(&graph.watched)
                .all(|(s, n)| s.is(graph, n))
            && self
                .imports
                .iter()
                .all(|(name, h)| graph.imports.contains_key(name) && graph.handle_of(name) == *h)
            && self.merges.iter().zip(&graph.merges).all(|(s, m)| {
                let (first, second, chain, name) = m.shape();
                s.second == second
                    && s.chain == chain
                    && s.name == *name
                    && match (&s.first, first) {
                        (None, None) => true,
                        (Some(s), Some(n)) => s.is(graph, n),
                        _ => false,
                    }
            })
    }
}

/// A frame graph's plan: the passes after culling, ordering and merging,
/// and what the executor derives from them before any pass records.
pub(crate) struct Plan {
    /// Unique in the process: what a frame's kept bindings are of (kept_bindings.rs).
    pub id: u64,
    shape: Shape,
    /// Per pass (declaration order, merged pairs folded into their first):
    /// its name as fields, as text (with its owner), its owner, the owner of
    /// another node's pass merged into it, what it reads and writes, and its
    /// outputs' texture keys at this output size.
    pub labels: Vec<PassName>,
    pub names: Vec<String>,
    pub owners: Vec<Option<u32>>,
    pub partners: Vec<Option<u32>>,
    pub reads: Vec<Vec<String>>,
    pub writes: Vec<Vec<(String, TextureDesc)>>,
    pub keys: Vec<smallvec::SmallVec<[TextureKey; 4]>>,
    pub order: Vec<usize>,
    /// The order the plan was made for, and with [`PassOrder::Waves`] per
    /// step of `order` the last step of its wave (waves.rs; empty in
    /// declaration order) and per pass whether it went first in its wave
    /// (it asked for the encoder itself last frame): a frame whose passes
    /// ask otherwise orders afresh.
    pub pass_order: PassOrder,
    pub wave_end: Vec<usize>,
    encoder_first: Vec<bool>,
    pub culled: Vec<usize>,
    pub requested: Vec<String>,
    /// Texture names by handle, and handles by name, as the frame that made
    /// the plan declared them: the names a frame taking the plan runs under.
    pub texture_names: Vec<String>,
    handles: FxHashMap<String, u32>,
    /// The merges that applied, to hand their runs to this frame's passes.
    merged: Vec<Applied>,
    /// Names read from outside the frame: persistent textures it needs.
    outside: Vec<String>,
    /// The step at which each texture is last read or written.
    pub last_use: FxHashMap<String, usize>,
    pub requested_set: FxHashSet<String>,
    /// Watched textures that no request names.
    pub watched_set: FxHashSet<String>,
    /// Temporaries a history may trade textures with (history.rs).
    pub tradable: FxHashSet<String>,
    /// The live textures' map, kept between the frames that take the plan
    /// (live.rs): empty of textures between frames.
    pub live: Mutex<super::live::Live>,
    /// Per pass and output, its pool slot: what keeps an output's texture
    /// from frame to frame (`texture_pool::slot` of the pass name, which of
    /// the passes of its name the pass is, and the output; hashed a write a
    /// frame before).
    pub slots: Vec<smallvec::SmallVec<[u64; 4]>>,
}

impl Plan {
    fn new(
        shape: Shape,
        parts: GraphParts<'_>,
        pass_order: PassOrder,
        encoder_first: &dyn Fn(&str) -> bool,
    ) -> Plan {
        let encoder_first = if pass_order == PassOrder::Waves {
            parts.names.iter().map(|n| encoder_first(n)).collect()
        } else {
            Vec::new()
        };
        let handles = (parts.texture_names.iter().enumerate())
            .map(|(h, name)| (name.clone(), h as u32))
            .collect();
        let mut last_use = FxHashMap::default();
        for (step, &p) in parts.order.iter().enumerate() {
            for name in parts.reads[p]
                .iter()
                .chain(parts.writes[p].iter().map(|(n, _)| n))
            {
                last_use.insert(name.clone(), step);
            }
        }
        let requested_set: FxHashSet<String> = parts.requested.iter().cloned().collect();
        let watched_set = parts.watched.iter().cloned().collect();
        let tradable = parts
            .writes
            .iter()
            .flatten()
            .filter(|(name, desc)| {
                desc.lifetime == Lifetime::Temporary && !requested_set.contains(name)
            })
            .map(|(name, _)| name.clone())
            .collect();
        let mut seen: FxHashMap<&str, u32> = FxHashMap::default();
        let occurrence = parts
            .names
            .iter()
            .map(|name| {
                let n = seen.entry(name.as_str()).or_default();
                *n += 1;
                *n - 1
            })
            .collect::<Vec<u32>>();
        let slots = (parts.names.iter().zip(&occurrence).zip(&parts.writes))
            .map(|((name, &n), writes)| {
                (0..writes.len())
                    .map(|output| crate::texture_pool::slot(name, n, output))
                    .collect()
            })
            .collect();
        static PLANS_MADE: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(1);
        Plan {
            id: PLANS_MADE.fetch_add(1, std::sync::atomic::Ordering::Relaxed),
            shape,
            labels: parts.labels,
            names: parts.names,
            owners: parts.owners,
            partners: parts.partners,
            reads: parts.reads,
            writes: parts.writes,
            keys: parts.keys,
            order: parts.order,
            pass_order,
            wave_end: parts.wave_end,
            encoder_first,
            culled: parts.culled,
            requested: parts.requested,
            texture_names: parts.texture_names,
            handles,
            merged: parts.merged,
            outside: parts.outside,
            last_use,
            requested_set,
            watched_set,
            tradable,
            live: Default::default(),
            slots,
        }
    }
}

/// The plans an executor keeps, most recently used first.
pub(crate) struct Plans {
    kept: Mutex<(bool, Vec<Arc<Plan>>)>,
}

impl Default for Plans {
    fn default() -> Self {
        Plans {
            kept: Mutex::new((true, Vec::with_capacity(KEPT))),
        }
    }
}

impl Plans {
    /// Reuse plans (the default) or plan every graph afresh.
    pub fn set_reuse(&self, reuse: bool) {
        let mut kept = self.kept.lock().unwrap_or_else(|e| e.into_inner());
        kept.0 = reuse;
        if !reuse {
            kept.1.clear();
        }
    }

    /// The kept plan `graph` declares again, if any (moved to the front).
    fn find(
        &self,
        graph: &FrameGraph<'_>,
        persistent: &dyn Fn(&str) -> bool,
        pass_order: PassOrder,
        encoder_first: &dyn Fn(&str) -> bool,
    ) -> Option<Arc<Plan>> {
        let mut kept = self.kept.lock().unwrap_or_else(|e| e.into_inner());
        if !kept.0 {
            return None;
        }
        let at = kept.1.iter().position(|plan| {
            plan.pass_order == pass_order
                && plan.shape.matches(graph)
                && (plan.names.iter().zip(&plan.encoder_first)).all(|(n, &e)| encoder_first(n) == e)
                && plan
                    .outside
                    .iter()
                    .all(|name| graph.imports.contains_key(name) || persistent(name))
        })?;
        kept.1[..=at].rotate_right(1);
        Some(kept.1[0].clone())
    }

    fn keep(&self, plan: Arc<Plan>) {
        let mut kept = self.kept.lock().unwrap_or_else(|e| e.into_inner());
        if !kept.0 {
            return;
        }
        kept.1.truncate(KEPT - 1);
        kept.1.insert(0, plan);
    }
}

/// A frame graph planned: the plan (kept or new) and this frame's own parts.
pub(crate) struct Planned<'a> {
    pub plan: Arc<Plan>,
    /// Whether the plan was a kept one.
    pub reused: bool,
    /// Per pass of the plan: the code that records it this frame (`None`
    /// for a pass merged into another).
    pub runs: Vec<Option<PassFn<'a>>>,
    pub imports: FxHashMap<String, wgpu::Texture>,
    pub counters: BTreeMap<&'static str, u64>,
    /// This frame's texture names by handle, where the plan is a kept one
    /// (it runs under the plan's names; the caller gets this frame's).
    pub frame_names: Option<Vec<String>>,
}

/// The name the caller knows a texture of the plan by: this frame's name
/// of its handle, where the frame took a kept plan (`frame_names`).
pub(crate) fn frame_name<'n>(
    plan: &'n Plan,
    frame_names: Option<&'n [String]>,
    name: &'n str,
) -> &'n str {
    match (frame_names, plan.handles.get(name)) {
        (Some(names), Some(&h)) => names.get(h as usize).map_or(name, String::as_str),
        _ => name,
    }
}

impl<'a> FrameGraph<'a> {
    /// This graph's plan: a kept one when the graph declares what it was
    /// made from and the persistent textures it reads exist, else a new one
    /// (kept for the next frames).
    pub(crate) fn plan(
        self,
        plans: &Plans,
        persistent: &dyn Fn(&str) -> bool,
        pass_order: PassOrder,
        encoder_first: &dyn Fn(&str) -> bool,
    ) -> Result<Planned<'a>, RenderError> {
        self.note_sizes();
        if let Some(plan) = plans.find(&self, persistent, pass_order, encoder_first) {
            let mut runs: Vec<Option<PassFn<'a>>> =
                self.passes.into_iter().map(|p| Some(p.run)).collect();
            super::merge::rerun(&mut runs, self.merges, &plan.merged);
            return Ok(Planned {
                plan,
                reused: true,
                runs,
                imports: self.imports,
                counters: self.counters,
                frame_names: Some(self.texture_names),
            });
        }
        let shape = Shape::of(&self);
        let mut parts = self.into_parts(persistent, pass_order, encoder_first)?;
        let runs = std::mem::take(&mut parts.runs);
        let imports = std::mem::take(&mut parts.imports);
        let counters = std::mem::take(&mut parts.counters);
        let plan = Arc::new(Plan::new(shape, parts, pass_order, encoder_first));
        plans.keep(plan.clone());
        Ok(Planned {
            plan,
            reused: false,
            runs,
            imports,
            counters,
            frame_names: None,
        })
    }
}
