//! `CompositeLight`: CookTorrance's components, an ambient term, emission,
//! ambient occlusion, indirect diffuse light (GI) and reflections into one
//! HDR image, each weighted per material: AO by the AmbientOcclusion
//! feature's strength, GI by albedo, reflections by the Reflection
//! feature's strength, and a matcap on materials with MatCap (looked up by
//! the G-buffer normal, `shaders/lib/matcap.wgsl`). Where the G-buffer's
//! surface target is written (glTF surface maps, a shader node material),
//! its occlusion, metallic and emission count, with or without a material
//! world (`shaders/lib/surface_target.wgsl`). A reflection input is not
//! even rendered when no material reflects ("reflection culled: no reflective
//! material"); the matcap code is compiled in only when some material has
//! MatCap ("matcap shaded"). Unlit materials show their albedo: that
//! test shares the emission permutation (`EMISSION`, compiled when some
//! material emits or is unlit; "unlit shaded"), one flag test per pixel,
//! rather than doubling the composite's 6,720 permutations.

use std::sync::Arc;

use crate::error::RenderError;
use crate::frame_graph::{Bindings, FrameGraph, PassContext, Tex, TextureDesc};
use crate::gbuffer::GBuffer;
use crate::material::{
    FEATURE_AMBIENT_OCCLUSION, FEATURE_EMISSION, FEATURE_MATCAP, FEATURE_REFLECTION, FEATURE_UNLIT,
    MaterialTextures, MaterialWorld,
};
use crate::recipe::{Recipe, TextureRef, next_recipe_id};
use crate::renderer::Renderer;
use crate::report::PassName;
use crate::shaders::{Permutation, Sampling, ShaderKey};

pub(crate) mod key;
pub use key::{CompositeKey, LightPairs, MaterialAo, MaterialTerms, Shading, Textured};

/// What a CompositeLight combines.
#[derive(Clone, Debug)]
pub struct CompositeInputs {
    /// One per light type, one to four.
    pub components: Vec<LightComponents>,
    /// Ambient radiance, times albedo.
    pub ambient: [f32; 3],
    /// Emission and AO strength per material come from here.
    pub materials: Option<Arc<MaterialWorld>>,
    /// Ambient visibility in R (0..1), from an AO pass.
    pub occlusion: Option<TextureRef>,
    /// Indirect diffuse radiance arriving at each pixel (RGB; SSGI, image-based
    /// diffuse light): times albedo. Not darkened by `occlusion`: SSGI lets
    /// environment light in only along its escaping rays, and what the
    /// occluders block they bounce.
    pub gi: Option<TextureRef>,
    /// Specular reflection radiance (RGB, Fresnel already applied: the
    /// Reflection or SSR pass), times each material's Reflection strength.
    pub reflection: Option<TextureRef>,
}

/// Light types one CompositeLight adds up.
pub const MAX_COMPONENTS: usize = 4;

/// What one CookTorrance contributes: diffuse, specular and, where materials
/// have FakeSSS, a subsurface term.
#[derive(Clone, Debug)]
pub struct LightComponents {
    pub diffuse: TextureRef,
    pub specular: TextureRef,
    pub sss: Option<TextureRef>,
}

pub struct CompositeLight {
    id: u64,
    owner: Option<u32>,
    gbuffer: Arc<GBuffer>,
    /// One per light type, one to four.
    components: Vec<LightComponents>,
    /// The material world, bound when emission or per-material AO needs it.
    materials: Option<Arc<MaterialWorld>>,
    /// Some material has Emission: the emission code is compiled in.
    emission: bool,
    /// An AO texture, and whether materials weight it (some has AmbientOcclusion).
    occlusion: Option<TextureRef>,
    ao_per_material: bool,
    gi: Option<TextureRef>,
    /// Only when some material has Reflection.
    reflection: Option<TextureRef>,
    /// A reflection input was wired, and dropped: no material reflects.
    reflection_culled: bool,
    /// Some material has MatCap: the matcap code is compiled in.
    matcap: bool,
    /// Some material is Unlit: the albedo replaces its lighting.
    unlit: bool,
    params: wgpu::Buffer,
    pub output: String,
}

