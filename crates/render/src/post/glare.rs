//! `Glare`: bloom from a bright pass through a downsample/upsample chain of
//! mip-like sizes (half, quarter... of the source, `SizeRule::scaled`),
//! then composited over the source with chromatic aberration
//! (shaders/post/glare.wgsl). Intensity 0 and aberration 0 cost one copy.

use std::sync::Arc;

use crate::error::RenderError;
use crate::frame_graph::{Bindings, FrameGraph, PassContext, Tex, TextureDesc};
use crate::recipe::{Recipe, TextureRef, next_recipe_id};
use crate::renderer::Renderer;
use crate::report::PassName;
use crate::shaders::{Permutation, Sampling};

pub use super::glare_key::GlareKey;

/// Counted when a Glare had nothing to add (intensity and aberration 0) and only copied.
pub const SKIPPED: &str = "glare skipped (nothing to add)";

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GlareSettings {
    /// Luminance below which nothing glows.
    pub threshold: f32,
    /// How much of the glow is added.
    pub intensity: f32,
    /// 0..1: how much each smaller (wider) level adds to the one above it.
    pub spread: f32,
    /// Red and blue pushed apart radially by this fraction of the distance to the centre.
    pub aberration: f32,
    /// Levels of the chain (the quality): more reach wider.
    pub levels: u32,
}

impl Default for GlareSettings {
    fn default() -> Self {
        GlareSettings {
            threshold: 1.0,
            intensity: 0.3,
            spread: 0.8,
            aberration: 0.003,
            levels: 6,
        }
    }
}

impl GlareSettings {
    pub fn clean(self) -> Self {
        let pick = |v: f32, lo: f32, hi: f32, fallback: f32| {
            if v.is_finite() {
                v.clamp(lo, hi)
            } else {
                fallback
            }
        };
        GlareSettings {
            threshold: pick(self.threshold, 0.0, 65000.0, 1.0),
            intensity: pick(self.intensity, 0.0, 1000.0, 0.3),
            spread: pick(self.spread, 0.0, 1.0, 0.8),
            aberration: pick(self.aberration, -0.5, 0.5, 0.0),
            levels: self.levels.clamp(1, 12),
        }
    }
}

pub struct Glare {
    id: u64,
    owner: Option<u32>,
    source: TextureRef,
    settings: GlareSettings,
    params: wgpu::Buffer,
    pub output: String,
}

impl Glare {
    pub fn new(
        renderer: &Renderer,
        owner: Option<u32>,
        source: TextureRef,
        settings: GlareSettings,
    ) -> Arc<Self> {
        let id = next_recipe_id();
        let s = settings.clean();
        let norm: f32 = (0..s.levels).map(|i| s.spread.powi(i as i32)).sum();
        let params = super::uniform(
            renderer,
            owner,
            "glare",
            &super::words(&[
                s.threshold,
                s.intensity,
                s.spread,
                s.aberration,
                1.0 / norm.max(1e-6),
                0.0,
                0.0,
                0.0,
            ]),
        );
        Arc::new(Glare {
            id,
            owner,
            source,
            settings: s,
            params,
            output: format!("glare{id}"),
        })
    }

    pub fn texture(self: &Arc<Self>) -> TextureRef {
        TextureRef {
            recipe: self.clone(),
            name: self.output.clone(),
        }
    }

    fn down(&self, level: usize) -> String {
        format!("glare{} down{level}", self.id)
    }

    fn up(&self, level: usize) -> String {
        format!("glare{} up{level}", self.id)
    }

