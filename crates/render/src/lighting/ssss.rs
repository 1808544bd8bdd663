//! `SSSS`: screen-space subsurface scattering over CookTorrance's
//! subsurface term (shaders/lighting/ssss.wgsl), a separable kernel driven
//! per material by the FakeSSS feature. When no material has FakeSSS (or
//! the width is 0) it runs nothing: its output is its input ("SSSS culled:
//! no subsurface material or width 0").

use std::sync::Arc;

use crate::error::RenderError;
use crate::frame_graph::{Bindings, FrameGraph, PassContext, Tex, TextureDesc};
use crate::gbuffer::GBuffer;
use crate::material::MaterialWorld;
use crate::recipe::{Recipe, TextureRef, next_recipe_id};
use crate::renderer::Renderer;
use crate::report::PassName;
use crate::shaders::{Permutation, ShaderKey};

pub use super::ssss_key::SsssKey;

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
        SsssKey {
            vertical,
            sources_2: n >= 2,
            sources_3: n >= 3,
        }
        .key()
    }

    fn pass(
        &self,
        cx: &mut PassContext<'_>,
        vertical: bool,
        io: &SsssIo,
    ) -> Result<(), RenderError> {
        const SOURCES: [&str; 3] = ["source", "source_b", "source_c"];
        const OUTPUTS: [&str; 3] = ["output", "output_b", "output_c"];
        let mut b = Bindings::new()
            .buffer("camera", self.gbuffer.camera_buffer())
            .buffer("params", &self.params)
            .texture("depth", io.depth)
            .texture("color", io.color)
            .extend(self.materials.bindings(None));
        for (k, (source, target)) in io.pairs.iter().enumerate() {
            b = b.texture(SOURCES[k], *source).texture(OUTPUTS[k], *target);
        }
        let (w, h) = self.gbuffer.pixel_size(cx.output_size);
        cx.dispatch_image(
            if vertical { "ssss y" } else { "ssss x" },
            &self.key(vertical),
            b,
            (w, h),
        )
    }
}

/// What one SSSS pass declared: per source, what it reads and what it writes.
struct SsssIo {
    depth: Tex,
    color: Tex,
    pairs: Vec<(Tex, Tex)>,
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
        // Across (x), each source into its own target; then down (y) into the outputs.
        let across: Vec<String> = (0..self.sources.len()).map(|k| self.across(k)).collect();
        let across: Vec<&str> = across.iter().map(String::as_str).collect();
        let sources: Vec<&str> = self.sources.iter().map(|s| s.name.as_str()).collect();
        let outputs: Vec<&str> = self.outputs.iter().map(String::as_str).collect();
        for (vertical, from, to) in [(false, &sources, &across), (true, &across, &outputs)] {
            let step = if vertical { "y" } else { "x" };
            let mut pass = fg.pass(PassName::new("SSSS").step(step), self.owner);
            let reads: Vec<Tex> = from.iter().map(|name| pass.read(name)).collect();
            let io = SsssIo {
                depth: pass.read(&g.depth),
                color: pass.read(&g.color),
                pairs: reads
                    .into_iter()
                    .zip(to.iter())
                    .map(|(read, name)| (read, pass.write(name, rgba)))
                    .collect(),
            };
            pass.will_dispatch(&self.key(vertical), "main");
            pass.run(move |cx| self.pass(cx, vertical, &io));
        }
    }
}
