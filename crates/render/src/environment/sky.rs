//! `Sky`: a procedural sky behind the scene (shaders/environment/sky.wgsl),
//! written where the G-buffer's depth is empty, the lit image passed
//! through elsewhere.

use std::sync::Arc;

use glam::Vec3;
use wgpu::util::DeviceExt;

use crate::error::RenderError;
use crate::frame_graph::{FrameGraph, PassContext, TextureDesc};
use crate::gbuffer::GBuffer;
use crate::recipe::{Recipe, TextureRef, next_recipe_id};
use crate::renderer::Renderer;
use crate::shaders::ShaderKey;

/// A procedural sky: linear radiance colours and the sun.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SkySettings {
    pub zenith: Vec3,
    pub horizon: Vec3,
    pub ground: Vec3,
    /// The direction the sunlight travels (as a `SunLight`'s): the disk is opposite it.
    pub sun_direction: Vec3,
    /// The disk's radiance.
    pub sun_color: Vec3,
    /// The disk's angular radius in radians (the sun's: 0.0047).
    pub sun_radius: f32,
    /// How bright the glow around the disk is, 0 for none.
    pub glow: f32,
}

impl Default for SkySettings {
    fn default() -> Self {
        SkySettings {
            zenith: Vec3::new(0.12, 0.25, 0.6),
            horizon: Vec3::new(0.6, 0.7, 0.85),
            ground: Vec3::new(0.2, 0.18, 0.16),
            sun_direction: Vec3::new(-0.3, -1.0, -0.2),
            sun_color: Vec3::new(50.0, 45.0, 38.0),
            sun_radius: 0.0047,
            glow: 1.0,
        }
    }
}

/// Matches `Sky` in shaders/environment/sky.wgsl.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct GpuSky {
    zenith: [f32; 4],
    horizon: [f32; 4],
    ground: [f32; 4],
    sun: [f32; 4],
    sun_color: [f32; 4],
}

/// Colours: finite and not negative (NaN is 0).
fn radiance(v: Vec3) -> [f32; 4] {
    let clean = |c: f32| {
        if c.is_finite() {
            c.clamp(0.0, 65000.0)
        } else {
            0.0
        }
    };
    [clean(v.x), clean(v.y), clean(v.z), 0.0]
}

pub struct Sky {
    id: u64,
    owner: Option<u32>,
    gbuffer: Arc<GBuffer>,
    source: TextureRef,
    params: wgpu::Buffer,
    pub output: String,
}

impl Sky {
    /// `source` (the lit image) with the sky where `gbuffer` saw nothing.
    pub fn new(
        renderer: &Renderer,
        owner: Option<u32>,
        gbuffer: Arc<GBuffer>,
        source: TextureRef,
        settings: SkySettings,
    ) -> Arc<Self> {
        let id = next_recipe_id();
        // Towards the sun: against the light's travel; straight up for a zero direction.
        let towards = (-settings.sun_direction).try_normalize().unwrap_or(Vec3::Y);
        let radius = if settings.sun_radius.is_finite() {
            settings.sun_radius.clamp(0.0, 0.5)
        } else {
            0.0
        };
        let glow = if settings.glow.is_finite() {
            settings.glow.clamp(0.0, 1e3)
        } else {
            0.0
        };
        let mut sun_color = radiance(settings.sun_color);
        sun_color[3] = glow;
        let gpu = GpuSky {
            zenith: radiance(settings.zenith),
            horizon: radiance(settings.horizon),
            ground: radiance(settings.ground),
            sun: towards.extend(radius.cos()).to_array(),
            sun_color,
        };
        let params = renderer
            .gpu
            .device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("sky"),
                contents: bytemuck::bytes_of(&gpu),
                usage: wgpu::BufferUsages::UNIFORM,
            });
        Arc::new(Sky {
            id,
            owner,
            gbuffer,
            source,
            params,
            output: format!("sky{id}"),
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
        let key = ShaderKey::new("environment/sky.wgsl", []);
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
            "sky",
            &pipeline,
            &[&group],
            (w.div_ceil(8), h.div_ceil(8), 1),
        );
        Ok(())
    }
}

impl Recipe for Sky {
    fn declare<'a>(&'a self, renderer: &'a Renderer, fg: &mut FrameGraph<'a>) {
        if !fg.include(self.id) {
            return;
        }
        self.gbuffer.declare(renderer, fg);
        self.source.recipe.declare(renderer, fg);
        let name = match self.owner {
            Some(node) => format!("Sky #{node}"),
            None => "Sky".to_owned(),
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
