//! The shader-node example blur (shaders/nodes/blur.wgsl) written as a
//! built-in pass: the same WGSL composed by the [`ShaderCache`](crate::shaders::ShaderCache),
//! its passes written out by hand (its bindings by the WGSL's names). It is the baseline the
//! `Blur (Shader)` node is benchmarked against (`patches/bench-shader-blur.ron` against `patches/bench-builtin-blur.ron`):
//! the two should cost the same on the GPU.

use std::sync::Arc;

use wgpu::util::DeviceExt;

use crate::error::RenderError;
use crate::frame_graph::{Bindings, FrameGraph, PassContext, Tex, TextureDesc};
use crate::recipe::{Recipe, TextureRef, next_recipe_id};
use crate::renderer::Renderer;
use crate::report::PassName;
use crate::shaders::{Permutation, Sampling};

pub use super::builtin_blur_key::BuiltinBlurKey;

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

    /// One direction: `entry` reads `input`, writes `output` (the shader's
    /// Params: radius, size, texel). The horizontal pass reads `source`
    /// and writes `half_out`, the vertical one reads `half` and writes `blurred`.
    fn run(
        &self,
        cx: &mut PassContext<'_>,
        entry: &'static str,
        input: Tex,
        output: Tex,
    ) -> Result<(), RenderError> {
        let (w, h) = cx.size_of(output)?;
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
        let (read, write) = if entry == "horizontal" {
            ("source", "half_out")
        } else {
            ("half", "blurred")
        };
        cx.dispatch_shader(
            entry,
            &BuiltinBlurKey.key(),
            entry,
            Bindings::new()
                .buffer("params", &params)
                .texture(read, input)
                .sampler("smp", Sampling::LinearClamp)
                .texture(write, output),
            (w.div_ceil(8), h.div_ceil(8), 1),
        )
    }
}

impl Recipe for BuiltinBlur {
    fn declare<'a>(&'a self, renderer: &'a Renderer, fg: &mut FrameGraph<'a>) {
        if !fg.include(self.id) {
            return;
        }
        self.source.recipe.declare(renderer, fg);
        let name = |what| PassName::new("BlurBuiltin").step(what);
        // At its source's size, through a half-size temporary (`FrameGraph::effect_size`).
        let size = fg.effect_size(&self.source.name);
        let mut pass = fg.pass(name("horizontal"), self.owner);
        let source = pass.read(&self.source.name);
        let half = pass.write(
            &self.half,
            TextureDesc::storage(FORMAT).size(size.scaled(0.5)),
        );
        pass.run(move |cx| self.run(cx, "horizontal", source, half));
        let mut pass = fg.pass(name("vertical"), self.owner);
        let half = pass.read(&self.half);
        let output = pass.write(&self.output, TextureDesc::storage(FORMAT).size(size));
        pass.run(move |cx| self.run(cx, "vertical", half, output));
    }
}
