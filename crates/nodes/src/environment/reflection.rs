//! `Reflection`: image-based light from an environment over the G-buffer:
//! Specular (the prefiltered environment along the reflected, or refracted,
//! direction times the split-sum factor) and Diffuse (irradiance / pi,
//! albedo not applied). Only materials with the Reflection feature get it;
//! when none has it the pass only clears and the environment is not built.

use spreadlight_graph::{NodeDef, Registry, ResourceKind};
use spreadlight_render::environment::{Environment, Reflection, ReflectionMode};
use spreadlight_render::material::MaterialWorld;

use crate::gpu::renderer;
use crate::lighting::require_finite;
use crate::post::{gbuffer_input, set_texture, texture_output};

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
        .with_pins(|p| {
            let g_buffer = gbuffer_input(p);
            let material_world = p.input_resource::<MaterialWorld>("Material World", ResourceKind::MaterialWorld);
            let environment_in = p.input_resource::<Environment>("Environment", ResourceKind::Environment);
            let refract = p.input("Refract", false);
            let ior = p.input("IOR", 1.5f32);
            let specular = texture_output(p, "Specular");
            let diffuse = texture_output(p, "Diffuse");
            move |cx| {
                require_finite(cx, ior)?;
                let renderer = renderer(cx)?;
                let gbuffer = cx.first_resource(g_buffer)?.ok_or_else(|| cx.error(g_buffer, "no G-buffer connected"))?;
                let materials = match cx.first_resource(material_world)? {
                    Some(world) => world,
                    // The default material has no Reflection feature: nothing reflects.
                    None => MaterialWorld::new(&renderer, Vec::new()),
                };
                let environment = cx.first_resource(environment_in)?.ok_or_else(|| {
                    cx.error(environment_in, "no environment connected: use Environment (File) or Environment (Sky)")
                })?;
                let mode = if cx.first(refract, false)? {
                    ReflectionMode::Refract { ior: cx.first(ior, 1.5)? }
                } else {
                    ReflectionMode::Reflect
                };
                let recipe = Reflection::new(&renderer, Some(cx.node_id.0), gbuffer, materials, environment, mode);
                set_texture(cx, specular, recipe.specular_texture());
                set_texture(cx, diffuse, recipe.diffuse_texture());
                Ok(())
            }
        }),
    );
}
