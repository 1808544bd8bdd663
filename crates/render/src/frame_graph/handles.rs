//! Typed handles: a pass is declared once, and its run reaches only what it declared.
//!
//! As in Frostbite's FrameGraph, declaring a pass hands back a [`Tex`] for
//! each texture it reads or writes, and the run resolves those handles
//! (`PassContext::view`, `PassContext::texture`): a handle of a texture the
//! pass did not declare is an error, never another pass's memory. Names
//! stay the graph's identity of a texture across recipes and frames
//! (a recipe's output, a persistent history); a pass writes each name once,
//! in its declaration.
//!
//! ```ignore
//! let mut pass = fg.pass(PassName::new("SSAO").step("blur x"), owner);
//! let source = pass.read(&raw);
//! let depth = pass.read(&g.depth);
//! let blurred = pass.write(&self.name("blurred"), desc);
//! pass.run(move |cx| cx.dispatch_image("ao blur x", &key, Bindings::new()
//!     .texture("source", source).texture("depth", depth).texture("output", blurred), size));
//! ```

use super::{FrameGraph, PassContext, PassEntry, PassName, TextureDesc};
use crate::error::RenderError;

/// A texture of the frame graph a pass declared. Copy, and only good in
/// the runs of the passes that declared it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Tex(pub(super) u32);

/// A pass being declared: [`PassBuilder::read`] and [`PassBuilder::write`]
/// give handles, [`PassBuilder::run`] adds it to the graph.
#[must_use = "a pass is added to the graph by `run`"]
pub struct PassBuilder<'g, 'a> {
    graph: &'g mut FrameGraph<'a>,
    name: PassName,
    owner: Option<u32>,
    /// What it reads and writes, as handles (the names are the graph's
    /// `texture_names`: not copied into each pass every frame), and how it
    /// declared each write.
    handles: super::PassHandles,
    descs: smallvec::SmallVec<[TextureDesc; 4]>,
    /// What the pass binds, named where it was declared (bound.rs).
    pub(super) bindings: super::Bindings<'a>,
}

impl<'a> FrameGraph<'a> {
    /// Begin declaring a pass `name` (its effect and step, for reports and
    /// captures) of node `owner` (whose errors it reports).
    pub fn pass(&mut self, name: impl Into<PassName>, owner: Option<u32>) -> PassBuilder<'_, 'a> {
        PassBuilder {
            graph: self,
            name: name.into(),
            owner,
            handles: Default::default(),
            descs: Default::default(),
            bindings: super::Bindings::new(),
        }
    }

    /// The handle of texture `name`, the same for every pass of this frame.
    /// A run resolves it only where its pass declared `name`: for the joint
    /// run of two passes ([`FrameGraph::chains_into`]), which holds the
    /// reads and writes of both, where each was declared by its own recipe.
    pub fn handle(&mut self, name: &str) -> Tex {
        let hash = name_hash(name);
        if let Some(id) = self.handle_hashed(hash, name) {
            return Tex(id);
        }
        let id = self.texture_names.len() as u32;
        self.texture_names.push(name.to_owned());
        self.handles.entry(hash).or_default().push(id);
        Tex(id)
    }

    /// The handle of `name`, if a pass declared it.
    pub(super) fn handle_of(&self, name: &str) -> Option<u32> {
        self.handle_hashed(name_hash(name), name)
    }

    fn handle_hashed(&self, hash: u64, name: &str) -> Option<u32> {
        let ids = self.handles.get(&hash)?;
        ids.iter()
            .copied()
            .find(|&id| self.texture_names[id as usize] == name)
    }
}

/// Handles by their name's hash (names that share one, in a list): the
/// names live once, in `texture_names`, instead of a second copy a name a
/// frame as a map's keys.
pub(super) type HandleTable = rustc_hash::FxHashMap<u64, smallvec::SmallVec<[u32; 1]>>;

