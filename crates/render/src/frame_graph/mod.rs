//! The frame graph: passes declare the textures they read and write (a name
//! is a texture's identity across recipes and frames) and get typed handles
//! back (handles.rs), which are all their runs can resolve; they bind their
//! shaders' variables by name (bindings.rs). Before anything runs, every pass
//! whose outputs do not reach a requested output is culled. A texture can
//! also be watched ([`FrameGraph::watch`]): handed back if the frame makes
//! it anyway, without changing which passes run, merge or share memory (the
//! editor's thumbnails). As in breezEngine, a texture is temporary (pooled by
//! descriptor and reused within and across frames), permanent (lives through
//! the frame) or persistent (kept across frames under its name: history,
//! adapted luminance). Sizes are absolute or a scale of the frame's output.
//!
//! How passes are recorded, timed and submitted is `execute.rs`: by default
//! each pass records into its own command encoder inside a validation error
//! scope, so a wgpu validation error is reported against the pass (and the
//! node that declared it) and the rest of the frame still renders.

use std::collections::BTreeMap;

use rustc_hash::{FxHashMap, FxHashSet};

mod bindings;
mod bound;
mod compute_pass;
mod execute;
mod executor;
mod finisher;
mod gather;
mod handles;
mod history;
mod kept_bindings;
mod live;
mod merge;
mod plan;
mod submitter;
#[cfg(test)]
mod tests;
mod waves;

use crate::context::GpuContext;
use crate::error::RenderError;
use crate::shaders::ShaderCache;

pub use crate::report::{FrameReport, PassName, PassReport};
pub use crate::texture_pool::TextureKey;
pub use bindings::{BindGroups, Bindings};
pub use bound::History;
pub use compute_pass::COMPUTE_PASSES;
pub use executor::{Executor, PERSISTENT_IDLE_GRAPHS, Recording, Timing};
pub use finisher::FRAME_CHUNKS;
pub(crate) use finisher::Finisher;
pub use handles::{PassBuilder, Tex};
pub use history::{COPIED as HISTORIES_COPIED, HANDED_OVER as HISTORIES_HANDED_OVER};
pub use kept_bindings::{BIND_GROUPS_KEPT, PIPELINES_KEPT};
pub use submitter::{SUBMIT_VAR, Submission};
pub use waves::{PASS_ORDER_VAR, PASS_WAVES, PassOrder};

/// What every texture a frame hands back to its caller can do, so that any
/// sink can read it: be copied (Output's readback) and sampled (the
/// editor's viewport).
pub const READABLE: wgpu::TextureUsages =
    wgpu::TextureUsages::COPY_SRC.union(wgpu::TextureUsages::TEXTURE_BINDING);

/// How big a texture is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SizeRule {
    Absolute {
        width: u32,
        height: u32,
    },
    /// A scale of the frame's output size (1.0 full, 0.25 quarter), at least 1x1.
    Relative(f32),
}

impl SizeRule {
    /// Level `k` of a mip chain of this size: halved `k` times, at least 1x1.
    pub fn mip(self, k: u32) -> SizeRule {
        match self {
            SizeRule::Relative(s) => SizeRule::Relative(s * 0.5f32.powi(k as i32)),
            SizeRule::Absolute { width, height } => SizeRule::Absolute {
                width: (width >> k).max(1),
                height: (height >> k).max(1),
            },
        }
    }

    /// This size times `factor`, rounded as a relative size rounds (so a
    /// chain of an image file's halvings has the sizes the same chain of a
    /// frame of its size has; [`SizeRule::mip`] rounds down).
    pub fn scaled(self, factor: f32) -> SizeRule {
        match self {
            SizeRule::Relative(s) => SizeRule::Relative(s * factor),
            SizeRule::Absolute { width, height } => {
                let (width, height) = SizeRule::Relative(factor).pixels((width, height));
                SizeRule::Absolute { width, height }
            }
        }
    }

