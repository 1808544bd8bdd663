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
//! MatCap ("matcap shaded").

use std::sync::Arc;

use crate::error::RenderError;
use crate::frame_graph::{FrameGraph, PassContext, TextureDesc};
use crate::gbuffer::GBuffer;
use crate::material::{
    FEATURE_AMBIENT_OCCLUSION, FEATURE_EMISSION, FEATURE_MATCAP, FEATURE_REFLECTION, MaterialWorld,
};
use crate::recipe::{Recipe, TextureRef, next_recipe_id};
use crate::renderer::Renderer;
use crate::shaders::ShaderKey;

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
        let emission = has(FEATURE_EMISSION);
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

    fn run(&self, cx: &mut PassContext<'_>) -> Result<(), RenderError> {
        let device = cx.gpu.device.clone();
        let mut features: Vec<&'static str> = ["LIGHTS_2", "LIGHTS_3", "LIGHTS_4"]
            .into_iter()
            .take(self.components.len().saturating_sub(1))
            .collect();
        if self.emission {
            features.push("EMISSION");
        }
        if self.occlusion.is_some() {
            features.push("AO");
        }
        if self.ao_per_material {
            features.push("AO_PER_MATERIAL");
        }
        if self.textured() {
            features.push("MATERIAL_TEXTURES");
        }
        if self.materials.is_some() {
            features.push("MATERIALS");
        }
        // Occlusion, metallic and emission where the G-buffer resolved them.
        features.extend(self.gbuffer.targets.surface_feature());
        if self.gi.is_some() {
            features.push("GI");
        }
        if self.reflection.is_some() {
            features.push("REFLECTION");
        }
        if self.reflection_culled {
            cx.count("reflection culled: no reflective material", 1);
        }
        if self.matcap {
            features.push("MATCAP");
            cx.count("matcap shaded", 1);
        }
        if self.matcap_images().is_some() {
            features.push("MATCAP_TEXTURE");
        }
        for (k, c) in self.components.iter().enumerate() {
            if c.sss.is_some() {
                features.push(["SSS_1", "SSS_2", "SSS_3", "SSS_4"][k]);
            }
        }
        let key = ShaderKey::new("lighting/composite.wgsl", features);
        let pipeline = cx.shaders.compute_pipeline(&device, &key, "main")?;
        let g = &self.gbuffer.targets;
        let fixed = [
            cx.view_named(&g.color)?,
            cx.view_named(&g.depth)?,
            cx.view_named(&self.output)?,
        ];
        let mut lights = Vec::new();
        let mut subsurface = Vec::new();
        for (k, c) in self.components.iter().enumerate() {
            lights.push((
                cx.view_named(&c.diffuse.name)?,
                cx.view_named(&c.specular.name)?,
            ));
            if let Some(sss) = &c.sss {
                subsurface.push((13 + k as u32, cx.view_named(&sss.name)?));
            }
        }
        let mut all = vec![
            (0, self.gbuffer.camera_buffer().as_entire_binding()),
            (1, self.params.as_entire_binding()),
            (2, wgpu::BindingResource::TextureView(&fixed[0])),
            (5, wgpu::BindingResource::TextureView(&fixed[1])),
            (6, wgpu::BindingResource::TextureView(&fixed[2])),
        ];
        // Pair 0 at bindings 3 and 4, pairs 1..3 from binding 7 on.
        for (k, (diffuse, specular)) in lights.iter().enumerate() {
            let (d, s) = if k == 0 {
                (3, 4)
            } else {
                (5 + 2 * k as u32, 6 + 2 * k as u32)
            };
            all.push((d, wgpu::BindingResource::TextureView(diffuse)));
            all.push((s, wgpu::BindingResource::TextureView(specular)));
        }
        let surface = match &g.surface {
            Some(name) => Some(cx.view_named(name)?),
            None => None,
        };
        if let Some(view) = &surface {
            all.push((
                crate::gbuffer::SURFACE_TARGET_BINDING,
                wgpu::BindingResource::TextureView(view),
            ));
        }
        let occlusion = match &self.occlusion {
            Some(ao) => Some(cx.view_named(&ao.name)?),
            None => None,
        };
        if let Some(view) = &occlusion {
            all.push((17, wgpu::BindingResource::TextureView(view)));
        }
        let gi = match &self.gi {
            Some(t) => Some(cx.view_named(&t.name)?),
            None => None,
        };
        if let Some(view) = &gi {
            all.push((18, wgpu::BindingResource::TextureView(view)));
        }
        let reflection = match &self.reflection {
            Some(t) => Some(cx.view_named(&t.name)?),
            None => None,
        };
        if let Some(view) = &reflection {
            all.push((19, wgpu::BindingResource::TextureView(view)));
        }
        for (binding, view) in &subsurface {
            all.push((*binding, wgpu::BindingResource::TextureView(view)));
        }
        let normals = if self.matcap {
            Some(cx.view_named(&g.normals)?)
        } else {
            None
        };
        if let Some(view) = &normals {
            all.push((22, wgpu::BindingResource::TextureView(view)));
        }
        let matcap_images = match self.matcap_images() {
            Some(t) => Some((
                cx.view_of(
                    &cx.texture_named(&t.name)?.clone(),
                    crate::texture_pool::ViewSpec::array(),
                ),
                // Clamped: the rim of a matcap must not wrap to the far side.
                cx.sampler(crate::shaders::Sampling::LinearClamp),
            )),
            None => None,
        };
        if let Some((images, sampler)) = &matcap_images {
            all.push((20, wgpu::BindingResource::TextureView(images)));
            all.push((21, wgpu::BindingResource::Sampler(sampler)));
        }
        let group = cx
            .shaders
            .bind_group(&device, &key, "main", &pipeline, 0, &all)?;
        let material_group = match &self.materials {
            Some(world) => Some(world.bind_group(
                cx,
                &key,
                &pipeline,
                self.textured(),
                self.gbuffer.targets.surface_targets(),
            )?),
            None => None,
        };
        let (w, h) = self.gbuffer.pixel_size(cx.output_size);
        let groups: Vec<&wgpu::BindGroup> = std::iter::once(&group)
            .chain(material_group.as_ref())
            .collect();
        cx.dispatch(
            "composite",
            &pipeline,
            &groups,
            (w.div_ceil(8), h.div_ceil(8), 1),
        );
        Ok(())
    }
}