impl CompositeLight {
    pub fn new(
        renderer: &Renderer,
        owner: Option<u32>,
        gbuffer: Arc<GBuffer>,
        inputs: CompositeInputs,
    ) -> Result<Arc<Self>, RenderError> {
        let CompositeInputs {
            components,
            ambient,
            materials,
            occlusion,
            gi,
            reflection,
        } = inputs;
        // A feature no material has costs nothing: its code is not compiled in.
        let has = |feature: u32| {
            materials
                .as_ref()
                .is_some_and(|w| w.union_flags() & (1 << feature) != 0)
        };
        let unlit = has(FEATURE_UNLIT);
        let emission = has(FEATURE_EMISSION) || unlit;
        let ao_per_material = occlusion.is_some() && has(FEATURE_AMBIENT_OCCLUSION);
        let reflection_culled = reflection.is_some() && !has(FEATURE_REFLECTION);
        let reflection = reflection.filter(|_| has(FEATURE_REFLECTION));
        let matcap = has(FEATURE_MATCAP);
        // GI reads each material's metallic: metals take no diffuse light.
        let materials = materials.filter(|_| {
            emission || ao_per_material || reflection.is_some() || gi.is_some() || matcap
        });
        if components.is_empty() || components.len() > MAX_COMPONENTS {
            return Err(RenderError::Pass {
                pass: "CompositeLight".to_owned(),
                message: format!(
                    "takes 1 to {MAX_COMPONENTS} diffuse/specular pairs, got {}",
                    components.len()
                ),
            });
        }
        let id = next_recipe_id();
        let ambient = ambient.map(|a| {
            if a.is_finite() {
                a.clamp(0.0, 65000.0)
            } else {
                0.0
            }
        });
        let params = renderer.uniform(
            owner,
            "composite params",
            bytemuck::cast_slice(&[ambient[0], ambient[1], ambient[2], 0.0]),
        );
        Ok(Arc::new(CompositeLight {
            id,
            owner,
            gbuffer,
            components,
            materials,
            emission,
            occlusion,
            ao_per_material,
            gi,
            reflection,
            reflection_culled,
            matcap,
            unlit,
            params,
            output: format!("composite{id}"),
        }))
    }

    /// Whether emission reads a texture (surface maps' emission and
    /// occlusion come through the G-buffer's surface target instead).
    fn textured(&self) -> bool {
        self.materials
            .as_ref()
            .is_some_and(|w| self.emission && w.textured(1 << FEATURE_EMISSION))
    }

    /// The texture array a matcap reads its images from, when some MatCap
    /// material names a layer (else only the built-in matcap is used).
    fn matcap_images(&self) -> Option<&TextureRef> {
        self.materials
            .as_ref()
            .filter(|w| self.matcap && w.textured(1 << FEATURE_MATCAP))
            .and_then(|w| w.textures())
    }

    pub fn texture(self: &Arc<Self>) -> TextureRef {
        TextureRef {
            recipe: self.clone(),
            name: self.output.clone(),
        }
    }

    /// The permutation: a feature no material has is compiled out.
    fn key(&self) -> Result<ShaderKey, RenderError> {
        let pairs =
            LightPairs::new(self.components.iter().map(|c| c.sss.is_some())).ok_or_else(|| {
                RenderError::Graph(format!(
                    "CompositeLight takes 1 to {MAX_COMPONENTS} light components, not {}",
                    self.components.len()
                ))
            })?;
        let textured = |on: bool| match on {
            true => Textured::Textured,
            false => Textured::Flat,
        };
        let ao = self.occlusion.is_some();
        let shading = match &self.materials {
            None => Shading::Plain { ao },
            Some(_) => Shading::Materials(MaterialTerms {
                ao: match (ao, self.ao_per_material) {
                    (false, _) => MaterialAo::Off,
                    (true, false) => MaterialAo::On,
                    (true, true) => MaterialAo::PerMaterial,
                },
                emission: self.emission.then(|| textured(self.textured())),
                reflection: self.reflection.is_some(),
                matcap: self
                    .matcap
                    .then(|| textured(self.matcap_images().is_some())),
            }),
        };
        Ok(CompositeKey {
            pairs,
            shading,
            gi: self.gi.is_some(),
            // Occlusion, metallic and emission where the G-buffer resolved them.
            surface_target: self.gbuffer.targets.surface_feature().is_some(),
        }
        .key())
    }