    /// Width and height in pixels for a frame of `output` size; never zero.
    pub fn pixels(self, output: (u32, u32)) -> (u32, u32) {
        match self {
            SizeRule::Absolute { width, height } => (width.max(1), height.max(1)),
            SizeRule::Relative(scale) => {
                let scale = if scale.is_finite() && scale > 0.0 {
                    scale
                } else {
                    1.0
                };
                (
                    ((output.0 as f32 * scale).round() as u32).max(1),
                    ((output.1 as f32 * scale).round() as u32).max(1),
                )
            }
        }
    }
}

/// How long a texture lives.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Lifetime {
    /// Within the passes that use it; its memory is reused by later passes.
    Temporary,
    /// Through the whole frame.
    Permanent,
    /// Across frames, under its name (last frame's depth, temporal history).
    Persistent,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TextureDesc {
    pub format: wgpu::TextureFormat,
    pub size: SizeRule,
    pub lifetime: Lifetime,
    pub usage: wgpu::TextureUsages,
    /// Made only when a later pass reads it or the caller asks for it
    /// ([`TextureDesc::only_if_read`]).
    pub only_if_read: bool,
}

impl TextureDesc {
    /// A full-size target that compute writes and later passes read: the common case.
    pub fn storage(format: wgpu::TextureFormat) -> Self {
        TextureDesc {
            format,
            size: SizeRule::Relative(1.0),
            lifetime: Lifetime::Temporary,
            usage: wgpu::TextureUsages::STORAGE_BINDING
                | wgpu::TextureUsages::TEXTURE_BINDING
                | wgpu::TextureUsages::COPY_SRC,
            only_if_read: false,
        }
    }

    /// A full-size raster target.
    pub fn attachment(format: wgpu::TextureFormat) -> Self {
        TextureDesc {
            format,
            size: SizeRule::Relative(1.0),
            lifetime: Lifetime::Temporary,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT
                | wgpu::TextureUsages::TEXTURE_BINDING
                | wgpu::TextureUsages::COPY_SRC,
            only_if_read: false,
        }
    }

    /// A 1x1 texture nobody reads: it only orders passes whose real output
    /// lives outside the graph (a buffer, a store kept between frames).
    pub fn token() -> Self {
        TextureDesc {
            format: wgpu::TextureFormat::R8Unorm,
            size: SizeRule::Absolute {
                width: 1,
                height: 1,
            },
            lifetime: Lifetime::Temporary,
            usage: wgpu::TextureUsages::TEXTURE_BINDING,
            only_if_read: false,
        }
    }

    /// A temporal history: persistent, written by compute, readable, and
    /// handed to its "previous" twin ([`TextureDesc::history_twin`]) before
    /// each update ([`PassContext::copy_history`]); COPY_DST so tools and
    /// tests can seed it.
    pub fn history(format: wgpu::TextureFormat) -> Self {
        let mut desc = TextureDesc::storage(format).lifetime(Lifetime::Persistent);
        desc.usage |= wgpu::TextureUsages::COPY_DST;
        desc
    }

    /// A temporary alike to [`TextureDesc::history`], so the two trade
    /// textures each frame instead of copying (`history.rs`): last frame's
    /// history, read while the history is written
    /// ([`PassContext::copy_history`]; a texture cannot be read and written
    /// in one dispatch without read-write storage), or this frame's result
    /// that becomes the history ([`PassContext::keep_as_history`]).
    pub fn history_twin(format: wgpu::TextureFormat) -> Self {
        TextureDesc::history(format).lifetime(Lifetime::Temporary)
    }

    /// Last frame's history, always copied (its usage differs from the
    /// history's, so they never trade): for a pass that may leave texels of
    /// the history unwritten and expects them kept, such as a user's shader.
    pub fn history_copy(format: wgpu::TextureFormat) -> Self {
        TextureDesc {
            usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
            ..TextureDesc::storage(format)
        }
    }

    pub fn lifetime(mut self, lifetime: Lifetime) -> Self {
        self.lifetime = lifetime;
        self
    }

    pub fn size(mut self, size: SizeRule) -> Self {
        self.size = size;
        self
    }

