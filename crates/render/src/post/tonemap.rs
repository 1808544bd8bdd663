//! `Tonemap`: exposure and one of Emeshe's operators (plus ACES and AgX),
//! HDR in, display-referred linear 0..1 out. The operator maths lives in
//! shaders/lib/tonemap.wgsl and, for tests, in `crate::reference::tonemap`.
//! With an adapted luminance (`EyeAdaptation`'s output) the exposure becomes
//! `exposure * key / adapted` (the shader's `EYE_ADAPTATION` permutation).

use std::sync::Arc;

use crate::error::RenderError;
use crate::frame_graph::{FrameGraph, PassContext, SizeRule, TextureDesc};
use crate::recipe::{Recipe, TextureRef, next_recipe_id};
use crate::renderer::Renderer;
use crate::shaders::ShaderKey;

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
    /// `operator` is one of `reference::tonemap`'s `TONEMAP_*` ids; `exposure` a linear multiplier.
    pub fn new(
        renderer: &Renderer,
        owner: Option<u32>,
        source: TextureRef,
        operator: u32,
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
        operator: u32,
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
                operator,
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

    fn run(&self, cx: &mut PassContext<'_>) -> Result<(), RenderError> {
        let features = self.adaptation.as_ref().map(|_| "EYE_ADAPTATION");
        let key = ShaderKey::new("post/tonemap.wgsl", features);
        let (source, output) = (
            cx.view_named(&self.source.name)?,
            cx.view_named(&self.output)?,
        );
        let adaptation = match &self.adaptation {
            Some(a) => Some(cx.view_named(&a.name)?),
            None => None,
        };
        let (w, h) = {
            let t = cx.texture_named(&self.output)?;
            (t.width(), t.height())
        };
        let mut all = vec![
            (0, self.params.as_entire_binding()),
            (1, wgpu::BindingResource::TextureView(&source)),
            (2, wgpu::BindingResource::TextureView(&output)),
        ];
        if let Some(view) = &adaptation {
            all.push((3, wgpu::BindingResource::TextureView(view)));
        }
        cx.dispatch_image_numbered("tonemap", &key, &all, (w, h))
    }
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
        let name = crate::recipe::pass_name("Tonemap", self.owner, None);
        let desc =
            TextureDesc::storage(wgpu::TextureFormat::Rgba16Float).size(SizeRule::Relative(1.0));
        let mut reads = vec![self.source.name.as_str()];
        if let Some(adaptation) = &self.adaptation {
            reads.push(&adaptation.name);
        }
        fg.add_pass(
            name,
            self.owner,
            &reads,
            &[(&self.output, desc)],
            move |cx| self.run(cx),
        );
    }
}
