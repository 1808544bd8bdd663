//! `Transparency`: weighted blended order-independent transparency over
//! the opaque lit image, lit forward+ by the light buffers CookTorrance
//! shades the opaque scene with.

use glam::Vec3;
use spreadlight_graph::{Choices, Color, NodeDef, Registry, ResourceKind};
use spreadlight_render::environment::Environment;
use spreadlight_render::gbuffer::Layer;
use spreadlight_render::lighting::{LightBuffer, LightLoop};
use spreadlight_render::material::MaterialWorld;
use spreadlight_render::post::{
    LitBy, RefractionBlur, TransmissionSettings, Transparency, TransparencySettings,
    TransparencyShading, TransparentLights,
};
use spreadlight_render::shadows::ShadowMaps;

use super::{gbuffer, gbuffer_input, set_texture, texture, texture_input, texture_output};
use crate::gpu::renderer;
use crate::lighting::cook_torrance::LIGHT_LOOPS;

/// The Refraction Blur pin's options as values.
static REFRACTION_BLURS: spreadlight_graph::Choices<RefractionBlur> =
    spreadlight_graph::Choices::new(
        "Refraction Blur",
        &["Auto", "Mips", "Taps"],
        &[
            RefractionBlur::Auto,
            RefractionBlur::Mips,
            RefractionBlur::Taps,
        ],
    );

pub static SHADING: Choices<TransparencyShading> = Choices::new(
    "Transparency Shading",
    &["Auto", "Forward", "Compute", "Tiled"],
    &[
        TransparencyShading::Auto,
        TransparencyShading::Forward,
        TransparencyShading::Compute,
        TransparencyShading::Tiled,
    ],
);