    /// An output made only when a later pass reads it or the caller asks
    /// for it: its pass declares it, but runs it only where it is needed
    /// ([`PassContext::is_read`] says which) and binds no texture for it
    /// otherwise. Nothing is allocated for it in a frame where nothing
    /// reads it (counted under [`TARGETS_NOT_MADE`]): a fused light sets'
    /// own targets when CompositeLight reads their sum (lighting::light_sets).
    pub fn only_if_read(mut self) -> Self {
        self.only_if_read = true;
        self
    }
}

/// Counted each frame: outputs declared [`TextureDesc::only_if_read`] that
/// nothing read, so no texture was allocated for them.
pub const TARGETS_NOT_MADE: &str = "targets not made: nothing reads them";

type PassFn<'a> = Box<dyn FnOnce(&mut PassContext<'_>) -> Result<(), RenderError> + 'a>;

struct PassEntry<'a> {
    name: PassName,
    /// The patch node that declared the pass, for error reports.
    owner: Option<u32>,
    /// Filled from `handles` and `descs` when the graph is planned
    /// (`FrameGraph::into_parts`), not while it is declared: a frame that
    /// takes a kept plan never names them (plan.rs).
    reads: Vec<String>,
    writes: Vec<(String, TextureDesc)>,
    handles: PassHandles,
    descs: smallvec::SmallVec<[TextureDesc; 4]>,
    run: PassFn<'a>,
}

/// A pass's reads and writes as handles (indices into the frame's texture
/// names), inline: how a kept plan recognises the same graph when its
/// recipes were made again under new names (plan.rs).
#[derive(Clone, Default, PartialEq, Eq)]
struct PassHandles {
    reads: smallvec::SmallVec<[u32; 8]>,
    writes: smallvec::SmallVec<[u32; 4]>,
}

/// What a pass sees while it records.
pub struct PassContext<'f> {
    pub gpu: &'f GpuContext,
    /// Used through [`PassContext::encoder`], which first ends the open compute pass.
    pub(crate) encoder: wgpu::CommandEncoder,
    /// The compute pass dispatches go into, open across graph passes of one
    /// encoder (compute_pass.rs).
    pub(crate) compute: Option<compute_pass::OpenCompute>,
    /// Whether timestamps can be written inside a compute pass, so that a
    /// timed graph pass can share one.
    pub(crate) timestamps_inside_passes: bool,
    pub shaders: &'f mut ShaderCache,
    /// What this pass's calls resolved last frame (kept_bindings.rs).
    /// None where calls are not kept (`Executor::set_kept_bindings`).
    pub(crate) kept: Option<&'f mut kept_bindings::PassCalls>,
    pub(crate) textures: &'f mut live::Live,
    /// The frame's texture names by handle, and what this pass declared:
    /// the only textures its handles resolve to (handles.rs).
    pub(crate) texture_names: &'f [String],
    pub(crate) reads: &'f [String],
    pub(crate) writes: &'f [(String, TextureDesc)],
    /// This frame's temporaries a history may trade textures with (not
    /// handed to the caller, not permanent): see `history.rs`.
    pub(crate) tradable: &'f FxHashSet<String>,
    /// The step at which each texture is last read or written, the names
    /// the caller asked for, and this pass's step: whether its outputs are
    /// read ([`PassContext::is_read`]).
    pub(crate) last_use: &'f FxHashMap<String, usize>,
    pub(crate) requested: &'f FxHashSet<String>,
    pub(crate) step: usize,
    pub(crate) handovers: Vec<history::Handover>,
    pub(crate) views: &'f std::cell::RefCell<crate::texture_pool::ViewCache>,
    pub(crate) fresh: &'f FxHashSet<String>,
    pub(crate) timestamps: Option<&'f wgpu::QuerySet>,
    pub(crate) queries: PassQueries,
    pub(crate) next_query: &'f mut u32,
    pub(crate) query_capacity: u32,
    /// Draw calls recorded (raster passes count theirs here).
    pub draws: u64,
    pub output_size: (u32, u32),
    /// What the pass decided, by name (shadow maps rendered, reused, culled...): summed into the frame report.
    pub(crate) counters: PassCounters,
    /// Whether the pass asked for the encoder itself (a render pass, a copy,
    /// a clear), ending the open compute pass: such passes go first in
    /// their wave next frame (waves.rs).
    pub(crate) used_encoder: bool,
}

