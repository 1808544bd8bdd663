//! `SSSS`: screen-space subsurface scattering over CookTorrance's
//! subsurface term (shaders/lighting/ssss.wgsl), a separable kernel driven
//! per material by the FakeSSS feature. When no material has FakeSSS (or
//! the width is 0) it runs nothing: its output is its input ("SSSS culled:
//! no subsurface material or width 0").

use std::sync::Arc;

use crate::error::RenderError;
use crate::frame_graph::{FrameGraph, PassContext, TextureDesc};
use crate::gbuffer::GBuffer;
use crate::material::MaterialWorld;
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

/// Sources one pass pair blurs together (shaders/lighting/ssss.wgsl,
/// SOURCES_2 and SOURCES_3): the taps' depths, materials and weights are
/// the same for each, so three light types' terms cost little more than one.
pub const SOURCES_PER_PASS: usize = 3;

pub struct Ssss {
    id: u64,
    owner: Option<u32>,
    gbuffer: Arc<GBuffer>,
    /// One to SOURCES_PER_PASS, each blurred into the output of its index.
    sources: Vec<TextureRef>,
    materials: Arc<MaterialWorld>,
    params: wgpu::Buffer,
    prefix: String,
    pub outputs: Vec<String>,
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
        let mut out = Self::textures(
            renderer,
            owner,
            gbuffer,
            vec![source],
            materials,
            width,
            quality,
        );
        out.remove(0)
    }

    /// [`Ssss::texture`] for each of `sources` (a spread, one term per
    /// light type), up to [`SOURCES_PER_PASS`] blurred in one pass pair.
    pub fn textures(
        renderer: &Renderer,
        owner: Option<u32>,
        gbuffer: Arc<GBuffer>,
        sources: Vec<TextureRef>,
        materials: Option<Arc<MaterialWorld>>,
        width: f32,
        quality: SsssQuality,
    ) -> Vec<TextureRef> {
        let width = if width.is_finite() {
            width.clamp(0.0, 1e3)
        } else {
            0.0
        };
        // No material scatters, or nothing to scatter over: the inputs as they are.
        let materials = materials
            .filter(|w| w.scatters_subsurface())
            .filter(|_| width > 0.0);
        let Some(materials) = materials else {
            return sources
                .into_iter()
                .map(|source| {
                    let name = source.name.clone();
                    TextureRef {
                        recipe: Arc::new(Skipped {
                            id: next_recipe_id(),
                            source,
                        }),
                        name,
                    }
                })
                .collect();
        };
        let params = renderer.kept_init(
            owner,
            "ssss params",
            bytemuck::cast_slice(&[width.to_bits(), quality.taps(), 0, 0]),
            wgpu::BufferUsages::UNIFORM,
        );
        let mut out = Vec::with_capacity(sources.len());
        for chunk in sources.chunks(SOURCES_PER_PASS) {
            let id = next_recipe_id();
            let prefix = format!("ssss{id}");
            let recipe = Arc::new(Ssss {
                id,
                owner,
                gbuffer: gbuffer.clone(),
                sources: chunk.to_vec(),
                materials: materials.clone(),
                params: params.clone(),
                outputs: (0..chunk.len())
                    .map(|k| format!("{prefix}/out{k}"))
                    .collect(),
                prefix,
            });
            for name in &recipe.outputs {
                out.push(TextureRef {
                    name: name.clone(),
                    recipe: recipe.clone(),
                });
            }
        }
        out
    }

    /// The first pass's output for source `k`.
    fn across(&self, k: usize) -> String {
        format!("{}/x{k}", self.prefix)
    }

    /// The source permutation: one, two or three sources a pass.
    fn key(&self, vertical: bool) -> ShaderKey {
        let n = self.sources.len();
        let features = [
            vertical.then_some("VERTICAL"),
            (n >= 2).then_some("SOURCES_2"),
            (n >= 3).then_some("SOURCES_3"),
        ];
        ShaderKey::new("lighting/ssss.wgsl", features.into_iter().flatten())
    }

    fn pass(&self, cx: &mut PassContext<'_>, vertical: bool) -> Result<(), RenderError> {
        let device = cx.gpu.device.clone();
        let key = self.key(vertical);
        let pipeline = cx.shaders.compute_pipeline(&device, &key, "main")?;
        let g = &self.gbuffer.targets;
        // (source, target) per source: its input then the x pass's output,
        // or the x pass's output then the final one.
        let mut pairs = Vec::with_capacity(self.sources.len());
        for (k, source) in self.sources.iter().enumerate() {
            pairs.push(if vertical {
                (
                    cx.view_named(&self.across(k))?,
                    cx.view_named(&self.outputs[k])?,
                )
            } else {
                (
                    cx.view_named(&source.name)?,
                    cx.view_named(&self.across(k))?,
                )
            });
        }
        let (depth, color) = (cx.view_named(&g.depth)?, cx.view_named(&g.color)?);
        let mut all = vec![
            (0, self.gbuffer.camera_buffer().as_entire_binding()),
            (1, self.params.as_entire_binding()),
            (3, wgpu::BindingResource::TextureView(&depth)),
            (4, wgpu::BindingResource::TextureView(&color)),
        ];
        // Bindings 2 and 5, then 6 and 7, then 8 and 9 (ssss.wgsl).
        for (k, (source, target)) in pairs.iter().enumerate() {
            let (read, write) = if k == 0 {
                (2, 5)
            } else {
                (4 + 2 * k as u32, 5 + 2 * k as u32)
            };
            all.push((read, wgpu::BindingResource::TextureView(source)));
            all.push((write, wgpu::BindingResource::TextureView(target)));
        }
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
        for source in &self.sources {
            source.recipe.declare(renderer, fg);
        }
        let g = &self.gbuffer.targets;
        let rgba = TextureDesc::storage(wgpu::TextureFormat::Rgba16Float).size(self.gbuffer.size);
        let across: Vec<String> = (0..self.sources.len()).map(|k| self.across(k)).collect();
        let mut reads: Vec<&str> = self.sources.iter().map(|s| s.name.as_str()).collect();
        reads.extend([g.depth.as_str(), g.color.as_str()]);
        let writes: Vec<(&str, TextureDesc)> = across.iter().map(|x| (x.as_str(), rgba)).collect();
        fg.add_pass(
            pass_name("SSSS", self.owner, Some("x")),
            self.owner,
            &reads,
            &writes,
            move |cx| self.pass(cx, false),
        );
        let mut reads: Vec<&str> = across.iter().map(String::as_str).collect();
        reads.extend([g.depth.as_str(), g.color.as_str()]);
        let writes: Vec<(&str, TextureDesc)> =
            self.outputs.iter().map(|o| (o.as_str(), rgba)).collect();
        fg.add_pass(
            pass_name("SSSS", self.owner, Some("y")),
            self.owner,
            &reads,
            &writes,
            move |cx| self.pass(cx, true),
        );
    }
}