pub fn register(r: &mut Registry) {
    r.add(
        NodeDef::new(
            "Transparency",
            "Post",
            "Transparent meshes over the opaque lit image, in any order (weighted blended order-independent \
             transparency, McGuire and Bavoil 2013): connect DeferredBase layers that are not in the MRE; each \
             instance's Color alpha is its opacity. Hidden behind the G-buffer's opaque depth. Every layer gets \
             its colour times Ambient plus its emission. Lights: the light buffers CookTorrance shades with (point, \
             spot, sun; several as a spread), each lighting the layers forward+ with Cook-Torrance (each type's code \
             compiled only when connected; the clustered froxel lists past 16 lights, or as Light Loop says), \
             shadowed by the ShadowMap of its type in Shadows. Shading: Forward draws every layer again per light \
             buffer, each fragment blending its lights; Compute draws each layer once, records its fragments per pixel \
             (8 a pixel; more are lit as the recorded ones on average) and lights them in compute, the same picture \
             within 4e-3; Tiled as Compute with each 8x8 tile sharing its froxels' lights through workgroup memory; \
             Auto is Compute (measured faster on the H200 and lavapipe; Forward where the device's storage limits hold \
             no record a pixel). Without Lights, one two-sided directional light \
             (Light Direction, towards the light; Light Color) as before. The surface is the layer's: glTF materials' \
             maps (base colour, normal, metallic-roughness, occlusion, emissive), a DeferredBase's Color Texture and \
             normal map; roughness, metallic and emission from the layer's material world, else Material World, \
             else Roughness and Metallic. Environment adds its irradiance and its prefiltered reflection (as much as \
             a material's Reflection feature says; fully for layers without a material world). Transmission \
             (0..1): that share of what shows through a layer is refracted instead of blended (glass; glTF \
             materials with KHR_materials_transmission bring their own, as does a material world's Transmission \
             feature): the opaque image sampled where the ray bent by IOR through a slab Thickness deep (world \
             units; 0: thin-walled) meets the opaque depth (Refraction Steps, 0..8), blurred by roughness (Refraction Blur: Mips, one \
             read of a mip chain of the opaque image, built only while something refracts; Taps, Refraction Taps \
             (1..32) reads, the reference; Auto is Mips), tinted by the colour and absorbed to Attenuation Color \
             after Attenuation Distance (0: no absorption). Only the opaque scene is seen refracted; a ray leaving \
             the screen sees the Environment (faded in just past the border; without one, the screen's edge). At \
             Transmission 0 no refraction code runs. Without transparent instances it costs one copy.",
        )
        .with_pins(|p| {
            let texture_in = texture_input(p, "Texture");
            let g_buffer = gbuffer_input(p);
            let layer = p.input_resource::<Layer>("Layer", ResourceKind::Layer);
            let ambient = p.input("Ambient", Color::rgba(0.3, 0.3, 0.3, 1.0));
            let light_direction = p.input("Light Direction", Vec3::new(0.3, 1.0, 0.5));
            let light_color = p.input("Light Color", Color::WHITE);
            let lights_in = p.input_resource::<LightBuffer>("Lights", ResourceKind::LightWorld);
            let shadows_in = p.input_resource::<ShadowMaps>("Shadows", ResourceKind::Shadows);
            let material_world = p.input_resource::<MaterialWorld>("Material World", ResourceKind::MaterialWorld);
            let roughness = p.input("Roughness", 0.5f32);
            let metallic = p.input("Metallic", 0.0f32);
            let energy_compensation = p.input("Energy Compensation", true);
            let light_loop = p.input_choice("Light Loop", &LIGHT_LOOPS, LightLoop::Auto);
            let shading = p.input_choice("Shading", &SHADING, TransparencyShading::Auto);
            let environment = p.input_resource::<Environment>("Environment", ResourceKind::Environment);
            let transmission = p.input("Transmission", 0.0f32);
            let ior = p.input("IOR", 1.5f32);
            let thickness = p.input("Thickness", 0.0f32);
            let attenuation_color = p.input("Attenuation Color", Color::WHITE);
            let attenuation_distance = p.input("Attenuation Distance", 0.0f32);
            let taps = p.input("Refraction Taps", 8i64);
            let steps = p.input("Refraction Steps", 2i64);
            let blur = p.input_choice("Refraction Blur", &REFRACTION_BLURS, RefractionBlur::Auto);
            let out = texture_output(p, "Texture");
            move |cx| {
                let renderer = renderer(cx)?;
                for pin in [
                    ambient.index(),
                    light_direction.index(),
                    light_color.index(),
                    roughness.index(),
                    metallic.index(),
                    transmission.index(),
                    ior.index(),
                    thickness.index(),
                    attenuation_color.index(),
                    attenuation_distance.index(),
                ] {
                    if let Some(slice) = cx.input(pin).first_non_finite() {
                        return Err(cx.input_error(pin, format!("slice {slice} is NaN or infinite")));
                    }
                }
                let source = texture(cx, texture_in)?;
                let g = gbuffer(cx, g_buffer, "transparent surfaces are depth-tested against it")?;
                let layers = cx.resources(layer)?;
                let ambient = cx.first(ambient, Color::WHITE)?;
                let light = cx.first(light_color, Color::WHITE)?;
                let shadows = cx.resources(shadows_in)?;
                // Each light buffer is shadowed by the shadow maps of its type: two of one type would be a guess.
                for (i, s) in shadows.iter().enumerate() {
                    if shadows[..i].iter().any(|other| other.kind == s.kind) {
                        return Err(cx.error(
                            shadows_in,
                            format!("slices hold two shadow maps of {:?} lights: connect one per light type", s.kind),
                        ));
                    }
                }
                let lights = cx
                    .resources(lights_in)?
                    .into_iter()
                    .map(|lights| TransparentLights {
                        shadows: shadows.iter().find(|s| s.kind == lights.kind).cloned(),
                        lights,
                    })
                    .collect();
                let settings = TransparencySettings {
                    ambient: Vec3::new(ambient.r, ambient.g, ambient.b),
                    light_direction: cx.first(light_direction, Vec3::Y)?,
                    light_color: Vec3::new(light.r, light.g, light.b),
                    roughness: cx.first(roughness, 0.5)?,
                    metallic: cx.first(metallic, 0.0)?,
                    energy_compensation: cx.first(energy_compensation, true)?,
                    light_loop: cx.choice(light_loop)?,
                    shading: cx.choice(shading)?,
                    transmission: {
                        let c = cx.first(attenuation_color, Color::WHITE)?;
                        let distance = cx.first(attenuation_distance, 0.0f32)?;
                        TransmissionSettings {
                            factor: cx.first(transmission, 0.0f32)?,
                            ior: cx.first(ior, 1.5f32)?,
                            thickness: cx.first(thickness, 0.0f32)?,
                            attenuation_color: Vec3::new(c.r, c.g, c.b),
                            // 0 (or less): none, as an infinite distance.
                            attenuation_distance: if distance > 0.0 { distance } else { f32::INFINITY },
                            taps: cx.first(taps, 8i64)?.clamp(1, 32) as u32,
                            steps: cx.first(steps, 2i64)?.clamp(0, 8) as u32,
                            blur: cx.choice(blur)?,
                        }
                    },
                };
                let by = LitBy {
                    lights,
                    materials: cx.first_resource(material_world)?,
                    environment: cx.first_resource(environment)?,
                };
                let pass = Transparency::lit(&renderer, Some(cx.node_id.0), source, g, layers, settings, by);
                set_texture(cx, out, pass.texture());
                Ok(())
            }
        }),
    );
}
