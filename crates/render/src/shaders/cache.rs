//! The permutation cache: shader modules, pipelines, samplers and bind
//! groups, each made once and counted.

use rustc_hash::FxHashMap;
use std::borrow::Cow;

use std::sync::Arc;

use super::BindGroups;
use super::reflection::{GroupEntries, Reflection, match_bindings, reflect};
use super::{ShaderComposer, ShaderKey, Splice};
use crate::error::RenderError;
use crate::shaders::generated::GeneratedKey;
use crate::shaders::pipelines_ahead::{AheadStats, Job, Made, PipelineId, PipelinesAhead};

/// A compute pipeline of `entry` in `module`, its bind group layouts derived
/// from the shader (also what `crate::shaders::pipelines_ahead` makes, the same way).
pub(crate) fn compute_pipeline_of(
    device: &wgpu::Device,
    cache: Option<&wgpu::PipelineCache>,
    module: &wgpu::ShaderModule,
    label: &str,
    entry: &str,
) -> wgpu::ComputePipeline {
    device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some(label),
        layout: None,
        module,
        entry_point: Some(entry),
        compilation_options: Default::default(),
        cache,
    })
}

/// How a pass samples a texture.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Sampling {
    /// Bilinear, tiling past 0..1 (surface textures mapped by UV).
    LinearRepeat,
    /// Bilinear, held at the edges (projected textures).
    LinearClamp,
}

/// A render pipeline's stage names and their merged reflection.
type MergedStages = (Vec<String>, Arc<Reflection>);

/// Compiled shader modules and pipelines, keyed by permutation. Counts what it
/// compiles, so the frame statistics show when a frame had to compile.
pub struct ShaderCache {
    /// Made when first needed ([`ShaderCache::lazy`]): naga_oil reading
    /// the libraries is CPU a renderer whose permutations were all composed
    /// ahead (`crate::precompose`) never spends.
    composer: Option<ShaderComposer>,
    modules: FxHashMap<ShaderKey, wgpu::ShaderModule>,
    /// Per permutation and entry point: its resource variables by name and
    /// which it uses. (Keyed by permutation, then entry: a look-up borrows
    /// the key, as every pass makes several a frame.)
    reflections: FxHashMap<ShaderKey, FxHashMap<String, Arc<Reflection>>>,
    /// Per permutation, a render pipeline's stages merged into one
    /// reflection (a variable used where any stage uses it): merged once,
    /// not at every bind (it cloned every variable's name, each frame).
    merged: FxHashMap<ShaderKey, Vec<MergedStages>>,
    /// Per shader file: every resource variable its source (or a library)
    /// declares under any feature, to tell a compiled-out name from a typo.
    declared: FxHashMap<&'static str, rustc_hash::FxHashSet<String>>,
    compute: FxHashMap<ShaderKey, FxHashMap<&'static str, wgpu::ComputePipeline>>,
    /// Per permutation, then variant (looked up by borrowing both).
    render: FxHashMap<ShaderKey, FxHashMap<String, wgpu::RenderPipeline>>,
    samplers: FxHashMap<Sampling, wgpu::Sampler>,
    /// Pipelines of shaders no typed key declares (shader node files), by the caller's key and entry.
    external: FxHashMap<(u64, String), wgpu::ComputePipeline>,
    /// Resolve permutations composed with a shader node material, by its source key.
    surfaces: FxHashMap<(ShaderKey, u64), SplicedPipeline>,
    /// Pipelines of generated shaders (the fused light loop), by the caller's key.
    generated: FxHashMap<u64, SplicedPipeline>,
    /// Bind groups by pipeline, group and what they bind (by identity), with
    /// the frame they were last used in: a pass that binds what it bound
    /// last frame reuses its group instead of making one. Under the hash of
    /// that key, so a look-up hashes the resources it is given and compares
    /// them in place, without building (allocating, cloning) a key.
    bind_groups: FxHashMap<u64, Vec<CachedGroup>>,
    frame: u64,
    /// Sources swapped in since the cache was made ([`ShaderCache::replace_sources`]):
    /// what a pipeline or bind group held outside the cache was resolved under.
    pub(crate) generation: u64,
    /// Pipelines compiled since the cache was made: by the cache itself,
    /// or on threads ahead of the look-up (`crate::shaders::pipelines_ahead`), of
    /// which those are `pipelines_taken_ahead`.
    pub pipelines_compiled: u64,
    pub pipelines_taken_ahead: u64,
    /// What those the cache made itself were (the rest were taken from
    /// threads): their labels, in the order made (`cold_start`'s
    /// `made_at_frame`, to see what is still left to a first frame).
    pub made_here: Vec<String>,
    /// Bind groups made and reused since the cache was made.
    pub bind_groups_created: u64,
    pub bind_groups_reused: u64,
    /// Where the time making shaders and pipelines went since the cache was made.
    pub compile_times: CompileTimes,
    /// The driver's cache kept on disk between runs (pipeline_cache.rs), if
    /// the device has one: every pipeline is compiled through it.
    pipeline_cache: Option<wgpu::PipelineCache>,
    /// Compute pipelines being made ahead on threads, from the last run's
    /// list (`crate::shaders::pipelines_ahead`): a look-up takes one from there
    /// before making its own.
    ahead: Option<PipelinesAhead>,
    /// Compute pipelines a frame's passes announced, being made on threads
    /// while it records (`frame_graph/gather.rs`), until the frame ends; and
    /// what those threads did, summed.
    frame_ahead: Vec<PipelinesAhead>,
    frame_ahead_done: AheadStats,
    /// Compute pipelines (a permutation's entry points, generated shaders)
    /// in the order first looked up: what the next run creates ahead, in
    /// the order its frame will want them.
    compute_order: Vec<PipelineId>,
}

