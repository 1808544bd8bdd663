//! `Transparency`: weighted blended order-independent transparency over
//! the opaque lit image, lit forward+ by the light buffers CookTorrance
//! shades the opaque scene with.

use glam::Vec3;
use spreadlight_graph::{Color, NodeDef, PinType, Registry, ResourceKind, Spread};
use spreadlight_render::environment::Environment;
use spreadlight_render::gbuffer::Layer;
use spreadlight_render::lighting::{LightBuffer, LightLoop};
use spreadlight_render::material::MaterialWorld;
use spreadlight_render::post::{LitBy, Transparency, TransparencySettings, TransparentLights};
use spreadlight_render::shadows::ShadowMaps;

use super::{gbuffer, set_texture, texture};
use crate::gpu::{renderer, resources};
use crate::lighting::cook_torrance::LIGHT_LOOP;

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
             shadowed by the ShadowMap of its type in Shadows. Without Lights, one two-sided directional light \
             (Light Direction, towards the light; Light Color) as before. The surface is the layer's: glTF materials' \
             maps (base colour, normal, metallic-roughness, occlusion, emissive), a DeferredBase's Color Texture and \
             normal map; roughness, metallic and emission from the layer's material world, else Material World, \
             else Roughness and Metallic. Environment adds its irradiance and its prefiltered reflection (as much as \
             a material's Reflection feature says; fully for layers without a material world). Without transparent \
             instances it costs one copy.",
        )
        .input_spread("Texture", PinType::Resource(ResourceKind::Texture), Spread::Resource(ResourceKind::Texture, vec![]))
        .input_spread("G-Buffer", PinType::Resource(ResourceKind::GBuffer), Spread::Resource(ResourceKind::GBuffer, vec![]))
        .input_spread("Layer", PinType::Resource(ResourceKind::Layer), Spread::Resource(ResourceKind::Layer, vec![]))
        .input("Ambient", Color::rgba(0.3, 0.3, 0.3, 1.0))
        .input("Light Direction", Vec3::new(0.3, 1.0, 0.5))
        .input("Light Color", Color::WHITE)
        .input_spread("Lights", PinType::Resource(ResourceKind::LightWorld), Spread::Resource(ResourceKind::LightWorld, vec![]))
        .input_spread("Shadows", PinType::Resource(ResourceKind::Shadows), Spread::Resource(ResourceKind::Shadows, vec![]))
        .input_spread(
            "Material World",
            PinType::Resource(ResourceKind::MaterialWorld),
            Spread::Resource(ResourceKind::MaterialWorld, vec![]),
        )
        .input("Roughness", 0.5f32)
        .input("Metallic", 0.0f32)
        .input("Energy Compensation", true)
        .input_enum("Light Loop", &LIGHT_LOOP, "Auto")
        .input_spread(
            "Environment",
            PinType::Resource(ResourceKind::Environment),
            Spread::Resource(ResourceKind::Environment, vec![]),
        )
        .output_typed("Texture", PinType::Resource(ResourceKind::Texture))
        .evaluate(|cx| {
            let renderer = renderer(cx)?;
            for pin in [3, 4, 5, 9, 10] {
                if let Some(slice) = cx.input(pin).first_non_finite() {
                    return Err(cx.input_error(pin, format!("slice {slice} is NaN or infinite")));
                }
            }
            let source = texture(cx, 0)?;
            let g = gbuffer(cx, 1, "transparent surfaces are depth-tested against it")?;
            let layers = resources::<Layer>(cx, 2)?;
            let ambient = cx.slices::<Color>(3)?.first().copied().unwrap_or(Color::WHITE);
            let light_direction = cx.slices::<Vec3>(4)?.first().copied().unwrap_or(Vec3::Y);
            let light = cx.slices::<Color>(5)?.first().copied().unwrap_or(Color::WHITE);
            let shadows = resources::<ShadowMaps>(cx, 7)?;
            // Each light buffer is shadowed by the shadow maps of its type: two of one type would be a guess.
            for (i, s) in shadows.iter().enumerate() {
                if shadows[..i].iter().any(|other| other.kind == s.kind) {
                    return Err(cx.input_error(7, format!("slices hold two shadow maps of {:?} lights: connect one per light type", s.kind)));
                }
            }
            let lights = resources::<LightBuffer>(cx, 6)?
                .into_iter()
                .map(|lights| TransparentLights {
                    shadows: shadows.iter().find(|s| s.kind == lights.kind).cloned(),
                    lights,
                })
                .collect();
            let materials = resources::<MaterialWorld>(cx, 8)?.into_iter().next();
            let light_loop = match cx.enum_slices(12)?.first().map(String::as_str) {
                Some("Naive") => LightLoop::Naive,
                Some("Clustered") => LightLoop::Clustered,
                _ => LightLoop::Auto,
            };
            let settings = TransparencySettings {
                ambient: Vec3::new(ambient.r, ambient.g, ambient.b),
                light_direction,
                light_color: Vec3::new(light.r, light.g, light.b),
                roughness: cx.slices::<f32>(9)?.first().copied().unwrap_or(0.5),
                metallic: cx.slices::<f32>(10)?.first().copied().unwrap_or(0.0),
                energy_compensation: cx.slices::<bool>(11)?.first().copied().unwrap_or(true),
                light_loop,
            };
            let by = LitBy {
                lights,
                materials,
                environment: resources::<Environment>(cx, 13)?.into_iter().next(),
            };
            let pass = Transparency::lit(&renderer, Some(cx.node_id.0), source, g, layers, settings, by);
            set_texture(cx, pass.texture());
            Ok(())
        }),
    );
}