    fn run(&self, cx: &mut PassContext<'_>, io: &CompositeIo) -> Result<(), RenderError> {
        if self.reflection_culled {
            cx.count("reflection culled: no reflective material", 1);
        }
        if self.matcap {
            cx.count("matcap shaded", 1);
        }
        if self.unlit {
            cx.count("unlit shaded", 1);
        }
        const DIFFUSE: [&str; MAX_COMPONENTS] = ["diffuse0", "diffuse1", "diffuse2", "diffuse3"];
        const SPECULAR: [&str; MAX_COMPONENTS] =
            ["specular0", "specular1", "specular2", "specular3"];
        const SSS: [&str; MAX_COMPONENTS] = ["sss0", "sss1", "sss2", "sss3"];
        let mut b = Bindings::new()
            .buffer("camera", self.gbuffer.camera_buffer())
            .buffer("params", &self.params)
            .texture("color", io.color)
            .texture("depth", io.depth)
            .texture("output", io.output)
            .texture_opt("surface_target", io.surface)
            .texture_opt("occlusion", io.occlusion)
            .texture_opt("gi", io.gi)
            .texture_opt("reflection", io.reflection)
            .texture_opt("normals", io.normals);
        for (k, light) in io.lights.iter().enumerate() {
            b = b
                .texture(DIFFUSE[k], light.diffuse)
                .texture(SPECULAR[k], light.specular)
                .texture_opt(SSS[k], light.sss);
        }
        if let Some(images) = io.matcap_images {
            // Clamped: the rim of a matcap must not wrap to the far side.
            b = b
                .array("matcap_images", images)
                .sampler("matcap_sampler", Sampling::LinearClamp);
        }
        if let Some(world) = &self.materials {
            b = b.extend(world.bindings(io.material_textures));
        }
        let (w, h) = self.gbuffer.pixel_size(cx.output_size);
        cx.dispatch_shader(
            "composite",
            &self.key()?,
            "main",
            b,
            (w.div_ceil(8), h.div_ceil(8), 1),
        )
    }
}

/// What a CompositeLight pass declared.
struct CompositeIo {
    color: Tex,
    depth: Tex,
    output: Tex,
    /// The G-buffer's surface target, where it has one.
    surface: Option<Tex>,
    lights: Vec<LightIo>,
    occlusion: Option<Tex>,
    gi: Option<Tex>,
    reflection: Option<Tex>,
    /// For MatCap: the normals, and the matcap images where a material names one.
    normals: Option<Tex>,
    matcap_images: Option<Tex>,
    material_textures: Option<MaterialTextures>,
}

struct LightIo {
    diffuse: Tex,
    specular: Tex,
    sss: Option<Tex>,
}

/// The name of an optional input.
fn name(t: &Option<TextureRef>) -> Option<&str> {
    t.as_ref().map(|t| t.name.as_str())
}

impl Recipe for CompositeLight {
    fn declare<'a>(&'a self, renderer: &'a Renderer, fg: &mut FrameGraph<'a>) {
        if !fg.include(self.id) {
            return;
        }
        self.gbuffer.declare(renderer, fg);
        let lights = self
            .components
            .iter()
            .flat_map(|c| [Some(&c.diffuse), Some(&c.specular), c.sss.as_ref()]);
        for input in [&self.occlusion, &self.gi, &self.reflection]
            .map(Option::as_ref)
            .into_iter()
            .chain(lights)
            .chain([self.matcap_images()])
            .flatten()
        {
            input.recipe.declare(renderer, fg);
        }
        if let Some(world) = &self.materials {
            world.declare_upstream(renderer, fg, self.textured());
        }
        let g = &self.gbuffer.targets;
        let mut pass = fg.pass(PassName::new("CompositeLight"), self.owner);
        let io = CompositeIo {
            color: pass.read(&g.color),
            depth: pass.read(&g.depth),
            surface: pass.read_opt(g.surface.as_deref()),
            lights: self
                .components
                .iter()
                .map(|c| LightIo {
                    diffuse: pass.read(&c.diffuse.name),
                    specular: pass.read(&c.specular.name),
                    sss: pass.read_opt(name(&c.sss)),
                })
                .collect(),
            occlusion: pass.read_opt(name(&self.occlusion)),
            gi: pass.read_opt(name(&self.gi)),
            reflection: pass.read_opt(name(&self.reflection)),
            normals: self.matcap.then(|| pass.read(&g.normals)),
            matcap_images: self.matcap_images().map(|t| pass.read(&t.name)),
            material_textures: self
                .materials
                .as_ref()
                .and_then(|w| w.read_textures(&mut pass, self.textured(), g.surface_targets())),
            output: pass.write(
                &self.output,
                TextureDesc::storage(wgpu::TextureFormat::Rgba16Float).size(self.gbuffer.size),
            ),
        };
        pass.run(move |cx| self.run(cx, &io));
    }
}
