//! What a pass binds, by the WGSL variable each resource fills.
//!
//! The bind groups are laid out from naga's reflection of the composed
//! permutation (`shaders::reflection`): no group or binding number is
//! written in Rust, a variable the permutation compiled out is dropped, a
//! name the shader never declares is an error, and so is a variable the
//! shader uses that the pass left unbound, each naming the variable.

use smallvec::SmallVec;

use super::kept_bindings::{Given, GroupsCall, PassCalls};
use super::{PassContext, Tex};
use crate::error::RenderError;
use crate::shaders::{PipelineRef, Reflection, Sampling, ShaderKey};
use crate::texture_pool::ViewSpec;

/// One resource, before the pass resolves it.
#[derive(Clone)]
enum Resource<'r> {
    /// A texture the pass declared, its default view.
    Texture(Tex),
    /// A texture the pass declared, viewed as an array.
    Array(Tex),
    /// A view made outside the frame graph (a node's shadow maps, a stand-in).
    View(wgpu::TextureView),
    Buffer(&'r wgpu::Buffer),
    /// Part of a buffer: an offset and a size (one view's uniforms of many).
    BufferRange(&'r wgpu::Buffer, u64, u64),
    Sampler(Sampling),
    /// A sampler the pass made itself (a material's filtering).
    SamplerObject(wgpu::Sampler),
}

// How many resources a dispatch holds inline, and a pipeline's bind groups:
// defined beside the reflection that matches them (shaders/reflection.rs), below
// the frame graph.
pub use crate::shaders::BindGroups;
pub(crate) use crate::shaders::INLINE_BINDINGS;

/// The resources of one dispatch, by WGSL variable name.
#[derive(Clone, Default)]
pub struct Bindings<'r> {
    /// A Vec (an inline array would make `Bindings` invariant over `'r`,
    /// which callers that extend one with a library's bindings rely on),
    /// sized once for a whole dispatch's resources.
    entries: Vec<(&'r str, Resource<'r>)>,
    /// Whole groups laid out elsewhere (a user's shader file numbers its own bindings).
    groups: Vec<(u32, wgpu::BindGroup)>,
}

impl<'r> Bindings<'r> {
    pub fn new() -> Self {
        Bindings::default()
    }

    fn with(mut self, name: &'r str, resource: Resource<'r>) -> Self {
        if self.entries.capacity() == 0 {
            // One allocation for the dispatch instead of a Vec's doublings.
            self.entries.reserve(INLINE_BINDINGS);
        }
        self.entries.push((name, resource));
        self
    }

    /// A declared texture's default view at variable `name`.
    pub fn texture(self, name: &'r str, tex: Tex) -> Self {
        self.with(name, Resource::Texture(tex))
    }

    /// An optional input: nothing is bound when it is `None`.
    pub fn texture_opt(self, name: &'r str, tex: Option<Tex>) -> Self {
        match tex {
            Some(tex) => self.texture(name, tex),
            None => self,
        }
    }

    /// A declared texture viewed as a 2D array (a texture array input).
    pub fn array(self, name: &'r str, tex: Tex) -> Self {
        self.with(name, Resource::Array(tex))
    }

    /// A view the frame graph does not manage.
    pub fn view(self, name: &'r str, view: wgpu::TextureView) -> Self {
        self.with(name, Resource::View(view))
    }

    /// A whole buffer.
    pub fn buffer(self, name: &'r str, buffer: &'r wgpu::Buffer) -> Self {
        self.with(name, Resource::Buffer(buffer))
    }

    /// `size` bytes of a buffer from `offset`.
    pub fn buffer_range(
        self,
        name: &'r str,
        buffer: &'r wgpu::Buffer,
        offset: u64,
        size: u64,
    ) -> Self {
        self.with(name, Resource::BufferRange(buffer, offset, size))
    }

