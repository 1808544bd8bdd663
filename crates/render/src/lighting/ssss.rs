//! `SSSS`: screen-space subsurface scattering over CookTorrance's
//! subsurface term (shaders/lighting/ssss.wgsl), a separable kernel driven
//! per material by the FakeSSS feature. When no material has FakeSSS (or
//! the width is 0) it runs nothing: its output is its input ("SSSS culled:
//! no subsurface material or width 0").

use std::sync::Arc;

use crate::error::RenderError;
use crate::frame_graph::{FrameGraph, PassContext, TextureDesc};
use crate::gbuffer::GBuffer;
use crate::material::{FEATURE_FAKE_SSS, MaterialWorld};
use crate::recipe::{Recipe, TextureRef, next_recipe_id, pass_name};
use crate::renderer::Renderer;
use crate::shaders::ShaderKey;

/// Taps per side: Low 4, Medium 8, High 16.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SsssQuality {
    Low,
    Medium,
    High,
}

impl SsssQuality {
    pub fn taps(self) -> u32 {
        match self {
            SsssQuality::Low => 4,
            SsssQuality::Medium => 8,
            SsssQuality::High => 16,
        }
    }
}

pub struct Ssss {
    id: u64,
    owner: Option<u32>,
    gbuffer: Arc<GBuffer>,
    source: TextureRef,
    materials: Arc<MaterialWorld>,
    params: wgpu::Buffer,
    prefix: String,
    pub output: String,
}

/// When no material scatters: the input, unchanged, and the decision counted.
struct Skipped {
    id: u64,
    source: TextureRef,
}

impl Recipe for Skipped {
    fn declare<'a>(&'a self, renderer: &'a Renderer, fg: &mut FrameGraph<'a>) {
        if !fg.include(self.id) {
            return;
        }
        self.source.recipe.declare(renderer, fg);
        fg.count("SSSS culled: no subsurface material or width 0", 1);
    }
}

impl Ssss {
    /// `width`: the widest channel's reach in world units. Returns the
    /// scattered texture, or `source` itself when no material has FakeSSS.
    pub fn texture(
        renderer: &Renderer,
        owner: Option<u32>,
        gbuffer: Arc<GBuffer>,
        source: TextureRef,
        materials: Option<Arc<MaterialWorld>>,
        width: f32,
        quality: SsssQuality,
    ) -> TextureRef {
        let id = next_recipe_id();
        let width = if width.is_finite() {
            width.clamp(0.0, 1e3)
        } else {
            0.0
        };
        // No material scatters, or nothing to scatter over: the input as it is.
        let materials = materials
            .filter(|w| w.union_flags() & (1 << FEATURE_FAKE_SSS) != 0)
            .filter(|_| width > 0.0);
        let Some(materials) = materials else {
            let name = source.name.clone();
            return TextureRef {
                recipe: Arc::new(Skipped { id, source }),
                name,
            };
        };
        let params = renderer.kept_init(
            owner,
            "ssss params",
            bytemuck::cast_slice(&[width.to_bits(), quality.taps(), 0, 0]),
            wgpu::BufferUsages::UNIFORM,
        );
        let prefix = format!("ssss{id}");
        let recipe = Arc::new(Ssss {
            id,
            owner,
            gbuffer,
            source,
            materials,
            params,
            output: format!("{prefix}/out"),
            prefix,
        });
        TextureRef {
            name: recipe.output.clone(),
            recipe,
        }
    }

    fn pass(&self, cx: &mut PassContext<'_>, vertical: bool) -> Result<(), RenderError> {
        let device = cx.gpu.device.clone();
        let (source, target) = if vertical {
            (format!("{}/x", self.prefix), self.output.clone())
        } else {
            (self.source.name.clone(), format!("{}/x", self.prefix))
        };
        let key = ShaderKey::new("lighting/ssss.wgsl", vertical.then_some("VERTICAL"));
        let pipeline = cx.shaders.compute_pipeline(&device, &key, "main")?;
        let g = &self.gbuffer.targets;
        let views = [
            cx.view(&source)?,
            cx.view(&g.depth)?,
            cx.view(&g.color)?,
            cx.view(&target)?,
        ];
        let mut all = vec![
            (0, self.gbuffer.camera_buffer().as_entire_binding()),
            (1, self.params.as_entire_binding()),
        ];
        all.extend(
            views
                .iter()
                .enumerate()
                .map(|(k, v)| (2 + k as u32, wgpu::BindingResource::TextureView(v))),
        );
        let group = cx
            .shaders
            .bind_group(&device, &key, "main", &pipeline, 0, &all)?;
        let materials =
            self.materials
                .bind_group(cx, &key, &pipeline, false, g.surface_targets())?;
        let (w, h) = self.gbuffer.pixel_size(cx.output_size);
        cx.dispatch(
            if vertical { "ssss y" } else { "ssss x" },
            &pipeline,
            &[&group, &materials],
            (w.div_ceil(8), h.div_ceil(8), 1),
        );
        Ok(())
    }
}

impl Recipe for Ssss {
    fn declare<'a>(&'a self, renderer: &'a Renderer, fg: &mut FrameGraph<'a>) {
        if !fg.include(self.id) {
            return;
        }
        self.gbuffer.declare(renderer, fg);
        self.source.recipe.declare(renderer, fg);
        let g = &self.gbuffer.targets;
        let rgba = TextureDesc::storage(wgpu::TextureFormat::Rgba16Float).size(self.gbuffer.size);
        let x = format!("{}/x", self.prefix);
        fg.add_pass(
            pass_name("SSSS", self.owner, Some("x")),
            self.owner,
            &[&self.source.name, &g.depth, &g.color],
            &[(&x, rgba)],
            move |cx| self.pass(cx, false),
        );
        fg.add_pass(
            pass_name("SSSS", self.owner, Some("y")),
            self.owner,
            &[&x, &g.depth, &g.color],
            &[(&self.output, rgba)],
            move |cx| self.pass(cx, true),
        );
    }
}
