//! `Tonemap`: exposure and one of Emeshe's operators (plus ACES and AgX),
//! HDR in, display-referred linear 0..1 out. The operator maths lives in
//! shaders/lib/tonemap.wgsl and, for tests, in `spreadlight_reference::tonemap`.
//! With an adapted luminance (`EyeAdaptation`'s output) the exposure becomes
//! `exposure * key / adapted` (the shader's `EYE_ADAPTATION` permutation).

use std::sync::Arc;

// The operator is named where its CPU maths is; the pass's callers find it here.
pub use spreadlight_reference::tonemap::TonemapOperator;

use crate::error::RenderError;
use crate::frame_graph::{Bindings, FrameGraph, PassContext, Tex, TextureDesc};
use crate::recipe::{Recipe, TextureRef, next_recipe_id};
use crate::renderer::Renderer;
use crate::report::PassName;
use crate::shaders::Permutation;

pub use super::tonemap_key::TonemapKey;

/// The key exposure maps an adapted luminance to: middle grey.
pub const DEFAULT_KEY: f32 = 0.18;

/// Exposure from an adapted luminance: `exposure * key / luminance`.
#[derive(Clone, Debug)]
pub struct AdaptedExposure {
    /// A 1x1 texture whose red channel is the adapted luminance (linear), e.g. `EyeAdaptation::texture`.
    pub luminance: TextureRef,
    /// What the adapted luminance maps to (0.18: middle grey).
    pub key: f32,
}

impl AdaptedExposure {
    pub fn new(luminance: TextureRef) -> Self {
        AdaptedExposure {
            luminance,
            key: DEFAULT_KEY,
        }
    }
}

pub struct Tonemap {
    id: u64,
    owner: Option<u32>,
    source: TextureRef,
    adaptation: Option<TextureRef>,
    params: wgpu::Buffer,
    pub output: String,
}

impl Tonemap {
    /// `exposure` is a linear multiplier.
    pub fn new(
        renderer: &Renderer,
        owner: Option<u32>,
        source: TextureRef,
        operator: TonemapOperator,
        exposure: f32,
        param: f32,
    ) -> Arc<Self> {
        Self::with_adaptation(renderer, owner, source, operator, exposure, param, None)
    }

    /// As [`Tonemap::new`]; with `adaptation` the exposure is `exposure * key / adapted luminance`.
    pub fn with_adaptation(
        renderer: &Renderer,
        owner: Option<u32>,
        source: TextureRef,
        operator: TonemapOperator,
        exposure: f32,
        param: f32,
        adaptation: Option<AdaptedExposure>,
    ) -> Arc<Self> {
        let id = next_recipe_id();
        let finite = |v: f32, fallback: f32| if v.is_finite() { v } else { fallback };
        let key = adaptation
            .as_ref()
            .map_or(DEFAULT_KEY, |a| finite(a.key, DEFAULT_KEY).clamp(0.0, 1e3));
        let params = renderer.kept_init(
            owner,
            "tonemap params",
            bytemuck::cast_slice(&[
                operator.id(),
                finite(exposure, 1.0).max(0.0).to_bits(),
                finite(param, 1.0).to_bits(),
                key.to_bits(),
            ]),
            wgpu::BufferUsages::UNIFORM,
        );
        Arc::new(Tonemap {
            id,
            owner,
            source,
            adaptation: adaptation.map(|a| a.luminance),
            params,
            output: format!("tonemap{id}"),
        })
    }

    pub fn texture(self: &Arc<Self>) -> TextureRef {
        TextureRef {
            recipe: self.clone(),
            name: self.output.clone(),
        }
    }

    fn run(&self, cx: &mut PassContext<'_>, io: &TonemapIo) -> Result<(), RenderError> {
        let size = cx.size_of(io.output)?;
        cx.dispatch_image(
            "tonemap",
            &TonemapKey {
                eye_adaptation: io.adaptation.is_some(),
            }
            .key(),
            Bindings::new()
                .buffer("params", &self.params)
                .texture("source", io.source)
                .texture("output", io.output)
                .texture_opt("adaptation", io.adaptation),
            size,
        )
    }
}

/// What the tonemap pass declared.
struct TonemapIo {
    source: Tex,
    /// The adapted luminance, with eye adaptation.
    adaptation: Option<Tex>,
    output: Tex,
}

impl Recipe for Tonemap {
    fn declare<'a>(&'a self, renderer: &'a Renderer, fg: &mut FrameGraph<'a>) {
        if !fg.include(self.id) {
            return;
        }
        self.source.recipe.declare(renderer, fg);
        if let Some(adaptation) = &self.adaptation {
            adaptation.recipe.declare(renderer, fg);
        }
        let name = PassName::new("Tonemap");
        // At its source's size (`FrameGraph::effect_size`): it reads texel for texel.
        let desc = TextureDesc::storage(wgpu::TextureFormat::Rgba16Float)
            .size(fg.effect_size(&self.source.name));
        let mut pass = fg.pass(name, self.owner);
        let io = TonemapIo {
            source: pass.read(&self.source.name),
            adaptation: pass.read_opt(self.adaptation.as_ref().map(|a| a.name.as_str())),
            output: pass.write(&self.output, desc),
        };
        let key = TonemapKey {
            eye_adaptation: io.adaptation.is_some(),
        };
        pass.will_dispatch(&key.key(), "main");
        pass.run(move |cx| self.run(cx, &io));
    }
}