/// A pass's timestamp query pairs, inline: a pass writes one or a few, and
/// each pass allocated a Vec for them every timed frame (issue 33).
pub(crate) type PassQueries = smallvec::SmallVec<[(u32, u32); 4]>;

/// A pass's counters by name, inline and searched in order: a pass counts
/// under a name or two, and each allocated a map node every frame.
pub(crate) type PassCounters = smallvec::SmallVec<[(&'static str, u64); 4]>;

impl<'f> PassContext<'f> {
    /// A view of any texture (one the frame graph does not manage too, such
    /// as a node's shadow maps), made once and kept while frames use it.
    pub fn view_of(
        &self,
        texture: &wgpu::Texture,
        spec: crate::texture_pool::ViewSpec,
    ) -> wgpu::TextureView {
        self.views.borrow_mut().view_of(texture, spec)
    }

    /// A sampler of kind `sampling`, made once per kind and kept by the
    /// shader cache, so passes neither make one each frame nor clone the
    /// device to ask the cache for it.
    pub fn sampler(&mut self, sampling: crate::shaders::Sampling) -> wgpu::Sampler {
        self.shaders.sampler(&self.gpu.device, sampling)
    }

    /// Add `n` to the frame report's counter `name`: how passes show the work
    /// they did and the work they saved.
    pub fn count(&mut self, name: &'static str, n: u64) {
        match self
            .counters
            .iter_mut()
            .find(|(counted, _)| *counted == name)
        {
            Some((_, count)) => *count += n,
            None => self.counters.push((name, n)),
        }
    }

    /// Whether this pass's output `tex` is read: by a later pass of this
    /// frame (its last use comes after this pass's write), or by the caller.
    /// A pass runs when any of its outputs is read; one with several can
    /// leave out the work of an output nobody reads (its texture is still
    /// allocated, and left unwritten).
    pub fn is_read(&self, tex: Tex) -> bool {
        self.declared(tex).is_ok_and(|name| {
            self.requested.contains(name) || self.last_use.get(name).is_some_and(|&s| s > self.step)
        })
    }

    /// A persistent texture this pass declared, created this frame: it holds no history yet.
    pub fn is_fresh(&self, tex: Tex) -> bool {
        self.declared(tex)
            .is_ok_and(|name| self.fresh.contains(name))
    }

    fn next_pair(&mut self) -> Option<(&'f wgpu::QuerySet, u32)> {
        let set = self.timestamps?;
        if *self.next_query + 2 > self.query_capacity {
            return None;
        }
        let begin = *self.next_query;
        *self.next_query += 2;
        self.queries.push((begin, begin + 1));
        Some((set, begin))
    }

    /// One compute dispatch, in the open compute pass ([`PassContext::compute_pass`]):
    /// the shape of most full-screen passes. `groups[i]` is bound at group i.
    pub fn dispatch(
        &mut self,
        label: &str,
        pipeline: &wgpu::ComputePipeline,
        groups: &[&wgpu::BindGroup],
        workgroups: (u32, u32, u32),
    ) {
        let pass = self.compute_pass(label);
        pass.set_pipeline(pipeline);
        for (index, group) in groups.iter().enumerate() {
            pass.set_bind_group(index as u32, *group, &[]);
        }
        pass.dispatch_workgroups(workgroups.0, workgroups.1, workgroups.2);
    }

    /// Timestamp writes for a render pass of this graph pass.
    pub fn render_timestamps(&mut self) -> Option<wgpu::RenderPassTimestampWrites<'f>> {
        self.next_pair()
            .map(|(query_set, i)| wgpu::RenderPassTimestampWrites {
                query_set,
                beginning_of_pass_write_index: Some(i),
                end_of_pass_write_index: Some(i + 1),
            })
    }
}

/// A frame being described; [`FrameGraph::execute`] runs it.
pub struct FrameGraph<'a> {
    output_size: (u32, u32),
    passes: Vec<PassEntry<'a>>,
    requested: Vec<String>,
    /// Textures handed back if the frame makes them anyway ([`FrameGraph::watch`]).
    watched: Vec<String>,
    imports: FxHashMap<String, wgpu::Texture>,
    included: FxHashSet<u64>,
    /// Texture names by handle ([`Tex`]), and handles by name.
    texture_names: Vec<String>,
    handles: handles::HandleTable,
    counters: BTreeMap<&'static str, u64>,
    /// Pairs of passes that run as one when both are needed (merge.rs).
    merges: Vec<merge::Merge<'a>>,
    /// Pipelines its passes will dispatch or draw with, announced (gather.rs).
    pipelines: Vec<crate::shaders::pipelines_ahead::Job>,
    /// Those announced for a pass that may be culled or merged (gather.rs).
    pipelines_if_run: Vec<gather::IfRun>,
    /// Those whose entry point follows which outputs are read (gather.rs).
    pipelines_if_read: Vec<gather::IfRead>,
}

