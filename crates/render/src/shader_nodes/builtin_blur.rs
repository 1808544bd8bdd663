//! The shader-node example blur (shaders/nodes/blur.wgsl) written as a
//! built-in pass: the same WGSL composed by the [`ShaderCache`](crate::shaders::ShaderCache),
//! its bindings and passes written out by hand. It is the baseline the
//! `Blur (Shader)` node is benchmarked against (`patches/bench-shader-blur.ron` against `patches/bench-builtin-blur.ron`):
//! the two should cost the same on the GPU.

use std::sync::Arc;

use wgpu::util::DeviceExt;

use crate::error::RenderError;
use crate::frame_graph::{FrameGraph, PassContext, SizeRule, TextureDesc};
use crate::recipe::{Recipe, TextureRef, next_recipe_id};
use crate::renderer::Renderer;
use crate::shaders::{Sampling, ShaderKey};

const SHADER: &str = "nodes/blur.wgsl";
const FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

pub struct BuiltinBlur {
    id: u64,
    owner: Option<u32>,
    source: TextureRef,
    radius: f32,
    half: String,
    pub output: String,
}

impl BuiltinBlur {
    pub fn new(owner: Option<u32>, source: TextureRef, radius: f32) -> Arc<Self> {
        let id = next_recipe_id();
        Arc::new(BuiltinBlur {
            id,
            owner,
            source,
            radius: if radius.is_finite() {
                radius.clamp(0.0, 32.0)
            } else {
                0.0
            },
            half: format!("builtin blur{id}/half"),
            output: format!("builtin blur{id}"),
        })
    }

    pub fn texture(self: &Arc<Self>) -> TextureRef {
        TextureRef {
            recipe: self.clone(),
            name: self.output.clone(),
        }
    }

    /// One direction: `entry` reads `input`, writes `output` (the shader's Params: radius, size, texel).
    fn run(
        &self,
        cx: &mut PassContext<'_>,
        entry: &'static str,
        input: &str,
        output: &str,
    ) -> Result<(), RenderError> {
        let (w, h) = {
            let t = cx.texture_named(output)?;
            (t.width(), t.height())
        };
        let (w_f, h_f) = (w as f32, h as f32);
        let words = [self.radius, 0.0, w_f, h_f, 1.0 / w_f, 1.0 / h_f];
        let params = cx
            .gpu
            .device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("builtin blur"),
                contents: bytemuck::cast_slice(&words),
                usage: wgpu::BufferUsages::UNIFORM,
            });
        let device = cx.gpu.device.clone();
        let sampler = cx.sampler(Sampling::LinearClamp);
        let (source, target) = (cx.view_named(input)?, cx.view_named(output)?);
        let key = ShaderKey::new(SHADER, []);
        let pipeline = cx.shaders.compute_pipeline(&device, &key, entry)?;
        let (read, write) = if entry == "horizontal" {
            (1, 4)
        } else {
            (3, 5)
        };
        let group = cx.shaders.bind_group(
            &device,
            &key,
            entry,
            &pipeline,
            0,
            &[
                (0, params.as_entire_binding()),
                (read, wgpu::BindingResource::TextureView(&source)),
                (2, wgpu::BindingResource::Sampler(&sampler)),
                (write, wgpu::BindingResource::TextureView(&target)),
            ],
        )?;
        cx.dispatch(
            entry,
            &pipeline,
            &[&group],
            (w.div_ceil(8), h.div_ceil(8), 1),
        );
        Ok(())
    }
}

impl Recipe for BuiltinBlur {
    fn declare<'a>(&'a self, renderer: &'a Renderer, fg: &mut FrameGraph<'a>) {
        if !fg.include(self.id) {
            return;
        }
        self.source.recipe.declare(renderer, fg);
        let name = |what| crate::recipe::pass_name("BlurBuiltin", self.owner, Some(what));
        fg.add_pass(
            name("horizontal"),
            self.owner,
            &[&self.source.name],
            &[(
                &self.half,
                TextureDesc::storage(FORMAT).size(SizeRule::Relative(0.5)),
            )],
            move |cx| self.run(cx, "horizontal", &self.source.name, &self.half),
        );
        fg.add_pass(
            name("vertical"),
            self.owner,
            &[&self.half],
            &[(&self.output, TextureDesc::storage(FORMAT))],
            move |cx| self.run(cx, "vertical", &self.half, &self.output),
        );
    }
}
