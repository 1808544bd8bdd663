//! `Reflection`: image-based light from an [`Environment`] over the
//! G-buffer (shaders/environment/reflection.wgsl): the prefiltered
//! environment along each pixel's reflected (or refracted) direction at its
//! roughness, times the split-sum factor, and the diffuse irradiance.
//!
//! Two passes, so each runs only when read: `specular` (only pixels whose
//! material has the Reflection feature) and `diffuse` (every surface: the
//! environment's diffuse light does not depend on reflecting). When no
//! material of the world has the Reflection feature, the specular pass
//! only clears its output ("reflection skipped" in the frame report), and
//! the environment is built only if the diffuse light is read.

use std::sync::Arc;

use super::environment_map::Environment;
use crate::error::RenderError;
use crate::frame_graph::{FrameGraph, PassContext, TextureDesc};
use crate::gbuffer::GBuffer;
use crate::material::{FEATURE_COOK_TORRANCE, FEATURE_REFLECTION, MaterialWorld};
use crate::recipe::{Recipe, TextureRef, next_recipe_id};
use crate::renderer::Renderer;
use crate::shaders::ShaderKey;
use crate::texture_pool::ViewSpec;

const SHADER: &str = "environment/reflection.wgsl";
/// Statistic: Reflection passes that wrote the diffuse light and the
/// specular in one dispatch (the frame read both).
pub const BOTH_IN_ONE_PASS: &str = "reflection diffuse and specular in one pass";

/// What the specular output shows.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ReflectionMode {
    /// The environment mirrored about the normal, times F0 A + B.
    Reflect,
    /// The environment seen through the surface along the refracted
    /// direction (index of refraction `ior` inside, air outside), times
    /// 1 - (F0 A + B); total internal reflection reflects instead.
    Refract { ior: f32 },
}

impl ReflectionMode {
    /// (mode, ior) for the shader: a bad IOR (NaN, below 1) is glass's 1.5 or 1.
    fn params(self) -> (u32, f32) {
        match self {
            ReflectionMode::Reflect => (0, 1.0),
            ReflectionMode::Refract { ior } => {
                let ior = if ior.is_finite() {
                    ior.clamp(1.0, 4.0)
                } else {
                    1.5
                };
                (1, ior)
            }
        }
    }
}

pub struct Reflection {
    id: u64,
    owner: Option<u32>,
    gbuffer: Arc<GBuffer>,
    materials: Arc<MaterialWorld>,
    environment: Arc<Environment>,
    pub mode: ReflectionMode,
    params: wgpu::Buffer,
    /// Reflected (or refracted) radiance, additive.
    pub specular: String,
    /// Irradiance / pi from the environment: multiply by albedo to light a surface.
    pub diffuse: String,
}

impl Reflection {
    pub fn new(
        renderer: &Renderer,
        owner: Option<u32>,
        gbuffer: Arc<GBuffer>,
        materials: Arc<MaterialWorld>,
        environment: Arc<Environment>,
        mode: ReflectionMode,
    ) -> Arc<Self> {
        let id = next_recipe_id();
        let (mode_id, ior) = mode.params();
        let levels = environment.quality.levels();
        let params = renderer.kept_init(
            owner,
            "reflection params",
            bytemuck::cast_slice(&[mode_id, levels, ior.to_bits(), 0]),
            wgpu::BufferUsages::UNIFORM,
        );
        Arc::new(Reflection {
            id,
            owner,
            gbuffer,
            materials,
            environment,
            mode,
            params,
            specular: format!("reflection{id}/specular"),
            diffuse: format!("reflection{id}/diffuse"),
        })
    }

    pub fn specular_texture(self: &Arc<Self>) -> TextureRef {
        TextureRef {
            recipe: self.clone(),
            name: self.specular.clone(),
        }
    }

    pub fn diffuse_texture(self: &Arc<Self>) -> TextureRef {
        TextureRef {
            recipe: self.clone(),
            name: self.diffuse.clone(),
        }
    }

    pub fn gbuffer(&self) -> &Arc<GBuffer> {
        &self.gbuffer
    }

    pub fn materials(&self) -> &Arc<MaterialWorld> {
        &self.materials
    }

    pub fn environment(&self) -> &Arc<Environment> {
        &self.environment
    }

    /// Whether some material reflects: otherwise there is nothing to compute.
    pub fn active(&self) -> bool {
        self.materials.any_has(FEATURE_REFLECTION)
    }

    fn textured(&self) -> bool {
        self.materials.textured(1 << FEATURE_COOK_TORRANCE)
    }

    fn key(&self) -> ShaderKey {
        self.materials
            .surface_key(SHADER, self.gbuffer.targets.surface_feature())
    }

    fn clear(&self, cx: &mut PassContext<'_>) -> Result<(), RenderError> {
        cx.count("reflection skipped", 1);
        let specular = cx.view_named(&self.specular)?;
        let all = [
            (0, self.gbuffer.camera_buffer().as_entire_binding()),
            (9, wgpu::BindingResource::TextureView(&specular)),
        ];
        self.dispatch(cx, "clear", "reflection clear", &all, false)
    }

