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
use crate::finite::finite_in;
use crate::frame_graph::{FrameGraph, TextureDesc};
use crate::gbuffer::GBuffer;
use crate::material::{
    FEATURE_AMBIENT_OCCLUSION, FEATURE_EMISSION, FEATURE_MATCAP, FEATURE_REFLECTION, FEATURE_UNLIT,
    MaterialWorld,
};
use crate::recipe::{Recipe, TextureRef, declare_inputs, name_of, next_recipe_id};
use crate::renderer::Renderer;
use crate::report::PassName;
use crate::shaders::{Permutation, Sampling};

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

/// Counted when a reflection input was wired but no material reflects.
const REFLECTION_CULLED: &str = "reflection culled: no reflective material";

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
    occlusion: Option<TextureRef>,
    gi: Option<TextureRef>,
    /// Only when some material has Reflection.
    reflection: Option<TextureRef>,
    /// The permutation: a feature no material has is compiled out. What the
    /// pass reads follows from it (a matcap's normals, textured emission).
    key: CompositeKey,
    /// The texture array a matcap reads its images from, when some MatCap
    /// material names a layer (else only the built-in matcap is used).
    matcap_images: Option<TextureRef>,
    /// What the pass counts each frame: a reflection input culled because no
    /// material reflects, matcap or unlit materials shaded.
    counts: Vec<&'static str>,
    /// The pairs of sums that fused light sets may write for two or more of
    /// the components, most first: read in their place when a frame
    /// declares one (lighting::light_sets, sums.rs).
    sums: Vec<super::light_sets::SumCandidate>,
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
        let pairs =
            LightPairs::new(components.iter().map(|c| c.sss.is_some())).ok_or_else(|| {
                RenderError::Pass {
                    pass: "CompositeLight".to_owned(),
                    message: format!(
                        "takes 1 to {MAX_COMPONENTS} diffuse/specular pairs, got {}",
                        components.len()
                    ),
                }
            })?;
        // A feature no material has costs nothing: its code is not compiled in.
        let has = |feature: u32| materials.as_ref().is_some_and(|w| w.has(feature));
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
        // Emission and matcaps read the texture array where a material names a layer.
        let textured = |feature: u32| materials.as_ref().filter(|w| w.textured(1 << feature));
        let matcap_images = textured(FEATURE_MATCAP).filter(|_| matcap);
        let matcap_images = matcap_images.and_then(|w| w.textures()).cloned();
        let ao = occlusion.is_some();
        let shading = match &materials {
            None => Shading::Plain { ao },
            Some(_) => Shading::Materials(MaterialTerms {
                ao: match (ao, ao_per_material) {
                    (false, _) => MaterialAo::Off,
                    (true, false) => MaterialAo::On,
                    (true, true) => MaterialAo::PerMaterial,
                },
                emission: emission.then(|| textured(FEATURE_EMISSION).is_some().into()),
                reflection: reflection.is_some(),
                matcap: matcap.then(|| matcap_images.is_some().into()),
            }),
        };
        let key = CompositeKey {
            pairs,
            shading,
            gi: gi.is_some(),
            // Occlusion, metallic and emission where the G-buffer resolved them.
            surface_target: gbuffer.targets.surface_feature().is_some(),
        };
        let counts = [
            (reflection_culled, REFLECTION_CULLED),
            (matcap, "matcap shaded"),
            (unlit, "unlit shaded"),
        ];
        let ambient = ambient.map(|a| finite_in(a, 0.0, 65000.0, 0.0));
        let params = renderer.uniform(
            owner,
            "composite params",
            bytemuck::cast_slice(&[ambient[0], ambient[1], ambient[2], 0.0]),
        );
        let id = next_recipe_id();
        let sums = super::light_sets::sum_candidates(
            &components
                .iter()
                .map(|c| (&c.diffuse, &c.specular, c.sss.as_ref()))
                .collect::<Vec<_>>(),
        );
        Ok(Arc::new(CompositeLight {
            id,
            owner,
            gbuffer,
            components,
            materials,
            occlusion,
            gi,
            reflection,
            key,
            matcap_images,
            counts: counts.into_iter().filter(|c| c.0).map(|c| c.1).collect(),
            sums,
            params,
            output: format!("composite{id}"),
        }))
    }

    pub fn texture(self: &Arc<Self>) -> TextureRef {
        TextureRef::of(self, &self.output)
    }

    /// The material terms the permutation compiles in.
    fn terms(&self) -> Option<MaterialTerms> {
        match self.key.shading {
            Shading::Materials(terms) => Some(terms),
            Shading::Plain { .. } => None,
        }
    }

    /// Whether emission reads a texture (surface maps' emission and
    /// occlusion come through the G-buffer's surface target instead).
    fn textured(&self) -> bool {
        self.terms().and_then(|t| t.emission) == Some(Textured::Textured)
    }
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
        let inputs = [&self.occlusion, &self.gi, &self.reflection].map(Option::as_ref);
        declare_inputs(renderer, fg, inputs.into_iter().flatten());
        // The CookTorrance recipes behind the components that can share
        // one dispatch, as one pass (when the renderer fuses light sets).
        super::light_sets::declare(renderer, fg, self.components.iter().map(|c| &c.diffuse));
        declare_inputs(renderer, fg, lights.flatten());
        // Light sets summed for these components (declared above, or by
        // another CompositeLight of the same sets): one pair in their place,
        // first; the other components after it, in order.
        let sum = self.sums.iter().find(|c| fg.planned(&c.diffuse).is_some());
        let mut pairs: smallvec::SmallVec<[(&str, &str, Option<&str>); MAX_COMPONENTS]> =
            smallvec::SmallVec::new();
        if let Some(sum) = sum {
            fg.count(super::light_sets::LIGHT_SUMS_READ, 1);
            pairs.push((&sum.diffuse, &sum.specular, None));
        }
        for (k, light) in self.components.iter().enumerate() {
            if sum.is_none_or(|c| c.members & (1 << k) == 0) {
                pairs.push((
                    &light.diffuse.name,
                    &light.specular.name,
                    name_of(&light.sss),
                ));
            }
        }
        let key = CompositeKey {
            pairs: LightPairs::new(pairs.iter().map(|p| p.2.is_some())).unwrap_or(self.key.pairs),
            ..self.key
        };
        declare_inputs(renderer, fg, &self.matcap_images);
        if let Some(world) = &self.materials {
            world.declare_upstream(renderer, fg, self.textured());
        }
        const DIFFUSE: [&str; MAX_COMPONENTS] = ["diffuse0", "diffuse1", "diffuse2", "diffuse3"];
        const SPECULAR: [&str; MAX_COMPONENTS] =
            ["specular0", "specular1", "specular2", "specular3"];
        const SSS: [&str; MAX_COMPONENTS] = ["sss0", "sss1", "sss2", "sss3"];
        let g = &self.gbuffer.targets;
        let mut pass = fg.pass(PassName::new("CompositeLight"), self.owner);
        pass.input("color", &g.color);
        pass.input("depth", &g.depth);
        pass.input_opt("surface_target", g.surface.as_deref());
        for (k, (diffuse, specular, sss)) in pairs.into_iter().enumerate() {
            pass.input(DIFFUSE[k], diffuse);
            pass.input(SPECULAR[k], specular);
            pass.input_opt(SSS[k], sss);
        }
        pass.input_opt("occlusion", name_of(&self.occlusion));
        pass.input_opt("gi", name_of(&self.gi));
        pass.input_opt("reflection", name_of(&self.reflection));
        if self.terms().is_some_and(|t| t.matcap.is_some()) {
            pass.input("normals", &g.normals);
        }
        if let Some(images) = &self.matcap_images {
            let images = pass.read(&images.name);
            // Clamped: the rim of a matcap must not wrap to the far side.
            pass.bind(|b| {
                b.array("matcap_images", images)
                    .sampler("matcap_sampler", Sampling::LinearClamp)
            });
        }
        if let Some(world) = &self.materials {
            let textures = world.read_textures(&mut pass, self.textured(), g.surface_targets());
            pass.bind(|b| b.extend(world.bindings(textures)));
        }
        let desc = TextureDesc::storage(wgpu::TextureFormat::Rgba16Float).size(self.gbuffer.size);
        pass.output("output", &self.output, desc);
        pass.bind(|b| {
            b.buffer("camera", self.gbuffer.camera_buffer())
                .buffer("params", &self.params)
        });
        pass.will_dispatch(&key.key(), "main");
        pass.run_bound(move |cx, b| {
            for counter in &self.counts {
                cx.count(counter, 1);
            }
            let size = self.gbuffer.pixel_size(cx.output_size);
            cx.dispatch_image("composite", &key.key(), b, size)
        });
    }
}
