//! `FXAA`: fast approximate anti-aliasing (shaders/post/fxaa.wgsl), one
//! compute pass, texture in, texture out, with a quality setting.

use std::sync::Arc;

use crate::error::RenderError;
use crate::frame_graph::{Bindings, FrameGraph, PassContext, Tex, TextureDesc};
use crate::recipe::{Recipe, TextureRef, next_recipe_id};
use crate::renderer::Renderer;
use crate::report::PassName;
use crate::shaders::Permutation;

pub use super::fxaa_key::FxaaKey;

/// How hard FXAA looks: more edge-search steps follow longer, shallower edges.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FxaaQuality {
    /// 4 steps, a coarse threshold: the cheapest.
    Low,
    /// 8 steps.
    Medium,
    /// 12 steps, the finest threshold.
    High,
}

impl FxaaQuality {
    /// (search steps, relative edge threshold, minimum threshold).
    fn settings(self) -> (f32, f32, f32) {
        match self {
            FxaaQuality::Low => (4.0, 0.25, 0.0833),
            FxaaQuality::Medium => (8.0, 0.166, 0.0625),
            FxaaQuality::High => (12.0, 0.125, 0.0312),
        }
    }
}

pub struct Fxaa {
    id: u64,
    owner: Option<u32>,
    source: TextureRef,
    params: wgpu::Buffer,
    pub output: String,
}

impl Fxaa {
    /// `subpixel` 0..1: how much sub-pixel aliasing is smoothed (0.75 is FXAA's default).
    pub fn new(
        renderer: &Renderer,
        owner: Option<u32>,
        source: TextureRef,
        quality: FxaaQuality,
        subpixel: f32,
    ) -> Arc<Self> {
        let id = next_recipe_id();
        let (steps, threshold, minimum) = quality.settings();
        let subpixel = if subpixel.is_finite() {
            subpixel.clamp(0.0, 1.0)
        } else {
            0.75
        };
        let params = renderer.kept_init(
            owner,
            "fxaa",
            bytemuck::cast_slice(&[steps, threshold, minimum, subpixel]),
            wgpu::BufferUsages::UNIFORM,
        );
        Arc::new(Fxaa {
            id,
            owner,
            source,
            params,
            output: format!("fxaa{id}"),
        })
    }

    pub fn texture(self: &Arc<Self>) -> TextureRef {
        TextureRef {
            recipe: self.clone(),
            name: self.output.clone(),
        }
    }

    fn run(&self, cx: &mut PassContext<'_>, source: Tex, output: Tex) -> Result<(), RenderError> {
        let size = cx.size_of(output)?;
        cx.dispatch_image(
            "fxaa",
            &FxaaKey.key(),
            Bindings::new()
                .buffer("params", &self.params)
                .texture("source", source)
                .texture("output", output),
            size,
        )
    }
}

impl Recipe for Fxaa {
    fn declare<'a>(&'a self, renderer: &'a Renderer, fg: &mut FrameGraph<'a>) {
        if !fg.include(self.id) {
            return;
        }
        self.source.recipe.declare(renderer, fg);
        let name = PassName::new("FXAA");
        // At its source's size (`FrameGraph::effect_size`): it reads texel for texel.
        let desc = TextureDesc::storage(wgpu::TextureFormat::Rgba16Float)
            .size(fg.effect_size(&self.source.name));
        let mut pass = fg.pass(name, self.owner);
        let source = pass.read(&self.source.name);
        let output = pass.write(&self.output, desc);
        pass.run(move |cx| self.run(cx, source, output));
    }
}
