//! `Fog`: distance and height fog over the lit image
//! (shaders/environment/fog.wgsl), analytic along each view ray.

use std::sync::Arc;

use glam::Vec3;
use wgpu::util::DeviceExt;

use crate::error::RenderError;
use crate::frame_graph::{FrameGraph, PassContext, TextureDesc};
use crate::gbuffer::GBuffer;
use crate::recipe::{Recipe, TextureRef, next_recipe_id};
use crate::renderer::Renderer;
use crate::shaders::ShaderKey;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FogSettings {
    /// The fog's own radiance (linear).
    pub color: Vec3,
    /// Extinction per unit length at the base height.
    pub density: f32,
    /// How fast it thins with height, per unit (0: uniform).
    pub height_falloff: f32,
    pub base_height: f32,
    /// No fog nearer than this to the camera.
    pub start: f32,
}

impl Default for FogSettings {
    fn default() -> Self {
        FogSettings {
            color: Vec3::new(0.5, 0.55, 0.6),
            density: 0.02,
            height_falloff: 0.2,
            base_height: 0.0,
            start: 0.0,
        }
    }
}

pub struct Fog {
    id: u64,
    owner: Option<u32>,
    gbuffer: Arc<GBuffer>,
    source: TextureRef,
    params: wgpu::Buffer,
    pub output: String,
}

impl Fog {
    pub fn new(
        renderer: &Renderer,
        owner: Option<u32>,
        gbuffer: Arc<GBuffer>,
        source: TextureRef,
        settings: FogSettings,
    ) -> Arc<Self> {
        let id = next_recipe_id();
        let clean = |v: f32, lo: f32, hi: f32| if v.is_finite() { v.clamp(lo, hi) } else { 0.0 };
        let params = [
            clean(settings.color.x, 0.0, 65000.0),
            clean(settings.color.y, 0.0, 65000.0),
            clean(settings.color.z, 0.0, 65000.0),
            clean(settings.density, 0.0, 1e6),
            clean(settings.height_falloff, 0.0, 1e3),
            clean(settings.base_height, -1e9, 1e9),
            clean(settings.start, 0.0, 1e9),
            0.0,
        ];
        let params = renderer
            .gpu
            .device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("fog"),
                contents: bytemuck::cast_slice(&params),
                usage: wgpu::BufferUsages::UNIFORM,
            });
        Arc::new(Fog {
            id,
            owner,
            gbuffer,
            source,
            params,
            output: format!("fog{id}"),
        })
    }

    pub fn texture(self: &Arc<Self>) -> TextureRef {
        TextureRef {
            recipe: self.clone(),
            name: self.output.clone(),
        }
    }

    fn run(&self, cx: &mut PassContext<'_>) -> Result<(), RenderError> {
        let device = cx.gpu.device.clone();
        let key = ShaderKey::new("environment/fog.wgsl", []);
        let pipeline = cx.shaders.compute_pipeline(&device, &key, "main")?;
        let (source, depth, output) = (
            cx.view(&self.source.name)?,
            cx.view(&self.gbuffer.targets.depth)?,
            cx.view(&self.output)?,
        );
        let all = [
            (0, self.gbuffer.camera_buffer().as_entire_binding()),
            (1, self.params.as_entire_binding()),
            (2, wgpu::BindingResource::TextureView(&source)),
            (3, wgpu::BindingResource::TextureView(&depth)),
            (4, wgpu::BindingResource::TextureView(&output)),
        ];
        let group = cx
            .shaders
            .bind_group(&device, &key, "main", &pipeline, 0, &all)?;
        let (w, h) = self.gbuffer.pixel_size(cx.output_size);
        cx.dispatch(
            "fog",
            &pipeline,
            &[&group],
            (w.div_ceil(8), h.div_ceil(8), 1),
        );
        Ok(())
    }
}

impl Recipe for Fog {
    fn declare<'a>(&'a self, renderer: &'a Renderer, fg: &mut FrameGraph<'a>) {
        if !fg.include(self.id) {
            return;
        }
        self.gbuffer.declare(renderer, fg);
        self.source.recipe.declare(renderer, fg);
        let name = match self.owner {
            Some(node) => format!("Fog #{node}"),
            None => "Fog".to_owned(),
        };
        let desc = TextureDesc::storage(wgpu::TextureFormat::Rgba16Float).size(self.gbuffer.size);
        fg.add_pass(
            name,
            self.owner,
            &[&self.source.name, &self.gbuffer.targets.depth],
            &[(&self.output, desc)],
            move |cx| self.run(cx),
        );
    }
}