    /// One of glare.wgsl's entry points: `source` (and the `lower` level of
    /// the chain) into `output`.
    fn run(
        &self,
        cx: &mut PassContext<'_>,
        entry: &'static str,
        source: Tex,
        lower: Option<Tex>,
        output: Tex,
    ) -> Result<(), RenderError> {
        // The composite reads the source through the sampler too where its
        // format filters (the other entries read their source by texel).
        let filterable = entry == "composite"
            && matches!(
                cx.texture(source)?
                    .format()
                    .sample_type(None, Some(cx.gpu.device.features())),
                Some(wgpu::TextureSampleType::Float { filterable: true })
            );
        let size = cx.size_of(output)?;
        let bindings = Bindings::new()
            .buffer("params", &self.params)
            .texture("source", source)
            .texture_opt("lower", lower)
            .texture("output", output)
            // The chain's levels are read through it (bright and copy bind none).
            .sampler("linear", Sampling::LinearClamp);
        cx.dispatch_shader(
            entry,
            &GlareKey {
                filtered_source: filterable,
            }
            .key(),
            entry,
            bindings,
            super::per_pixel(size),
        )
    }
}

impl Recipe for Glare {
    fn declare<'a>(&'a self, renderer: &'a Renderer, fg: &mut FrameGraph<'a>) {
        if !fg.include(self.id) {
            return;
        }
        self.source.recipe.declare(renderer, fg);
        // The source's size (`FrameGraph::effect_size`), and the chain's
        // levels halvings of it: the passes read texel for texel.
        let source_size = fg.effect_size(&self.source.name);
        let full = TextureDesc::storage(wgpu::TextureFormat::Rgba16Float).size(source_size);
        let name = |what: std::borrow::Cow<'static, str>| PassName::new("Glare").step(what);
        if self.settings.intensity == 0.0 && self.settings.aberration == 0.0 {
            super::declare_copy(
                fg,
                name("copy".into()),
                self.owner,
                &self.source.name,
                (&self.output, full),
                SKIPPED,
            );
            return;
        }
        // No level smaller than 2 pixels: a chain of 1x1 levels adds nothing.
        let (w, h) = source_size.pixels(fg.output_size());
        let mut levels = 1usize;
        while levels < self.settings.levels as usize && (w.min(h) >> (levels + 1)) >= 2 {
            levels += 1;
        }
        let level = |l: usize| full.size(source_size.scaled(0.5f32.powi(l as i32 + 1)));
        // The pipelines `run` dispatches (frame_graph/gather.rs): the
        // composite's is the one of a filterable source, the usual one.
        for (entry, filtered_source, used) in [
            ("bright", false, true),
            ("down", false, levels > 1),
            ("up", false, levels > 1),
            ("composite", true, true),
        ] {
            if used {
                fg.will_dispatch(&GlareKey { filtered_source }.key(), entry);
            }
        }
        let mut pass = fg.pass(name("bright pass".into()), self.owner);
        let source = pass.read(&self.source.name);
        let output = pass.write(&self.down(0), level(0));
        pass.run(move |cx| self.run(cx, "bright", source, None, output));
        for l in 1..levels {
            let mut pass = fg.pass(name(format!("down {l}").into()), self.owner);
            let source = pass.read(&self.down(l - 1));
            let output = pass.write(&self.down(l), level(l));
            pass.run(move |cx| self.run(cx, "down", source, None, output));
        }
        // The smallest level is its own "up"; each larger one adds the one below.
        let lower_of = |l: usize| -> String {
            if l + 1 == levels {
                self.down(l)
            } else {
                self.up(l)
            }
        };
        for l in (0..levels.saturating_sub(1)).rev() {
            let mut pass = fg.pass(name(format!("up {l}").into()), self.owner);
            let source = pass.read(&self.down(l));
            let lower = pass.read(&lower_of(l + 1));
            let output = pass.write(&self.up(l), level(l));
            pass.run(move |cx| self.run(cx, "up", source, Some(lower), output));
        }
        let mut pass = fg.pass(name("composite".into()), self.owner);
        let source = pass.read(&self.source.name);
        let top = pass.read(&lower_of(0));
        let output = pass.write(&self.output, full);
        pass.run(move |cx| self.run(cx, "composite", source, Some(top), output));
    }
}