    /// `entry` over the G-buffer with `all` at group 0 (and the material world at group 1 when `materials`).
    fn dispatch(
        &self,
        cx: &mut PassContext<'_>,
        entry: &'static str,
        label: &str,
        all: &[(u32, wgpu::BindingResource<'_>)],
        materials: bool,
    ) -> Result<(), RenderError> {
        let device = cx.gpu.device.clone();
        let key = self.key();
        let pipeline = cx.shaders.compute_pipeline(&device, &key, entry)?;
        let group = cx
            .shaders
            .bind_group(&device, &key, entry, &pipeline, 0, all)?;
        let material_group = if materials {
            Some(self.materials.bind_group(
                cx,
                &key,
                &pipeline,
                self.textured(),
                self.gbuffer.targets.surface_targets(),
            )?)
        } else {
            None
        };
        let groups: Vec<&wgpu::BindGroup> = std::iter::once(&group)
            .chain(material_group.as_ref())
            .collect();
        let (w, h) = self.gbuffer.pixel_size(cx.output_size);
        cx.dispatch(label, &pipeline, &groups, (w.div_ceil(8), h.div_ceil(8), 1));
        Ok(())
    }

    /// The diffuse light, the specular, or both in one dispatch.
    fn run(&self, cx: &mut PassContext<'_>, outputs: Outputs) -> Result<(), RenderError> {
        let specular = outputs != Outputs::Diffuse;
        if specular {
            cx.count("reflection shaded", 1);
        }
        if outputs == Outputs::Both {
            cx.count(BOTH_IN_ONE_PASS, 1);
        }
        let maps = self.environment.maps_for("reflection")?;
        let g = &self.gbuffer;
        let (color, normals, depth) = (
            cx.view_named(&g.targets.color)?,
            cx.view_named(&g.targets.normals)?,
            cx.view_named(&g.targets.depth)?,
        );
        // Only the outputs this pass writes (a diffuse-only pass has no specular).
        let diffuse = match outputs {
            Outputs::Specular => None,
            _ => Some(cx.view_named(&self.diffuse)?),
        };
        let specular_out = match outputs {
            Outputs::Diffuse => None,
            _ => Some(cx.view_named(&self.specular)?),
        };
        // Cached views: new ones each frame would make new bind groups.
        let prefiltered = cx.view_of(&maps.prefiltered, ViewSpec::cube());
        let irradiance = cx.view_of(&maps.irradiance, ViewSpec::cube());
        let lut = cx.view_of(&maps.lut, ViewSpec::default());
        let all = [
            (0, g.camera_buffer().as_entire_binding()),
            (1, self.params.as_entire_binding()),
            (2, wgpu::BindingResource::TextureView(&color)),
            (3, wgpu::BindingResource::TextureView(&normals)),
            (4, wgpu::BindingResource::TextureView(&depth)),
            (5, wgpu::BindingResource::TextureView(&prefiltered)),
            (6, wgpu::BindingResource::TextureView(&irradiance)),
            (7, wgpu::BindingResource::TextureView(&lut)),
            (8, wgpu::BindingResource::Sampler(&maps.sampler)),
        ];
        // Roughness and metallic where the G-buffer resolved them (only `main` reads it).
        let surface = match (&g.targets.surface, specular) {
            (Some(name), true) => Some(cx.view_named(name)?),
            _ => None,
        };
        let mut all = all.to_vec();
        if let Some(view) = &specular_out {
            all.push((9, wgpu::BindingResource::TextureView(view)));
        }
        if let Some(view) = &diffuse {
            all.push((10, wgpu::BindingResource::TextureView(view)));
        }
        if let Some(view) = &surface {
            all.push((
                crate::gbuffer::SURFACE_TARGET_BINDING,
                wgpu::BindingResource::TextureView(view),
            ));
        }
        match outputs {
            Outputs::Both => self.dispatch(cx, "both", "reflection", &all, true),
            Outputs::Specular => self.dispatch(cx, "main", "reflection", &all, true),
            Outputs::Diffuse => self.dispatch(cx, "diffuse", "reflection diffuse", &all, false),
        }
    }
}

/// Which of a Reflection's outputs a pass writes.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Outputs {
    Diffuse,
    Specular,
    Both,
}

impl Recipe for Reflection {
    fn declare<'a>(&'a self, renderer: &'a Renderer, fg: &mut FrameGraph<'a>) {
        if !fg.include(self.id) {
            return;
        }
        self.gbuffer.declare(renderer, fg);
        let hdr = TextureDesc::storage(wgpu::TextureFormat::Rgba16Float).size(self.gbuffer.size);
        let g = &self.gbuffer.targets;
        self.environment.declare(renderer, fg);
        if !self.active() {
            fg.add_pass(
                crate::recipe::pass_name("Reflection", self.owner, Some("diffuse")),
                self.owner,
                &[
                    self.environment.token(),
                    g.normals.as_str(),
                    g.depth.as_str(),
                ],
                &[(self.diffuse.as_str(), hdr)],
                move |cx| self.run(cx, Outputs::Diffuse),
            );
            fg.add_pass(
                crate::recipe::pass_name("Reflection", self.owner, Some("none reflective")),
                self.owner,
                &[],
                &[(self.specular.as_str(), hdr)],
                move |cx| self.clear(cx),
            );
            return;
        }
        let mut reads = vec![
            self.environment.token(),
            g.color.as_str(),
            g.normals.as_str(),
            g.depth.as_str(),
        ];
        reads.extend(g.surface.as_deref());
        reads.extend(self.materials.declare_textures(
            renderer,
            fg,
            self.textured(),
            g.surface_targets(),
        ));
        // One pass for both outputs: it runs when either is read, and
        // writes only what the frame reads.
        fg.add_pass(
            crate::recipe::pass_name("Reflection", self.owner, Some("diffuse and specular")),
            self.owner,
            &reads,
            &[(self.diffuse.as_str(), hdr), (self.specular.as_str(), hdr)],
            move |cx| {
                let outputs = match (
                    cx.is_read_named(&self.diffuse),
                    cx.is_read_named(&self.specular),
                ) {
                    (true, true) => Outputs::Both,
                    (true, false) => Outputs::Diffuse,
                    _ => Outputs::Specular,
                };
                self.run(cx, outputs)
            },
        );
    }
}