thread_local! {
    /// How many passes, textures and recipes the last graph planned on this
    /// thread declared: the next is sized for as many up front (it grew
    /// its vectors and maps step by step, a score of allocations a frame).
    static LAST_SIZES: std::cell::Cell<(usize, usize, usize)> =
        const { std::cell::Cell::new((0, 0, 0)) };
}

impl<'a> FrameGraph<'a> {
    pub fn new(output_size: (u32, u32)) -> Self {
        let (passes, textures, recipes) = LAST_SIZES.get();
        FrameGraph {
            output_size: (output_size.0.max(1), output_size.1.max(1)),
            passes: Vec::with_capacity(passes),
            requested: Vec::new(),
            watched: Vec::new(),
            imports: FxHashMap::default(),
            included: FxHashSet::with_capacity_and_hasher(recipes, Default::default()),
            texture_names: Vec::with_capacity(textures),
            handles: handles::HandleTable::with_capacity_and_hasher(textures, Default::default()),
            counters: BTreeMap::new(),
            merges: Vec::new(),
            pipelines: Vec::new(),
            pipelines_if_run: Vec::new(),
            pipelines_if_read: Vec::new(),
        }
    }

    /// Remember this graph's sizes for the next one made on this thread.
    fn note_sizes(&self) {
        LAST_SIZES.set((
            self.passes.len(),
            self.texture_names.len(),
            self.included.len(),
        ));
    }

    /// Count a decision made while declaring (work a recipe left out
    /// altogether, such as an effect no material needs): it reaches the
    /// frame report's counters like those passes count.
    pub fn count(&mut self, name: &'static str, n: u64) {
        *self.counters.entry(name).or_default() += n;
    }

    pub fn output_size(&self) -> (u32, u32) {
        self.output_size
    }

    /// Ask for a texture: only the passes it depends on will run.
    pub fn request(&mut self, name: &str) {
        self.requested.push(name.to_owned());
    }

    /// Watch a texture: hand it back if the frame makes it anyway, without
    /// changing the frame (a request keeps its pass from being culled or
    /// merged into the next, makes its texture readable, keeps it from
    /// trading with a history and from being handed to a later pass). It is
    /// handed back when a pass that ran wrote it and a later pass read it,
    /// and it can be sampled; it is kept to the end of the frame, the one
    /// difference a watch makes. A watched texture that no pass of the frame
    /// needs is made for the watch alone, as a request: its passes are the
    /// watch's own. One merged into the next pass (`chains_into`), or an
    /// output that no pass reads (left unwritten), is not handed back: the
    /// caller asks for it with [`FrameGraph::request`] when it must have it.
    pub fn watch(&mut self, name: &str) {
        self.watched.push(name.to_owned());
    }

    /// Make an outside texture readable by passes under `name`.
    pub fn import(&mut self, name: &str, texture: wgpu::Texture) {
        self.imports.insert(name.to_owned(), texture);
    }