impl Recipe for CompositeLight {
    fn declare<'a>(&'a self, renderer: &'a Renderer, fg: &mut FrameGraph<'a>) {
        if !fg.include(self.id) {
            return;
        }
        self.gbuffer.declare(renderer, fg);
        for input in [&self.occlusion, &self.gi, &self.reflection]
            .into_iter()
            .flatten()
        {
            input.recipe.declare(renderer, fg);
        }
        for c in &self.components {
            for texture in [Some(&c.diffuse), Some(&c.specular), c.sss.as_ref()]
                .into_iter()
                .flatten()
            {
                texture.recipe.declare(renderer, fg);
            }
        }
        let name = crate::recipe::pass_name("CompositeLight", self.owner, None);
        let g = &self.gbuffer.targets;
        let mut reads: Vec<&str> = vec![&g.color, &g.depth];
        reads.extend(g.surface.as_deref());
        reads.extend(
            [&self.occlusion, &self.gi, &self.reflection]
                .into_iter()
                .flatten()
                .map(|t| t.name.as_str()),
        );
        if let Some(world) = &self.materials {
            reads.extend(world.declare_textures(
                renderer,
                fg,
                self.textured(),
                g.surface_targets(),
            ));
        }
        if self.matcap {
            reads.push(&g.normals);
        }
        if let Some(images) = self.matcap_images() {
            images.recipe.declare(renderer, fg);
            reads.push(&images.name);
        }
        for c in &self.components {
            reads.extend(
                [Some(&c.diffuse), Some(&c.specular), c.sss.as_ref()]
                    .into_iter()
                    .flatten()
                    .map(|t| t.name.as_str()),
            );
        }
        fg.add_pass(
            name,
            self.owner,
            &reads,
            &[(
                &self.output,
                TextureDesc::storage(wgpu::TextureFormat::Rgba16Float).size(self.gbuffer.size),
            )],
            move |cx| self.run(cx),
        );
    }
}
