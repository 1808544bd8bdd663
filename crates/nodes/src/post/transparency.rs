//! `Transparency`: weighted blended order-independent transparency over
//! the opaque lit image.

use glam::Vec3;
use spreadlight_graph::{Color, NodeDef, PinType, Registry, ResourceKind, Spread};
use spreadlight_render::gbuffer::Layer;
use spreadlight_render::post::{Transparency, TransparencySettings};

use super::{gbuffer, set_texture, texture};
use crate::gpu::{renderer, resources};

pub fn register(r: &mut Registry) {
    r.add(
        NodeDef::new(
            "Transparency",
            "Post",
            "Transparent meshes over the opaque lit image, in any order (weighted blended order-independent \
             transparency, McGuire and Bavoil 2013): connect DeferredBase layers that are not in the MRE; each \
             instance's Color alpha is its opacity. Hidden behind the G-buffer's opaque depth. Lighting is simple: \
             the colour times Ambient plus one two-sided directional light (Light Direction, towards the light; Light \
             Color). Without transparent instances it costs one copy.",
        )
        .input_spread("Texture", PinType::Resource(ResourceKind::Texture), Spread::Resource(ResourceKind::Texture, vec![]))
        .input_spread("G-Buffer", PinType::Resource(ResourceKind::GBuffer), Spread::Resource(ResourceKind::GBuffer, vec![]))
        .input_spread("Layer", PinType::Resource(ResourceKind::Layer), Spread::Resource(ResourceKind::Layer, vec![]))
        .input("Ambient", Color::rgba(0.3, 0.3, 0.3, 1.0))
        .input("Light Direction", Vec3::new(0.3, 1.0, 0.5))
        .input("Light Color", Color::WHITE)
        .output_typed("Texture", PinType::Resource(ResourceKind::Texture))
        .evaluate(|cx| {
            let renderer = renderer(cx)?;
            for pin in 3..6 {
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
            let settings = TransparencySettings {
                ambient: Vec3::new(ambient.r, ambient.g, ambient.b),
                light_direction,
                light_color: Vec3::new(light.r, light.g, light.b),
            };
            let pass = Transparency::new(&renderer, Some(cx.node_id.0), source, g, layers, settings);
            set_texture(cx, pass.texture());
            Ok(())
        }),
    );
}