    /// True the first time an id is included: a recipe declares its passes only once per frame.
    pub fn include(&mut self, id: u64) -> bool {
        self.included.insert(id)
    }

    /// Whether recipe `id` was included already (declared, or being declared).
    pub fn included(&self, id: u64) -> bool {
        self.included.contains(&id)
    }

    /// The texture `name` will be, before the frame runs: written by a pass
    /// (its descriptor at this frame's size, readable if requested) or
    /// imported. For a sink to refuse what it could not read back before
    /// any work is done.
    pub fn planned(&self, name: &str) -> Option<TextureKey> {
        if let Some(texture) = self.imports.get(name) {
            return Some(TextureKey {
                format: texture.format(),
                width: texture.width(),
                height: texture.height(),
                usage: texture.usage(),
            });
        }
        let mut key = self.resolve(self.declared(name)?);
        if self.requested.iter().any(|r| r == name) {
            key.usage |= READABLE;
        }
        Some(key)
    }

    /// The size of an image effect's output whose source is texture `name`
    /// (declared before this call, as recipes declare their sources first):
    /// the source's own, as vvvv's texture effects keep their input's size.
    /// An imported texture (a FileTexture) gives its pixels, a pass's output
    /// its size rule (a frame-size chain `Relative(1.0)`, as before this
    /// rule, a shader node's target its size, a DeferredBase of a fixed
    /// size its G-buffer's); a texture nothing declared (a persistent one
    /// from last frame) the frame's size. The effects read their source
    /// texel for texel, so this is what keeps a source of another size from
    /// landing in one corner of a black frame. The one place the rule lives
    /// (docs/post.md, "Sizes").
    pub fn effect_size(&self, name: &str) -> SizeRule {
        if let Some(texture) = self.imports.get(name) {
            return SizeRule::Absolute {
                width: texture.width(),
                height: texture.height(),
            };
        }
        self.declared(name)
            .map_or(SizeRule::Relative(1.0), |d| d.size)
    }

    /// How the pass that writes `name` declared it (a name has one writer:
    /// `schedule` refuses two).
    fn declared(&self, name: &str) -> Option<&TextureDesc> {
        let h = self.handle_of(name)?;
        self.passes.iter().find_map(|p| {
            let at = p.handles.writes.iter().position(|&w| w == h)?;
            p.descs.get(at)
        })
    }

    pub fn resolve(&self, desc: &TextureDesc) -> TextureKey {
        let (width, height) = desc.size.pixels(self.output_size);
        TextureKey {
            format: desc.format,
            width,
            height,
            usage: desc.usage,
        }
    }

