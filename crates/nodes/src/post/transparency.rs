//! `Transparency`: weighted blended order-independent transparency over
//! the opaque lit image.

use glam::Vec3;
use spreadlight_graph::{Color, NodeDef, Registry, ResourceKind};
use spreadlight_render::gbuffer::Layer;
use spreadlight_render::post::{Transparency, TransparencySettings};

use super::{gbuffer, gbuffer_input, set_texture, texture, texture_input, texture_output};
use crate::gpu::renderer;

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
        .with_pins(|p| {
            let texture_in = texture_input(p, "Texture");
            let g_buffer = gbuffer_input(p);
            let layer = p.input_resource::<Layer>("Layer", ResourceKind::Layer);
            let ambient = p.input("Ambient", Color::rgba(0.3, 0.3, 0.3, 1.0));
            let light_direction = p.input("Light Direction", Vec3::new(0.3, 1.0, 0.5));
            let light_color = p.input("Light Color", Color::WHITE);
            let out = texture_output(p, "Texture");
            move |cx| {
                let renderer = renderer(cx)?;
                for pin in [ambient.index(), light_direction.index(), light_color.index()] {
                    if let Some(slice) = cx.input(pin).first_non_finite() {
                        return Err(cx.input_error(pin, format!("slice {slice} is NaN or infinite")));
                    }
                }
                let source = texture(cx, texture_in)?;
                let g = gbuffer(cx, g_buffer, "transparent surfaces are depth-tested against it")?;
                let layers = cx.resources(layer)?;
                let ambient = cx.first(ambient, Color::WHITE)?;
                let light = cx.first(light_color, Color::WHITE)?;
                let settings = TransparencySettings {
                    ambient: Vec3::new(ambient.r, ambient.g, ambient.b),
                    light_direction: cx.first(light_direction, Vec3::Y)?,
                    light_color: Vec3::new(light.r, light.g, light.b),
                };
                let pass = Transparency::new(&renderer, Some(cx.node_id.0), source, g, layers, settings);
                set_texture(cx, out, pass.texture());
                Ok(())
            }
        }),
    );
}
