//! `Reflection`: image-based light from an environment over the G-buffer:
//! Specular (the prefiltered environment along the reflected, or refracted,
//! direction times the split-sum factor) and Diffuse (irradiance / pi,
//! albedo not applied). Only materials with the Reflection feature get it;
//! when none has it the pass only clears and the environment is not built.

use spreadlight_graph::{NodeDef, PinType, Registry, ResourceKind, Spread};
use spreadlight_render::TextureRef;
use spreadlight_render::environment::{Environment, Reflection, ReflectionMode};
use spreadlight_render::gbuffer::GBuffer;
use spreadlight_render::material::MaterialWorld;

use crate::gpu::{renderer, resource_spread, resources};

pub fn register(r: &mut Registry) {
    r.add(
        NodeDef::new(
            "Reflection",
            super::CATEGORY,
            "Environment light on the G-buffer for materials with the Reflection feature (others get zero). Specular: the \
             Environment prefiltered at the material's CookTorrance roughness along the reflected direction, times the \
             split-sum factor F0 A + B (F0 = mix(reflectance, albedo, metallic)); additive. With Refract on, the environment \
             seen through the surface along the refracted direction (index of refraction IOR inside, 1..4) times 1 - (F0 A + B) \
             instead; total internal reflection reflects. Diffuse: the environment's irradiance / pi at the normal, not \
             multiplied by albedo. Sky pixels are zero. Cost: one pass, a few texture reads per pixel.",
        )
        .input_spread("G-Buffer", PinType::Resource(ResourceKind::GBuffer), Spread::Resource(ResourceKind::GBuffer, vec![]))
        .input_spread(
            "Material World",
            PinType::Resource(ResourceKind::MaterialWorld),
            Spread::Resource(ResourceKind::MaterialWorld, vec![]),
        )
        .input_spread("Environment", PinType::Resource(ResourceKind::Environment), Spread::Resource(ResourceKind::Environment, vec![]))
        .input("Refract", false)
        .input("IOR", 1.5f32)
        .output_typed("Specular", PinType::Resource(ResourceKind::Texture))
        .output_typed("Diffuse", PinType::Resource(ResourceKind::Texture))
        .evaluate(|cx| {
            if let Some(slice) = cx.input(4).first_non_finite() {
                return Err(cx.input_error(4, format!("slice {slice} is NaN or infinite")));
            }
            let renderer = renderer(cx)?;
            let gbuffer = resources::<GBuffer>(cx, 0)?.into_iter().next().ok_or_else(|| cx.input_error(0, "no G-buffer connected"))?;
            let materials = match resources::<MaterialWorld>(cx, 1)?.into_iter().next() {
                Some(world) => world,
                // The default material has no Reflection feature: nothing reflects.
                None => MaterialWorld::new(&renderer, Vec::new()),
            };
            let environment = resources::<Environment>(cx, 2)?
                .into_iter()
                .next()
                .ok_or_else(|| cx.input_error(2, "no environment connected: use Environment (File) or Environment (Sky)"))?;
            let mode = if cx.slices::<bool>(3)?.first().copied().unwrap_or(false) {
                ReflectionMode::Refract { ior: cx.slices::<f32>(4)?.first().copied().unwrap_or(1.5) }
            } else {
                ReflectionMode::Reflect
            };
            let recipe = Reflection::new(&renderer, Some(cx.node_id.0), gbuffer, materials, environment, mode);
            cx.set_output(0, resource_spread::<TextureRef>(ResourceKind::Texture, vec![std::sync::Arc::new(recipe.specular_texture())]));
            cx.set_output(1, resource_spread::<TextureRef>(ResourceKind::Texture, vec![std::sync::Arc::new(recipe.diffuse_texture())]));
            Ok(())
        }),
    );
}