/// CPU time spent making shaders and pipelines, by step: most of what a
/// fresh process's first frame costs (`spreadlight bench --json`'s
/// `cold_start`, `render --timings`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CompileTimes {
    /// naga_oil composing permutations (preprocessing, naga's parse and
    /// validation); a permutation composed once is reused by every renderer of the process.
    pub compose: std::time::Duration,
    /// Shader modules made from composed naga modules (wgpu validates them again).
    pub modules: std::time::Duration,
    /// The composer made (naga_oil reading the libraries), once per cache at most.
    pub libraries: std::time::Duration,
    /// Permutations this cache composed itself.
    pub composed: u64,
    /// Look-ups (a module's, a reflection's) that found their permutation
    /// composed already in the process (by `crate::precompose`'s threads,
    /// by another renderer, or by this cache for another look-up).
    pub ready: u64,
    /// Pipelines made (naga's backend writes the driver's language, the driver compiles it).
    pub pipelines: std::time::Duration,
}

/// `work`'s result, its time added to `total`.
fn timed<T>(total: &mut std::time::Duration, work: impl FnOnce() -> T) -> T {
    let started = std::time::Instant::now();
    let value = work();
    *total += started.elapsed();
    value
}

/// A pipeline composed with a shader node material, and its reflection.
type SplicedPipeline = (wgpu::ComputePipeline, Arc<Reflection>);

/// A resource a bind group binds, by identity (wgpu handles compare by the object).
#[derive(Clone, PartialEq, Eq, Hash)]
enum Bound {
    Buffer(wgpu::Buffer, u64, Option<wgpu::BufferSize>),
    View(wgpu::TextureView),
    Sampler(wgpu::Sampler),
}

impl Bound {
    /// None for resources the cache does not key (arrays of them).
    fn of(resource: &wgpu::BindingResource<'_>) -> Option<Bound> {
        match resource {
            wgpu::BindingResource::Buffer(b) => {
                Some(Bound::Buffer(b.buffer.clone(), b.offset, b.size))
            }
            wgpu::BindingResource::TextureView(v) => Some(Bound::View((*v).clone())),
            wgpu::BindingResource::Sampler(s) => Some(Bound::Sampler((*s).clone())),
            _ => None,
        }
    }
}

/// The pipeline whose derived layout a cached bind group was made for.
#[derive(Clone, PartialEq, Eq, Hash)]
pub enum PipelineRef {
    Compute(wgpu::ComputePipeline),
    Render(wgpu::RenderPipeline),
}

impl PipelineRef {
    fn layout(&self, group: u32) -> wgpu::BindGroupLayout {
        match self {
            PipelineRef::Compute(p) => p.get_bind_group_layout(group),
            PipelineRef::Render(p) => p.get_bind_group_layout(group),
        }
    }
}

type BindGroupKey = (PipelineRef, u32, Vec<(u32, Bound)>);

struct CachedGroup {
    key: BindGroupKey,
    group: wgpu::BindGroup,
    /// The frame it was last bound in.
    last: u64,
}