    /// Which passes run, in order, and which are culled.
    fn schedule(
        &self,
        persistent: &dyn Fn(&str) -> bool,
    ) -> Result<(Vec<usize>, Vec<usize>), RenderError> {
        // Sized once: a frame of ~50 passes grew these maps and vectors
        // step by step (1% of the recording thread in session 11's profile).
        let mut producer: FxHashMap<&str, usize> = FxHashMap::with_capacity_and_hasher(
            self.passes.iter().map(|p| p.writes.len()).sum(),
            Default::default(),
        );
        for (i, pass) in self.passes.iter().enumerate() {
            for (name, _) in &pass.writes {
                if let Some(other) = producer.insert(name, i) {
                    return Err(RenderError::Graph(format!(
                        "`{name}` is written by two passes, `{}` and `{}`",
                        self.passes[other].name.text(self.passes[other].owner),
                        pass.name.text(pass.owner)
                    )));
                }
            }
        }
        let available = |name: &str| self.imports.contains_key(name) || persistent(name);
        let mut live = vec![false; self.passes.len()];
        // What to keep, and which pass reads it (for the error when none writes it).
        let mut stack: Vec<(&str, Option<usize>)> =
            self.requested.iter().map(|n| (n.as_str(), None)).collect();
        while let Some((name, reader)) = stack.pop() {
            match producer.get(name) {
                Some(&p) => {
                    if !live[p] {
                        live[p] = true;
                        stack.extend(self.passes[p].reads.iter().map(|r| (r.as_str(), Some(p))));
                    }
                }
                None if available(name) => {}
                None => {
                    return Err(RenderError::Graph(match reader {
                        Some(p) => format!(
                            "pass `{}` reads `{name}`, which no pass writes",
                            self.passes[p].name.text(self.passes[p].owner)
                        ),
                        None => format!("`{name}` was requested, but no pass writes it"),
                    }));
                }
            }
        }
        // Kahn's order over live passes, keeping declaration order where free.
        let mut indegree = vec![0usize; self.passes.len()];
        let mut dependents: Vec<Vec<usize>> = vec![Vec::new(); self.passes.len()];
        for (i, pass) in self.passes.iter().enumerate().filter(|(i, _)| live[*i]) {
            for read in &pass.reads {
                if let Some(&p) = producer.get(read.as_str()) {
                    indegree[i] += 1;
                    dependents[p].push(i);
                }
            }
        }
        let mut order = Vec::with_capacity(self.passes.len());
        let mut ready: std::collections::BTreeSet<usize> = (0..self.passes.len())
            .filter(|&i| live[i] && indegree[i] == 0)
            .collect();
        while let Some(i) = ready.pop_first() {
            order.push(i);
            for &d in &dependents[i] {
                indegree[d] -= 1;
                if indegree[d] == 0 {
                    ready.insert(d);
                }
            }
        }
        if order.len() != live.iter().filter(|l| **l).count() {
            return Err(RenderError::Graph(
                "the passes read each other's outputs in a cycle".to_owned(),
            ));
        }
        let culled = (0..self.passes.len()).filter(|&i| !live[i]).collect();
        Ok((order, culled))
    }
}

/// The parts of a frame graph the renderer's executor needs, taken apart.
pub(crate) struct GraphParts<'a> {
    /// Per pass: its name as fields, and as text for people (with its owner).
    pub labels: Vec<PassName>,
    pub names: Vec<String>,
    pub owners: Vec<Option<u32>>,
    /// Per pass: the owner of another node's pass merged into it (merge.rs).
    pub partners: Vec<Option<u32>>,
    pub reads: Vec<Vec<String>>,
    pub writes: Vec<Vec<(String, TextureDesc)>>,
    pub runs: Vec<Option<PassFn<'a>>>,
    pub order: Vec<usize>,
    /// With [`PassOrder::Waves`], per step of `order`: the last step of its
    /// wave (waves.rs); empty in declaration order.
    pub wave_end: Vec<usize>,
    pub culled: Vec<usize>,
    pub requested: Vec<String>,
    /// Watched textures that no request names ([`FrameGraph::watch`]).
    pub watched: Vec<String>,
    pub imports: FxHashMap<String, wgpu::Texture>,
    /// Inline: a pass writes a few textures, and a Vec each was a pass's allocation a frame.
    pub keys: Vec<smallvec::SmallVec<[TextureKey; 4]>>,
    pub counters: BTreeMap<&'static str, u64>,
    /// Texture names by handle.
    pub texture_names: Vec<String>,
    /// The merges that applied (merge.rs), for a kept plan (plan.rs).
    pub merged: Vec<merge::Applied>,
    /// Names live passes read, or the caller requested, that no pass
    /// writes and none imports: persistent textures the frame needs.
    pub outside: Vec<String>,
}