    pub fn buffer_opt(self, name: &'r str, buffer: Option<&'r wgpu::Buffer>) -> Self {
        match buffer {
            Some(buffer) => self.buffer(name, buffer),
            None => self,
        }
    }

    /// A cached sampler of kind `sampling`.
    pub fn sampler(self, name: &'r str, sampling: Sampling) -> Self {
        self.with(name, Resource::Sampler(sampling))
    }

    /// A sampler made elsewhere.
    pub fn sampler_object(self, name: &'r str, sampler: wgpu::Sampler) -> Self {
        self.with(name, Resource::SamplerObject(sampler))
    }

    /// Group `index` as made elsewhere: its variables are not bound by name.
    pub fn group(mut self, index: u32, group: wgpu::BindGroup) -> Self {
        self.groups.push((index, group));
        self
    }

    /// The same resources under the names `rename` gives (a fused light
    /// set's, `lighting::light_sets`); one it gives none for is kept only
    /// with `keep_others` (resources shared by the sets, bound once), and so
    /// are whole groups.
    pub fn renamed(mut self, rename: impl Fn(&str) -> Option<&'r str>, keep_others: bool) -> Self {
        self.entries.retain_mut(|(name, _)| match rename(name) {
            Some(to) => {
                *name = to;
                true
            }
            None => keep_others,
        });
        if !keep_others {
            self.groups.clear();
        }
        self
    }

    /// Only the resources whose variable names `keep` accepts (a fused
    /// light set leaves out the targets nothing reads, which are not made).
    pub fn retain(mut self, keep: impl Fn(&str) -> bool) -> Self {
        self.entries.retain(|(name, _)| keep(name));
        self
    }

    /// Everything `other` binds too (a library's resources, such as the material world's).
    pub fn extend(mut self, other: Bindings<'r>) -> Self {
        self.entries.extend(other.entries);
        self.groups.extend(other.groups);
        self
    }
}

/// What a dispatch binds, resolved (`PassContext::resolve_bindings`).
type Resolved<'r> = SmallVec<[(&'r str, Owned<'r>); INLINE_BINDINGS]>;

fn as_resources<'a>(
    owned: &'a [(&'a str, Owned<'a>)],
) -> SmallVec<[(&'a str, wgpu::BindingResource<'a>); INLINE_BINDINGS]> {
    owned
        .iter()
        .map(|(name, r)| {
            let resource = match r {
                Owned::View(view) => wgpu::BindingResource::TextureView(view),
                Owned::Buffer(buffer) => buffer.as_entire_binding(),
                Owned::BufferRange(buffer, offset, size) => {
                    wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                        buffer,
                        offset: *offset,
                        size: wgpu::BufferSize::new(*size),
                    })
                }
                Owned::Sampler(sampler) => wgpu::BindingResource::Sampler(sampler),
            };
            (*name, resource)
        })
        .collect()
}

