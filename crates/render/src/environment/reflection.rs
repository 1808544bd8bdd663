//! `Reflection`: image-based light from an [`Environment`] over the
//! G-buffer (shaders/environment/reflection.wgsl): the prefiltered
//! environment along each pixel's reflected (or refracted) direction at its
//! roughness, times the split-sum factor, and the diffuse irradiance.
//!
//! Only what the scene calls for: when no material of the world has the
//! Reflection feature, the pass only clears its outputs and the environment
//! is not built ("reflection skipped" in the frame report).

use std::sync::Arc;

use wgpu::util::DeviceExt;

use super::environment_map::{Environment, EnvironmentMaps};
use crate::error::RenderError;
use crate::frame_graph::{FrameGraph, PassContext, TextureDesc};
use crate::gbuffer::GBuffer;
use crate::material::{FEATURE_COOK_TORRANCE, FEATURE_REFLECTION, MaterialWorld};
use crate::recipe::{Recipe, TextureRef, next_recipe_id};
use crate::renderer::Renderer;
use crate::shaders::ShaderKey;

const SHADER: &str = "environment/reflection.wgsl";

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
        let params = renderer
            .gpu
            .device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("reflection params"),
                contents: bytemuck::cast_slice(&[mode_id, levels, ior.to_bits(), 0]),
                usage: wgpu::BufferUsages::UNIFORM,
            });
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
        self.materials.union_flags() & (1 << FEATURE_REFLECTION) != 0
    }

    fn textured(&self) -> bool {
        self.materials.textured(1 << FEATURE_COOK_TORRANCE)
    }

    fn key(&self) -> ShaderKey {
        let features: &[&'static str] = if self.textured() {
            &["MATERIAL_TEXTURES"]
        } else {
            &[]
        };
        ShaderKey::new(SHADER, features.iter().copied())
    }

    fn clear(&self, cx: &mut PassContext<'_>) -> Result<(), RenderError> {
        cx.count("reflection skipped", 1);
        let (specular, diffuse) = (cx.view(&self.specular)?, cx.view(&self.diffuse)?);
        let device = cx.gpu.device.clone();
        let key = self.key();
        let pipeline = cx.shaders.compute_pipeline(&device, &key, "clear")?;
        let all = [
            (0, self.gbuffer.camera_buffer().as_entire_binding()),
            (9, wgpu::BindingResource::TextureView(&specular)),
            (10, wgpu::BindingResource::TextureView(&diffuse)),
        ];
        let group = cx
            .shaders
            .bind_group(&device, &key, "clear", &pipeline, 0, &all)?;
        let (w, h) = self.gbuffer.pixel_size(cx.output_size);
        cx.dispatch(
            "reflection clear",
            &pipeline,
            &[&group],
            (w.div_ceil(8), h.div_ceil(8), 1),
        );
        Ok(())
    }

    fn run(&self, cx: &mut PassContext<'_>) -> Result<(), RenderError> {
        cx.count("reflection shaded", 1);
        let maps = self.environment.maps_for("reflection")?;
        let g = &self.gbuffer;
        let (color, normals, depth) = (
            cx.view(&g.targets.color)?,
            cx.view(&g.targets.normals)?,
            cx.view(&g.targets.depth)?,
        );
        let (specular, diffuse) = (cx.view(&self.specular)?, cx.view(&self.diffuse)?);
        let prefiltered = EnvironmentMaps::cube_view(&maps.prefiltered);
        let irradiance = EnvironmentMaps::cube_view(&maps.irradiance);
        let lut = maps.lut.create_view(&Default::default());
        let device = cx.gpu.device.clone();
        let key = self.key();
        let pipeline = cx.shaders.compute_pipeline(&device, &key, "main")?;
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
            (9, wgpu::BindingResource::TextureView(&specular)),
            (10, wgpu::BindingResource::TextureView(&diffuse)),
        ];
        let group = cx
            .shaders
            .bind_group(&device, &key, "main", &pipeline, 0, &all)?;
        let materials = self.materials.bind_group(
            cx,
            &key,
            &pipeline,
            self.textured(),
            &g.targets.velocity_uv,
        )?;
        let (w, h) = g.pixel_size(cx.output_size);
        cx.dispatch(
            "reflection",
            &pipeline,
            &[&group, &materials],
            (w.div_ceil(8), h.div_ceil(8), 1),
        );
        Ok(())
    }
}

impl Recipe for Reflection {
    fn declare<'a>(&'a self, renderer: &'a Renderer, fg: &mut FrameGraph<'a>) {
        if !fg.include(self.id) {
            return;
        }
        self.gbuffer.declare(renderer, fg);
        let hdr = TextureDesc::storage(wgpu::TextureFormat::Rgba16Float).size(self.gbuffer.size);
        let outputs = [(self.specular.as_str(), hdr), (self.diffuse.as_str(), hdr)];
        if !self.active() {
            fg.add_pass(
                crate::recipe::pass_name("Reflection", self.owner, Some("none reflective")),
                self.owner,
                &[],
                &outputs,
                move |cx| self.clear(cx),
            );
            return;
        }
        self.environment.declare(renderer, fg);
        let g = &self.gbuffer.targets;
        let mut reads = vec![
            self.environment.token(),
            g.color.as_str(),
            g.normals.as_str(),
            g.depth.as_str(),
        ];
        reads.extend(self.materials.declare_textures(
            renderer,
            fg,
            self.textured(),
            &g.velocity_uv,
        ));
        fg.add_pass(
            crate::recipe::pass_name("Reflection", self.owner, None),
            self.owner,
            &reads,
            &outputs,
            move |cx| self.run(cx),
        );
    }
}