impl<'a> FrameGraph<'a> {
    pub(crate) fn into_parts(
        mut self,
        persistent: &dyn Fn(&str) -> bool,
        pass_order: PassOrder,
        encoder_first: &dyn Fn(&str) -> bool,
    ) -> Result<GraphParts<'a>, RenderError> {
        // The passes' reads and writes by name, from their handles.
        let names = &self.texture_names;
        for pass in &mut self.passes {
            let name = |h: &u32| names[*h as usize].clone();
            pass.reads = pass.handles.reads.iter().map(name).collect();
            pass.writes = (pass.handles.writes.iter().map(name))
                .zip(pass.descs.iter().copied())
                .collect();
        }
        let (mut order, mut culled) = self.schedule(persistent)?;
        // A watched texture no pass of the frame makes is made for the watch
        // alone: requested. The frame's own passes are scheduled as before,
        // and what they make is only watched.
        if !self.watched.is_empty() {
            let made: FxHashSet<&str> = order
                .iter()
                .flat_map(|&p| self.passes[p].writes.iter().map(|(n, _)| n.as_str()))
                .collect();
            let alone: Vec<String> = self
                .watched
                .iter()
                .filter(|w| !made.contains(w.as_str()) && !self.requested.contains(w))
                .cloned()
                .collect();
            if !alone.is_empty() {
                self.requested.extend(alone);
                (order, culled) = self.schedule(persistent)?;
            }
            let requested = &self.requested;
            self.watched.retain(|w| !requested.contains(w));
            self.watched.dedup();
        }
        // What a kept plan needs to exist (plan.rs): what scheduling found
        // available outside the frame.
        let mut outside: Vec<String> = Vec::new();
        {
            let written = |name: &str| {
                order
                    .iter()
                    .any(|&p| self.passes[p].writes.iter().any(|(w, _)| w == name))
            };
            let needed = self
                .requested
                .iter()
                .chain(order.iter().flat_map(|&p| &self.passes[p].reads));
            for name in needed {
                if !written(name) && !self.imports.contains_key(name) && !outside.contains(name) {
                    outside.push(name.clone());
                }
            }
        }
        // What the caller gets back, any sink must be able to read: copy
        // it (Output's readback) or sample it (the editor's viewport).
        let keys = self
            .passes
            .iter()
            .map(|p| {
                p.writes
                    .iter()
                    .map(|(name, d)| {
                        let mut key = self.resolve(d);
                        if self.requested.contains(name) {
                            key.usage |= READABLE;
                        }
                        key
                    })
                    .collect()
            })
            .collect();
        let n = self.passes.len();
        let mut parts = GraphParts {
            labels: Vec::with_capacity(n),
            names: Vec::with_capacity(n),
            owners: Vec::with_capacity(n),
            partners: Vec::with_capacity(n),
            reads: Vec::with_capacity(n),
            writes: Vec::with_capacity(n),
            runs: Vec::with_capacity(n),
            order,
            wave_end: Vec::new(),
            culled,
            requested: self.requested,
            watched: self.watched,
            imports: self.imports,
            keys,
            counters: self.counters,
            texture_names: self.texture_names,
            merged: Vec::new(),
            outside,
        };
        for pass in self.passes {
            parts.names.push(pass.name.text(pass.owner));
            parts.labels.push(pass.name);
            parts.owners.push(pass.owner);
            parts.partners.push(None);
            parts.reads.push(pass.reads);
            parts.writes.push(pass.writes);
            parts.runs.push(Some(pass.run));
        }
        // Merges first, in declaration order, so that both orders merge the
        // same passes (and so render the same images).
        merge::apply(&mut parts, self.merges);
        if pass_order == PassOrder::Waves {
            let first = |p: usize| encoder_first(&parts.names[p]);
            (parts.order, parts.wave_end) =
                waves::in_waves(&parts.order, &parts.reads, &parts.writes, &first);
        }
        Ok(parts)
    }
}

/// What a pass recorded, for the executor (which finishes the encoder: a
/// batched frame shares one between passes).
pub(crate) struct Recorded {
    pub encoder: wgpu::CommandEncoder,
    /// The pass asked for the encoder itself ([`PassContext::used_encoder`]).
    pub used_encoder: bool,
    /// The compute pass left open for the next graph pass on this encoder.
    pub compute: Option<compute_pass::OpenCompute>,
    pub queries: PassQueries,
    pub draws: u64,
    pub counters: PassCounters,
    pub handovers: Vec<history::Handover>,
}

impl PassContext<'_> {
    pub(crate) fn finish(mut self) -> Recorded {
        self.close_graph_pass();
        Recorded {
            encoder: self.encoder,
            used_encoder: self.used_encoder,
            compute: self.compute,
            queries: self.queries,
            draws: self.draws,
            counters: self.counters,
            handovers: self.handovers,
        }
    }
}