fn name_hash(name: &str) -> u64 {
    use std::hash::{Hash, Hasher};
    let mut hasher = rustc_hash::FxHasher::default();
    name.hash(&mut hasher);
    hasher.finish()
}

impl<'a> PassBuilder<'_, 'a> {
    /// The pass reads `name`: another pass writes it, or it is imported or persistent.
    pub fn read(&mut self, name: &str) -> Tex {
        let tex = self.graph.handle(name);
        if !self.handles.reads.contains(&tex.0) {
            self.handles.reads.push(tex.0);
        }
        tex
    }

    /// Reads of an optional input: `None` stays `None`.
    pub fn read_opt(&mut self, name: Option<&str>) -> Option<Tex> {
        name.map(|n| self.read(n))
    }

    /// The pass writes `name`, which the graph creates as `desc` says.
    pub fn write(&mut self, name: &str, desc: TextureDesc) -> Tex {
        let tex = self.graph.handle(name);
        self.descs.push(desc);
        self.handles.writes.push(tex.0);
        tex
    }

    /// The pass will dispatch `entry` of `key` (gather.rs): made on a thread
    /// ahead of the frame's recording where it is not made yet.
    pub fn will_dispatch(&mut self, key: &crate::shaders::ShaderKey, entry: &'static str) {
        self.graph.will_dispatch(key, entry);
    }

    /// The pass will draw with `key`'s render pipeline `variant`, which
    /// `build` makes (gather.rs, [`FrameGraph::will_render`]).
    pub fn will_render(
        &mut self,
        key: &crate::shaders::ShaderKey,
        variant: &str,
        build: crate::shaders::pipelines_ahead::RenderBuild,
    ) {
        self.graph.will_render(key, variant, build);
    }

    /// The graph the pass is declared in (its output size, counters).
    pub fn graph(&self) -> &FrameGraph<'a> {
        self.graph
    }

    /// Add the pass, with the code that records it.
    pub fn run(self, run: impl FnOnce(&mut PassContext<'_>) -> Result<(), RenderError> + 'a) {
        self.graph.passes.push(PassEntry {
            name: self.name,
            owner: self.owner,
            reads: Vec::new(),
            writes: Vec::new(),
            handles: self.handles,
            descs: self.descs,
            run: Box::new(run),
        });
    }
}

impl PassContext<'_> {
    /// The name of a texture this pass declared; an error for any other.
    pub(super) fn declared(&self, tex: Tex) -> Result<&str, RenderError> {
        let name = self
            .texture_names
            .get(tex.0 as usize)
            .map(String::as_str)
            .ok_or_else(|| RenderError::Graph(format!("{tex:?} is not of this frame")))?;
        let declared =
            self.reads.iter().any(|r| r == name) || self.writes.iter().any(|(w, _)| w == name);
        if !declared {
            return Err(RenderError::Graph(format!(
                "a pass used `{name}`, which it did not declare"
            )));
        }
        Ok(name)
    }

    /// A texture this pass declared.
    pub fn texture(&self, tex: Tex) -> Result<&wgpu::Texture, RenderError> {
        self.live(self.declared(tex)?)
    }

    /// The live texture of a name the caller checked this pass declared.
    pub(super) fn live(&self, name: &str) -> Result<&wgpu::Texture, RenderError> {
        self.textures
            .get(name)
            .ok_or_else(|| RenderError::Graph(format!("texture `{name}` is not available here")))
    }

    /// Its default view, made once per texture and kept while frames use it.
    pub fn view(&self, tex: Tex) -> Result<wgpu::TextureView, RenderError> {
        let texture = self.texture(tex)?;
        Ok(self.views.borrow_mut().view(texture))
    }

    /// Its size in pixels.
    pub fn size_of(&self, tex: Tex) -> Result<(u32, u32), RenderError> {
        let t = self.texture(tex)?;
        Ok((t.width(), t.height()))
    }
}