/// The hash a bind group is cached under: its pipeline, group index and
/// the resources of `entries` by identity; None where one is not keyed
/// (arrays of resources), so the group is made each time.
fn group_hash(
    pipeline: &PipelineRef,
    group: u32,
    entries: &[wgpu::BindGroupEntry<'_>],
) -> Option<u64> {
    use std::hash::{Hash, Hasher};
    let mut hasher = rustc_hash::FxHasher::default();
    (pipeline, group).hash(&mut hasher);
    for e in entries {
        e.binding.hash(&mut hasher);
        match &e.resource {
            wgpu::BindingResource::Buffer(b) => (0u8, b.buffer, b.offset, b.size).hash(&mut hasher),
            wgpu::BindingResource::TextureView(v) => (1u8, *v).hash(&mut hasher),
            wgpu::BindingResource::Sampler(v) => (2u8, *v).hash(&mut hasher),
            _ => return None,
        }
    }
    Some(hasher.finish())
}

/// Whether a cached group's key is `pipeline`'s group `group` over exactly
/// the resources of `entries`.
fn same_group(
    key: &BindGroupKey,
    pipeline: &PipelineRef,
    group: u32,
    entries: &[wgpu::BindGroupEntry<'_>],
) -> bool {
    key.0 == *pipeline
        && key.1 == group
        && key.2.len() == entries.len()
        && key.2.iter().zip(entries).all(|((binding, bound), e)| {
            *binding == e.binding
                && match (bound, &e.resource) {
                    (Bound::Buffer(buffer, offset, size), wgpu::BindingResource::Buffer(b)) => {
                        buffer == b.buffer && *offset == b.offset && *size == b.size
                    }
                    (Bound::View(view), wgpu::BindingResource::TextureView(v)) => view == *v,
                    (Bound::Sampler(sampler), wgpu::BindingResource::Sampler(v)) => sampler == *v,
                    _ => false,
                }
        })
}

/// Frames a cached bind group may go unused before it is dropped (with the
/// buffers and views it keeps alive): recipes re-made each frame make new
/// buffers, whose groups are never hit again.
const BIND_GROUP_IDLE_FRAMES: u64 = 2;

impl ShaderCache {
    pub fn new(composer: ShaderComposer) -> Self {
        ShaderCache {
            composer: Some(composer),
            ..ShaderCache::lazy()
        }
    }

    /// A cache over the embedded sources whose composer is made when a
    /// permutation is not composed already (`crate::precompose`).
    pub fn lazy() -> Self {
        ShaderCache {
            composer: None,
            modules: FxHashMap::default(),
            reflections: FxHashMap::default(),
            merged: FxHashMap::default(),
            declared: FxHashMap::default(),
            compute: FxHashMap::default(),
            render: FxHashMap::default(),
            samplers: FxHashMap::default(),
            external: FxHashMap::default(),
            surfaces: FxHashMap::default(),
            generated: FxHashMap::default(),
            bind_groups: FxHashMap::default(),
            frame: 0,
            generation: 0,
            pipelines_compiled: 0,
            pipelines_taken_ahead: 0,
            made_here: Vec::new(),
            bind_groups_created: 0,
            bind_groups_reused: 0,
            compile_times: CompileTimes::default(),
            pipeline_cache: None,
            ahead: None,
            frame_ahead: Vec::new(),
            frame_ahead_done: AheadStats::default(),
            compute_order: Vec::new(),
        }
    }

    /// Whether look-ups may take pipelines made on threads: over the
    /// embedded sources, as those threads compose (`crate::shaders::pipelines_ahead`).
    fn shares_embedded(&self) -> bool {
        self.composer
            .as_ref()
            .is_none_or(ShaderComposer::shares_embedded)
    }

    /// Start making, on threads, those of `wanted` (a frame's announced
    /// pipelines) that are neither made nor being made already.
    pub fn make_ahead(&mut self, device: &wgpu::Device, wanted: Vec<Job>) {
        if !self.shares_embedded() || !crate::shaders::pipelines_ahead::enabled() {
            return;
        }
        let mut missing: Vec<Job> = Vec::new();
        for job in wanted {
            let made = match &job.id {
                PipelineId::Entry(key, entry) => self
                    .compute
                    .get(key)
                    .is_some_and(|m| m.contains_key(entry.as_str())),
                // Looked up before (its map is keyed by the frame's hash).
                PipelineId::Generated(_) => self.compute_order.contains(&job.id),
                PipelineId::Render(key, variant) => self
                    .render
                    .get(key)
                    .is_some_and(|m| m.contains_key(variant.as_str())),
            };
            let making = self
                .ahead
                .iter()
                .chain(&self.frame_ahead)
                .any(|a| a.has(&job.id));
            if !made && !making && !missing.iter().any(|m| m.id == job.id) {
                missing.push(job);
            }
        }
        if missing.is_empty() {
            return;
        }
        self.frame_ahead.push(PipelinesAhead::start(
            device.clone(),
            self.pipeline_cache.clone(),
            missing,
            crate::shaders::pipelines_ahead::threads(),
        ));
    }

    /// `id` made ahead, taken from the threads' where they made it (over
    /// the embedded sources only, as those threads compose).
    fn take_ahead(&self, id: &PipelineId) -> Option<Made> {
        if !self.shares_embedded() {
            return None;
        }
        (self.ahead.iter().chain(&self.frame_ahead)).find_map(|a| a.take(id))
    }

    /// A frame ended: what its threads made and it did not take is let go
    /// once they are done (a later frame makes it if it needs it).
    pub fn end_frame_ahead(&mut self) {
        let done = &mut self.frame_ahead_done;
        self.frame_ahead.retain(|ahead| {
            let stats = ahead.stats();
            let running = stats.wall == std::time::Duration::ZERO;
            if !running {
                done.add(&stats);
            }
            running
        });
    }

    /// What the threads making frames' announced pipelines did so far
    /// (None: no frame announced one the cache lacked).
    pub fn pipelines_gathered(&self) -> Option<AheadStats> {
        let mut sum = self.frame_ahead_done;
        for ahead in &self.frame_ahead {
            sum.add(&ahead.stats());
        }
        (sum.listed > 0).then_some(sum)
    }

    /// Take compute pipelines from `ahead` where it made them (over the
    /// embedded sources: a cache over other sources ignores it).
    pub fn set_pipelines_ahead(&mut self, ahead: PipelinesAhead) {
        self.ahead = Some(ahead);
    }

    /// Wait until every thread making pipelines ahead (from the list, or
    /// announced by frames) ended: what they made is then in the driver's
    /// pipeline cache, for a host that saves it and ends.
    pub fn wait_ahead(&self) {
        for ahead in self.ahead.iter().chain(&self.frame_ahead) {
            ahead.wait();
        }
    }

    /// What creating pipelines ahead did, if this cache was given any.
    pub fn pipelines_ahead(&self) -> Option<AheadStats> {
        self.ahead.as_ref().map(PipelinesAhead::stats)
    }

    /// Every compute pipeline looked up so far, by permutation and entry
    /// point or generated shader, in the order first asked for.
    pub fn compute_pipelines_used(&self) -> &[PipelineId] {
        &self.compute_order
    }

    /// Compile every pipeline through `cache` (GpuContext::pipeline_cache).
    pub fn with_pipeline_cache(mut self, cache: Option<wgpu::PipelineCache>) -> Self {
        self.pipeline_cache = cache;
        self
    }

    /// A new frame begins: bind groups unused for a while are dropped.
    pub(crate) fn begin_frame(&mut self) {
        self.frame += 1;
        let frame = self.frame;
        self.bind_groups.retain(|_, groups| {
            groups.retain(|g| frame - g.last <= BIND_GROUP_IDLE_FRAMES);
            !groups.is_empty()
        });
    }

    /// Swap in new sources (live shader editing); everything compiled is dropped.
    pub fn replace_sources(&mut self, composer: ShaderComposer) {
        *self = ShaderCache {
            pipelines_compiled: self.pipelines_compiled,
            pipelines_taken_ahead: self.pipelines_taken_ahead,
            made_here: std::mem::take(&mut self.made_here),
            compile_times: self.compile_times,
            pipeline_cache: self.pipeline_cache.take(),
            generation: self.generation + 1,
            ..ShaderCache::new(composer)
        };
    }

    /// The composer, made the first time it is needed.
    fn composer(&mut self) -> Result<&mut ShaderComposer, RenderError> {
        let times = &mut self.compile_times;
        match &mut self.composer {
            Some(composer) => Ok(composer),
            slot @ None => {
                let made = timed(&mut times.libraries, ShaderComposer::new)?;
                Ok(slot.insert(made))
            }
        }
    }

    /// Permutation `key` composed: found composed in the process where the
    /// sources are the embedded ones, else composed here.
    fn compose(&mut self, key: &ShaderKey) -> Result<naga::Module, RenderError> {
        let shared = self
            .composer
            .as_ref()
            .is_none_or(ShaderComposer::shares_embedded);
        if shared
            && let Some(module) = timed(&mut self.compile_times.compose, || {
                super::composer::embedded_module_or_wait(key)
            })
        {
            self.compile_times.ready += 1;
            return Ok(module);
        }
        // Made first: its making is timed apart (`libraries`).
        self.composer()?;
        let started = std::time::Instant::now();
        let composed = self.composer()?.compose(key);
        self.compile_times.compose += started.elapsed();
        let module = composed?;
        self.compile_times.composed += 1;
        Ok(module)
    }

    pub fn module(
        &mut self,
        device: &wgpu::Device,
        key: &ShaderKey,
    ) -> Result<wgpu::ShaderModule, RenderError> {
        if let Some(m) = self.modules.get(key) {
            return Ok(m.clone());
        }
        let module = self.compose(key)?;
        let label = format!("{}{}", key.path(), key.describe_defs());
        let m = timed(&mut self.compile_times.modules, || {
            device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(&label),
                source: wgpu::ShaderSource::Naga(Cow::Owned(module)),
            })
        });
        self.modules.insert(key.clone(), m.clone());
        Ok(m)
    }

    /// `entry`'s resource variables in a permutation, by name, and which it
    /// uses (naga's reflection of the composed module).
    pub fn reflection(
        &mut self,
        key: &ShaderKey,
        entry: &str,
    ) -> Result<Arc<Reflection>, RenderError> {
        if let Some(found) = self.reflections.get(key).and_then(|by| by.get(entry)) {
            return Ok(found.clone());
        }
        let module = self.compose(key)?;
        let reflection =
            Arc::new(
                reflect(&module, entry).map_err(|message| RenderError::Shader {
                    shader: key.path().to_owned(),
                    defs: key.describe_defs(),
                    message,
                })?,
            );
        self.reflections
            .entry(key.clone())
            .or_default()
            .insert(entry.to_owned(), reflection.clone());
        Ok(reflection)
    }

    /// Bind groups 0..=last for a pipeline of `key`'s `entries` (one for
    /// compute, the stages of a render pipeline), from
    /// resources named by the WGSL variables they fill: what the
    /// permutation compiled out or leaves unused is dropped, a group the
    /// entry point skips is bound empty, and a name the shader never
    /// declares or a used variable left unbound is an error naming it.
    pub fn named_groups(
        &mut self,
        device: &wgpu::Device,
        key: &ShaderKey,
        entries: &[&str],
        pipeline: &PipelineRef,
        resources: &[(&str, wgpu::BindingResource<'_>)],
        prebuilt: &[(u32, wgpu::BindGroup)],
    ) -> Result<BindGroups, RenderError> {
        let reflection = match entries {
            [entry] => self.reflection(key, entry)?,
            _ => self.merged_reflection(key, entries)?,
        };
        let path = key.path();
        // A name the permutation lacks must be one the shader (or a library)
        // declares under some feature: compiled out, not a typo.
        let composer = &mut self.composer;
        let declared = self.declared.entry(path).or_insert_with(|| match composer {
            Some(composer) => composer.declared_names(key.file),
            None => super::composer::embedded_declared_names(key.file),
        });
        let matched = match_bindings(&reflection, resources, prebuilt, |name| {
            declared
                .contains(name)
                .then_some(())
                .ok_or_else(|| format!("a pass binds `{name}`, which the shader does not declare"))
        })
        .map_err(|message| RenderError::Shader {
            shader: path.to_owned(),
            defs: key.describe_defs(),
            message,
        })?;
        Ok(self.groups_of(device, pipeline, path, &matched, prebuilt))
    }

    /// The reflection of a render pipeline's stages `entries` together: a
    /// variable is used where any stage uses it.
    fn merged_reflection(
        &mut self,
        key: &ShaderKey,
        entries: &[&str],
    ) -> Result<Arc<Reflection>, RenderError> {
        let same = |stages: &[String]| {
            stages.len() == entries.len() && stages.iter().zip(entries).all(|(a, b)| a == b)
        };
        if let Some((_, found)) = self
            .merged
            .get(key)
            .and_then(|made| made.iter().find(|(stages, _)| same(stages)))
        {
            return Ok(found.clone());
        }
        let mut merged: Vec<super::ShaderVar> = Vec::new();
        for entry in entries {
            for var in self.reflection(key, entry)?.vars() {
                match merged.iter_mut().find(|v| v.name == var.name) {
                    Some(v) => v.used |= var.used,
                    None => merged.push(var.clone()),
                }
            }
        }
        let reflection = Arc::new(Reflection::new(merged));
        self.merged.entry(key.clone()).or_default().push((
            entries.iter().map(|e| (*e).to_owned()).collect(),
            reflection.clone(),
        ));
        Ok(reflection)
    }

    /// [`ShaderCache::named_groups`] for a pipeline reflected elsewhere (a
    /// resolve composed with a shader node material); every name must be
    /// one the module has or a variable it compiled out, which the caller vouches for.
    pub fn groups_by_name(
        &mut self,
        device: &wgpu::Device,
        label: &str,
        reflection: &Reflection,
        pipeline: &PipelineRef,
        resources: &[(&str, wgpu::BindingResource<'_>)],
        prebuilt: &[(u32, wgpu::BindGroup)],
    ) -> Result<BindGroups, String> {
        let matched = match_bindings(reflection, resources, prebuilt, |_| Ok(()))?;
        Ok(self.groups_of(device, pipeline, label, &matched, prebuilt))
    }

    /// Each group's bind group: the one made elsewhere, or a cached one of its entries.
    fn groups_of(
        &mut self,
        device: &wgpu::Device,
        pipeline: &PipelineRef,
        label: &str,
        matched: &[GroupEntries<'_>],
        prebuilt: &[(u32, wgpu::BindGroup)],
    ) -> BindGroups {
        matched
            .iter()
            .enumerate()
            .map(|(group, entries)| {
                let group = group as u32;
                match prebuilt.iter().find(|(g, _)| *g == group) {
                    Some((_, made)) => made.clone(),
                    None => self.group(device, pipeline, group, label, entries),
                }
            })
            .collect()
    }

    /// A bind group of exactly `entries` for group `group` of `pipeline`'s
    /// derived layout, made once and reused while a pass binds the same
    /// resources (counted in `bind_groups_created` and `bind_groups_reused`): for passes
    /// that choose their entries themselves, and for render pipelines.
    pub fn group(
        &mut self,
        device: &wgpu::Device,
        pipeline: &PipelineRef,
        group: u32,
        label: &str,
        entries: &[wgpu::BindGroupEntry<'_>],
    ) -> wgpu::BindGroup {
        let hash = group_hash(pipeline, group, entries);
        if let Some(cached) = hash
            .and_then(|h| self.bind_groups.get_mut(&h))
            .and_then(|groups| {
                groups
                    .iter_mut()
                    .find(|g| same_group(&g.key, pipeline, group, entries))
            })
        {
            cached.last = self.frame;
            self.bind_groups_reused += 1;
            return cached.group.clone();
        }
        let made = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some(label),
            layout: &pipeline.layout(group),
            entries,
        });
        self.bind_groups_created += 1;
        let bound: Option<Vec<(u32, Bound)>> = entries
            .iter()
            .map(|e| Bound::of(&e.resource).map(|b| (e.binding, b)))
            .collect();
        if let (Some(hash), Some(bound)) = (hash, bound) {
            self.bind_groups.entry(hash).or_default().push(CachedGroup {
                key: (pipeline.clone(), group, bound),
                group: made.clone(),
                last: self.frame,
            });
        }
        made
    }

    /// A sampler, made once per device rather than once per pass or frame.
    pub fn sampler(&mut self, device: &wgpu::Device, sampling: Sampling) -> wgpu::Sampler {
        self.samplers
            .entry(sampling)
            .or_insert_with(|| {
                let address = match sampling {
                    Sampling::LinearRepeat => wgpu::AddressMode::Repeat,
                    Sampling::LinearClamp => wgpu::AddressMode::ClampToEdge,
                };
                device.create_sampler(&wgpu::SamplerDescriptor {
                    label: Some(match sampling {
                        Sampling::LinearRepeat => "linear repeat",
                        Sampling::LinearClamp => "linear clamp",
                    }),
                    address_mode_u: address,
                    address_mode_v: address,
                    mag_filter: wgpu::FilterMode::Linear,
                    min_filter: wgpu::FilterMode::Linear,
                    ..Default::default()
                })
            })
            .clone()
    }

    /// The permutations compiled so far (tests check a feature no scene uses
    /// never is): a module made here, or a compute or render pipeline made
    /// for this cache on a thread ahead of its look-up
    /// (`crate::shaders::pipelines_ahead`), which leaves no module here.
    pub fn compiled_keys(&self) -> impl Iterator<Item = &ShaderKey> {
        self.modules.keys().chain(
            (self.compute.keys().chain(self.render.keys()))
                .filter(|key| !self.modules.contains_key(*key)),
        )
    }

    /// Every permutation composed for this cache so far (made a module of,
    /// or reflected), sorted: what `crate::precompose` composes ahead next time.
    pub fn used_permutations(&self) -> Vec<ShaderKey> {
        let used: std::collections::BTreeSet<&ShaderKey> = self
            .modules
            .keys()
            .chain(self.reflections.keys())
            .chain(self.compute_order.iter().filter_map(|id| match id {
                PipelineId::Entry(key, _) => Some(key),
                _ => None,
            }))
            .collect();
        used.into_iter().cloned().collect()
    }

    /// The compute pipeline of `entry` in a permutation (bind group layouts derived from the shader).
    pub fn compute_pipeline(
        &mut self,
        device: &wgpu::Device,
        key: &ShaderKey,
        entry: &'static str,
    ) -> Result<wgpu::ComputePipeline, RenderError> {
        if let Some(p) = self
            .compute
            .get(key)
            .and_then(|by_entry| by_entry.get(entry))
        {
            return Ok(p.clone());
        }
        let id = PipelineId::entry(key, entry);
        let taken = self.take_ahead(&id);
        self.compute_order.push(id);
        if let Some(Made::Compute(pipeline)) = taken {
            self.pipelines_compiled += 1;
            self.pipelines_taken_ahead += 1;
            self.compute
                .entry(key.clone())
                .or_default()
                .insert(entry, pipeline.clone());
            return Ok(pipeline);
        }
        let module = self.module(device, key)?;
        let label = format!("{}{}::{entry}", key.path(), key.describe_defs());
        let pipeline = timed(&mut self.compile_times.pipelines, || {
            compute_pipeline_of(device, self.pipeline_cache.as_ref(), &module, &label, entry)
        });
        self.pipelines_compiled += 1;
        self.made_here.push(label);
        self.compute
            .entry(key.clone())
            .or_default()
            .insert(entry, pipeline.clone());
        Ok(pipeline)
    }

    /// The compute pipeline of `entry` in a module validated elsewhere (a
    /// shader node file), cached under `key`, which must change with the
    /// source: `module` is called only the first time.
    pub fn external_compute_pipeline(
        &mut self,
        device: &wgpu::Device,
        key: u64,
        label: &str,
        module: impl FnOnce() -> naga::Module,
        entry: &str,
    ) -> wgpu::ComputePipeline {
        let cache_key = (key, entry.to_owned());
        if let Some(p) = self.external.get(&cache_key) {
            return p.clone();
        }
        let module = timed(&mut self.compile_times.compose, module);
        let module = timed(&mut self.compile_times.modules, || {
            device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(label),
                source: wgpu::ShaderSource::Naga(Cow::Owned(module)),
            })
        });
        let pipeline = timed(&mut self.compile_times.pipelines, || {
            compute_pipeline_of(
                device,
                self.pipeline_cache.as_ref(),
                &module,
                &format!("{label}::{entry}"),
                entry,
            )
        });
        self.pipelines_compiled += 1;
        self.made_here.push(format!("{label}::{entry}"));
        self.external.insert(cache_key, pipeline.clone());
        pipeline
    }

    /// The compute pipeline of `entry` in permutation `key` composed with
    /// library `module` replaced by a shader node material's `source`
    /// (identified by `source_key`, which must change with it), and the
    /// reflection of the composed module, to build its bind groups by.
    pub fn surface_pipeline(
        &mut self,
        device: &wgpu::Device,
        key: &ShaderKey,
        splice: &Splice<'_>,
        entry: &str,
    ) -> Result<SplicedPipeline, RenderError> {
        let Splice {
            key: source_key,
            module,
            file_path,
            source,
        } = *splice;
        let cache_key = (key.clone(), source_key);
        if let Some(found) = self.surfaces.get(&cache_key) {
            return Ok(found.clone());
        }
        self.composer()?;
        let started = std::time::Instant::now();
        let composed = self
            .composer()?
            .compose_with_module(key, module, file_path, source);
        self.compile_times.compose += started.elapsed();
        let composed = composed?;
        let reflection =
            Arc::new(
                reflect(&composed, entry).map_err(|message| RenderError::Shader {
                    shader: file_path.to_owned(),
                    defs: key.describe_defs(),
                    message,
                })?,
            );
        let label = format!("{}{} + {file_path}", key.path(), key.describe_defs());
        let pipeline = self.composed_pipeline(device, &label, composed, entry);
        self.surfaces
            .insert(cache_key, (pipeline.clone(), reflection.clone()));
        Ok((pipeline, reflection))
    }

    /// The compute pipeline of `entry` in a module composed outside the
    /// permutation table (a spliced or generated shader), timed and counted
    /// as the table's are.
    fn composed_pipeline(
        &mut self,
        device: &wgpu::Device,
        label: &str,
        composed: naga::Module,
        entry: &str,
    ) -> wgpu::ComputePipeline {
        let shader = timed(&mut self.compile_times.modules, || {
            device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(label),
                source: wgpu::ShaderSource::Naga(Cow::Owned(composed)),
            })
        });
        let pipeline = timed(&mut self.compile_times.pipelines, || {
            compute_pipeline_of(
                device,
                self.pipeline_cache.as_ref(),
                &shader,
                &format!("{label}::{entry}"),
                entry,
            )
        });
        self.pipelines_compiled += 1;
        self.made_here.push(format!("{label}::{entry}"));
        pipeline
    }

    /// The compute pipeline of a shader generated over the sources (the
    /// fused light loop, `lighting::light_sets`) and its reflection, cached
    /// under `hash`, which must change with the key `key` makes (a hash the
    /// frame computes without building the key, which is made only the
    /// first time): taken from the threads that made it ahead
    /// (`shaders/generated.rs`), else generated, composed and made here.
    pub fn generated_pipeline(
        &mut self,
        device: &wgpu::Device,
        hash: u64,
        key: impl FnOnce() -> GeneratedKey,
    ) -> Result<SplicedPipeline, RenderError> {
        if let Some(found) = self.generated.get(&hash) {
            return Ok(found.clone());
        }
        let key = key();
        let id = PipelineId::Generated(key.clone());
        let taken = self.take_ahead(&id);
        self.compute_order.push(id);
        if let Some(Made::Generated(pipeline, reflection)) = taken {
            self.pipelines_compiled += 1;
            self.pipelines_taken_ahead += 1;
            self.generated
                .insert(hash, (pipeline.clone(), reflection.clone()));
            return Ok((pipeline, reflection));
        }
        let entry = key.generator.entry;
        let started = std::time::Instant::now();
        let ready = match self.shares_embedded() {
            true => crate::shaders::embedded_generated_or_wait(&key),
            false => None,
        };
        let composed = match ready {
            Some(made) => {
                self.compile_times.ready += 1;
                Ok(made)
            }
            None => self.composer().and_then(|c| c.generate(&key)),
        };
        self.compile_times.compose += started.elapsed();
        let (label, composed) = composed?;
        let reflection =
            Arc::new(
                reflect(&composed, entry).map_err(|message| RenderError::Shader {
                    shader: label.clone(),
                    defs: String::new(),
                    message,
                })?,
            );
        let pipeline = self.composed_pipeline(device, &label, composed, entry);
        self.generated
            .insert(hash, (pipeline.clone(), reflection.clone()));
        Ok((pipeline, reflection))
    }

    /// A render pipeline for a permutation; `variant` names what else the
    /// caller's descriptor depends on (target formats, blend), and `build`
    /// makes it (through the pipeline cache it is given).
    pub fn render_pipeline(
        &mut self,
        device: &wgpu::Device,
        key: &ShaderKey,
        variant: &str,
        build: impl FnOnce(&wgpu::ShaderModule, Option<&wgpu::PipelineCache>) -> wgpu::RenderPipeline,
    ) -> Result<wgpu::RenderPipeline, RenderError> {
        if let Some(p) = self.render.get(key).and_then(|by| by.get(variant)) {
            return Ok(p.clone());
        }
        // Announced by its pass and made on a thread (frame_graph/gather.rs).
        if !self.frame_ahead.is_empty()
            && let Some(Made::Render(pipeline)) =
                self.take_ahead(&PipelineId::Render(key.clone(), variant.to_owned()))
        {
            self.pipelines_compiled += 1;
            self.pipelines_taken_ahead += 1;
            self.render
                .entry(key.clone())
                .or_default()
                .insert(variant.to_owned(), pipeline.clone());
            return Ok(pipeline);
        }
        let module = self.module(device, key)?;
        let cache = self.pipeline_cache.as_ref();
        let pipeline = timed(&mut self.compile_times.pipelines, || build(&module, cache));
        self.pipelines_compiled += 1;
        self.made_here
            .push(format!("{}{} ({variant})", key.path(), key.describe_defs()));
        self.render
            .entry(key.clone())
            .or_default()
            .insert(variant.to_owned(), pipeline.clone());
        Ok(pipeline)
    }
}