/// The groups the pass's `kept` calls got in one of the last frames for a
/// call that binds exactly what this one binds (kept_bindings.rs: the
/// permutation `key`, None for groups a caller laid out itself, its
/// `entries`, the pipeline, the resources by name and identity, groups made
/// elsewhere), else `resolve()`'s, kept for next time; `resolve()`'s alone
/// when calls are not kept.
fn kept_or(
    kept: &mut Option<&mut PassCalls>,
    key: Option<&ShaderKey>,
    entries: &[&str],
    pipeline: &PipelineRef,
    owned: &[(&str, Owned<'_>)],
    prebuilt: &[(u32, wgpu::BindGroup)],
    resolve: impl FnOnce() -> Result<BindGroups, RenderError>,
) -> Result<BindGroups, RenderError> {
    let Some(kept) = kept else {
        return resolve();
    };
    let given: SmallVec<[(&str, Given<'_>); INLINE_BINDINGS]> =
        owned.iter().map(|(name, r)| (*name, r.given())).collect();
    let call = GroupsCall {
        key,
        entries,
        pipeline,
        resources: &given,
        prebuilt,
    };
    Ok(kept.groups(&call, resolve)?.0)
}

/// A binding resolved to what wgpu binds.
enum Owned<'r> {
    View(wgpu::TextureView),
    Buffer(&'r wgpu::Buffer),
    BufferRange(&'r wgpu::Buffer, u64, u64),
    Sampler(wgpu::Sampler),
}

impl Owned<'_> {
    /// What the binding is by identity, to compare with last frame's.
    fn given(&self) -> Given<'_> {
        match self {
            Owned::View(view) => Given::View(view),
            Owned::Buffer(buffer) => Given::Buffer(buffer, 0, None),
            Owned::BufferRange(buffer, offset, size) => Given::Buffer(buffer, *offset, Some(*size)),
            Owned::Sampler(sampler) => Given::Sampler(sampler),
        }
    }
}

impl PassContext<'_> {
    /// The bind groups (0 up to the last the entry point uses) of a compute
    /// pipeline of `key`/`entry`, from `bindings` by name.
    pub fn bind_groups(
        &mut self,
        key: &ShaderKey,
        entry: &str,
        pipeline: &wgpu::ComputePipeline,
        bindings: Bindings<'_>,
    ) -> Result<BindGroups, RenderError> {
        let (owned, groups) = self.resolve_bindings(bindings)?;
        let pipeline = PipelineRef::Compute(pipeline.clone());
        self.kept_groups(key, &[entry], &pipeline, &owned, &groups)
    }

    /// [`PassContext::bind_groups`] for a render pipeline of `key`'s stages `entries`.
    pub fn render_bind_groups(
        &mut self,
        key: &ShaderKey,
        entries: &[&str],
        pipeline: &wgpu::RenderPipeline,
        bindings: Bindings<'_>,
    ) -> Result<BindGroups, RenderError> {
        let (owned, groups) = self.resolve_bindings(bindings)?;
        let pipeline = PipelineRef::Render(pipeline.clone());
        self.kept_groups(key, entries, &pipeline, &owned, &groups)
    }

    /// The groups this call got last frame when it binds exactly what it
    /// bound then (kept_bindings.rs), else the shader cache's: matched by
    /// name to the permutation's reflection, each group found or made.
    fn kept_groups(
        &mut self,
        key: &ShaderKey,
        entries: &[&str],
        pipeline: &PipelineRef,
        owned: &[(&str, Owned<'_>)],
        prebuilt: &[(u32, wgpu::BindGroup)],
    ) -> Result<BindGroups, RenderError> {
        let shaders = &mut *self.shaders;
        let device = &self.gpu.device;
        kept_or(
            &mut self.kept,
            Some(key),
            entries,
            pipeline,
            owned,
            prebuilt,
            || {
                let resources = as_resources(owned);
                shaders.named_groups(device, key, entries, pipeline, &resources, prebuilt)
            },
        )
    }

    /// Bind groups the caller lays out itself (a user's shader file numbers
    /// its own bindings: shader_nodes/recipe.rs), kept as
    /// [`PassContext::bind_groups`] keeps its: the ones this pass's call got
    /// in one of the last frames when `pipeline` and every resource of
    /// `bindings` (by name and identity) are the same, else `make()`'s.
    pub fn bind_groups_made(
        &mut self,
        entry: &str,
        pipeline: &wgpu::ComputePipeline,
        bindings: Bindings<'_>,
        make: impl FnOnce() -> BindGroups,
    ) -> Result<BindGroups, RenderError> {
        let (owned, prebuilt) = self.resolve_bindings(bindings)?;
        let pipeline = PipelineRef::Compute(pipeline.clone());
        kept_or(
            &mut self.kept,
            None,
            &[entry],
            &pipeline,
            &owned,
            &prebuilt,
            || Ok(make()),
        )
    }

    /// The compute pipeline of `entry` in permutation `key`: the one this
    /// pass's call got last frame when it asks for the same (kept_bindings.rs),
    /// else the shader cache's.
    pub fn compute_pipeline(
        &mut self,
        key: &ShaderKey,
        entry: &'static str,
    ) -> Result<wgpu::ComputePipeline, RenderError> {
        let shaders = &mut *self.shaders;
        let device = &self.gpu.device;
        let mut resolve = || shaders.compute_pipeline(device, key, entry);
        match &mut self.kept {
            Some(kept) => Ok(kept.pipeline(key, entry, resolve)?.0),
            None => resolve(),
        }
    }

    /// [`PassContext::bind_groups`] for a pipeline reflected elsewhere
    /// (`reflection`: a resolve composed with a shader node material).
    pub fn bind_groups_reflected(
        &mut self,
        label: &str,
        reflection: &Reflection,
        pipeline: &wgpu::ComputePipeline,
        bindings: Bindings<'_>,
    ) -> Result<BindGroups, RenderError> {
        let (owned, groups) = self.resolve_bindings(bindings)?;
        let resources = as_resources(&owned);
        let device = self.gpu.device.clone();
        self.shaders
            .groups_by_name(
                &device,
                label,
                reflection,
                &PipelineRef::Compute(pipeline.clone()),
                &resources,
                &groups,
            )
            .map_err(|message| RenderError::Pass {
                pass: label.to_owned(),
                message,
            })
    }

    /// Handles to views, sampling kinds to samplers.
    #[allow(clippy::type_complexity)]
    fn resolve_bindings<'r>(
        &mut self,
        bindings: Bindings<'r>,
    ) -> Result<(Resolved<'r>, Vec<(u32, wgpu::BindGroup)>), RenderError> {
        let mut owned = Resolved::new();
        for (name, resource) in bindings.entries {
            let resolved = match resource {
                Resource::Texture(tex) => Owned::View(self.view(tex)?),
                Resource::Array(tex) => {
                    let texture = self.texture(tex)?.clone();
                    Owned::View(self.view_of(&texture, ViewSpec::array()))
                }
                Resource::View(view) => Owned::View(view),
                Resource::Buffer(buffer) => Owned::Buffer(buffer),
                Resource::BufferRange(buffer, offset, size) => {
                    Owned::BufferRange(buffer, offset, size)
                }
                Resource::Sampler(sampling) => Owned::Sampler(self.sampler(sampling)),
                Resource::SamplerObject(sampler) => Owned::Sampler(sampler),
            };
            owned.push((name, resolved));
        }
        Ok((owned, bindings.groups))
    }

    /// `key`'s `entry` dispatched as `workgroups`, its bind groups from
    /// `bindings` by name: in the open compute pass ([`PassContext::compute_pass`]).
    pub fn dispatch_shader(
        &mut self,
        label: &str,
        key: &ShaderKey,
        entry: &'static str,
        bindings: Bindings<'_>,
        workgroups: (u32, u32, u32),
    ) -> Result<(), RenderError> {
        let pipeline = self.compute_pipeline(key, entry)?;
        let groups = self.bind_groups(key, entry, &pipeline, bindings)?;
        let groups: SmallVec<[&wgpu::BindGroup; 4]> = groups.iter().collect();
        self.dispatch(label, &pipeline, &groups, workgroups);
        Ok(())
    }

    /// The most common pass: `key`'s `main` entry, one thread per pixel of
    /// `size` in 8x8 workgroups, bound by name.
    pub fn dispatch_image(
        &mut self,
        label: &str,
        key: &ShaderKey,
        bindings: Bindings<'_>,
        size: (u32, u32),
    ) -> Result<(), RenderError> {
        self.dispatch_shader(
            label,
            key,
            "main",
            bindings,
            (size.0.div_ceil(8), size.1.div_ceil(8), 1),
        )
    }
}
