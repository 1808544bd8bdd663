//! A DeferredBase layer's shader node material, as the G-buffer sees it:
//! the file's text (spliced into the surface resolve in place of
//! `spreadlight::custom_surface`), what its group-1 bindings are, and one
//! slice's uniform block and textures. The node library makes it from a
//! compiled material file (crates/render/src/shader_nodes/material.rs);
//! the G-buffer needs nothing else of shader nodes. The passes a file is
//! spliced into (the resolve, CookTorrance's light shaders) get its pipeline
//! and its own bind group here, written once for both.

use std::sync::atomic::{AtomicBool, Ordering};

use crate::error::RenderError;
use crate::frame_graph::{PassContext, Tex};
use crate::recipe::TextureRef;
use crate::shaders::{Reflection, ShaderKey};

/// The library a material's file takes the place of in the resolve.
pub const SURFACE_MODULE: &str = "spreadlight::custom_surface";

/// What one group-1 binding of a material is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SurfaceBinding {
    /// The uniform block (the pins).
    Uniform,
    /// Texture input `i` (in `@input` order).
    Texture(usize),
    /// A linear sampler, repeating or clamping at the edge.
    Sampler { repeat: bool },
}

/// A material applied to a layer: one slice of a material node.
#[derive(Debug)]
pub struct SurfaceShader {
    /// The node and type, for pass names and errors (`Marble (Shader) #4`).
    pub label: String,
    /// The file as errors name it.
    pub file: String,
    /// Its text with the switches resolved: the module spliced into the resolve.
    pub text: String,
    /// Changes with the text (pipelines are cached under it).
    pub key: u64,
    pub bindings: Vec<(u32, SurfaceBinding)>,
    /// The uniform block with the pins written (empty without one).
    pub params: Vec<u8>,
    pub textures: Vec<TextureRef>,
    /// Permutations compiled to make it (counted once in the frame report).
    pub compiled: u64,
    /// It imports `spreadlight::materials`: the resolve binds the layer's
    /// material world in group 3 ([`SurfaceShader::reading_materials`]).
    pub reads_materials: bool,
    counted: AtomicBool,
}

impl SurfaceShader {
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        label: String,
        file: String,
        text: String,
        key: u64,
        bindings: Vec<(u32, SurfaceBinding)>,
        params: Vec<u8>,
        textures: Vec<TextureRef>,
        compiled: u64,
    ) -> Self {
        SurfaceShader {
            label,
            file,
            text,
            key,
            bindings,
            params,
            textures,
            compiled,
            reads_materials: false,
            counted: AtomicBool::new(false),
        }
    }

    /// The material, reading its layer's material world (`spreadlight::materials`).
    pub fn reading_materials(mut self, reads: bool) -> Self {
        self.reads_materials = reads;
        self
    }

    /// The permutations compiled for it, the first time a frame asks.
    pub(crate) fn take_compiled(&self) -> u64 {
        if self.counted.swap(true, Ordering::Relaxed) {
            0
        } else {
            self.compiled
        }
    }
}

impl SurfaceShader {
    /// Built-in shader `key` composed with this file in place of `module`
    /// (a material in the resolve, a light shader in CookTorrance): its
    /// `main` pipeline and reflection, an error named by `label`.
    pub(crate) fn pipeline(
        &self,
        cx: &mut PassContext<'_>,
        key: &ShaderKey,
        module: &'static str,
        label: &str,
    ) -> Result<(wgpu::ComputePipeline, std::sync::Arc<Reflection>), RenderError> {
        let splice = crate::shaders::Splice {
            key: self.key,
            module,
            file_path: &self.file,
            source: &self.text,
        };
        let device = cx.gpu.device.clone();
        cx.shaders
            .surface_pipeline(&device, key, &splice, "main")
            .map_err(|e| RenderError::Pass {
                pass: label.to_owned(),
                message: e.to_string(),
            })
    }
}

/// Where a spliced shader node file's own bindings go.
pub(crate) struct SplicedGroup<'a> {
    /// 1 for a material in the resolve, 2 for a light shader in CookTorrance.
    pub group: u32,
    /// The pass, for errors.
    pub label: &'a str,
    pub reflection: &'a Reflection,
}

/// The group of a built-in pass composed with a shader node file (a
/// material in the resolve, a light shader in CookTorrance): its pins'
/// uniform block, texture inputs and samplers, numbered as the user's file
/// numbers them, those the permutation uses. None where it uses no such group.
pub(crate) fn shader_node_group(
    cx: &mut PassContext<'_>,
    pipeline: &wgpu::ComputePipeline,
    surface: &SurfaceShader,
    params: Option<&wgpu::Buffer>,
    textures: &[Tex],
    spliced: &SplicedGroup<'_>,
) -> Result<Option<wgpu::BindGroup>, RenderError> {
    let (group, reflection) = (spliced.group, spliced.reflection);
    // A derived layout has groups up to the last one used: none past the last.
    if reflection.last_group().is_none_or(|last| last < group) {
        return Ok(None);
    }
    let mut resources = Vec::new();
    for (binding, role) in &surface.bindings {
        if !reflection.used().any(|u| u == (group, *binding)) {
            continue;
        }
        let resource = match role {
            SurfaceBinding::Uniform => match params {
                Some(buffer) => Bound::Buffer(buffer.clone()),
                None => continue,
            },
            SurfaceBinding::Texture(t) => {
                let tex = textures.get(*t).ok_or_else(|| RenderError::Pass {
                    pass: spliced.label.to_owned(),
                    message: format!("texture input {t} is not connected"),
                })?;
                Bound::View(cx.view(*tex)?)
            }
            SurfaceBinding::Sampler { repeat } => Bound::Sampler(cx.sampler(if *repeat {
                crate::shaders::Sampling::LinearRepeat
            } else {
                crate::shaders::Sampling::LinearClamp
            })),
        };
        resources.push((*binding, resource));
    }
    let entries: Vec<wgpu::BindGroupEntry<'_>> = resources
        .iter()
        .map(|(binding, bound)| wgpu::BindGroupEntry {
            binding: *binding,
            resource: match bound {
                Bound::Buffer(b) => b.as_entire_binding(),
                Bound::View(v) => wgpu::BindingResource::TextureView(v),
                Bound::Sampler(s) => wgpu::BindingResource::Sampler(s),
            },
        })
        .collect();
    Ok(Some(cx.gpu.device.create_bind_group(
        &wgpu::BindGroupDescriptor {
            label: Some(spliced.label),
            layout: &pipeline.get_bind_group_layout(group),
            entries: &entries,
        },
    )))
}

/// A resource of a shader node material's group, resolved.
enum Bound {
    Buffer(wgpu::Buffer),
    View(wgpu::TextureView),
    Sampler(wgpu::Sampler),
}
