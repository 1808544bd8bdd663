//! `Sky`: a procedural sky where the G-buffer saw nothing, the lit image
//! elsewhere. Put it between `CompositeLight` and `Tonemap`; give it the
//! sun's direction so the disk sits where the light comes from.

use glam::Vec3;
use spreadlight_graph::{Color, NodeDef, PinType, Registry, ResourceKind, Spread};
use spreadlight_render::TextureRef;
use spreadlight_render::environment::{Sky, SkySettings};
use spreadlight_render::gbuffer::GBuffer;

use crate::gpu::{renderer, resource_spread, resources};

const TEXTURE: usize = 0;
const GBUFFER: usize = 1;

pub fn register(r: &mut Registry) {
    let d = SkySettings::default();
    let color = |v: Vec3| Color::rgba(v.x, v.y, v.z, 1.0);
    r.add(
        NodeDef::new(
            "Sky",
            super::CATEGORY,
            "A procedural sky behind the scene: where the G-buffer saw nothing, a gradient from Ground (below the \
             horizon) through Horizon to Zenith (linear radiance, times Intensity), and a sun disk of Sun Radius \
             (cycles; ours is 0.00075) and Sun Color x Sun Intensity opposite Sun Direction (the way the light \
             travels, as AddLight (Sun) takes it), with a Glow around it. Elsewhere Texture passes through.",
        )
        .input_spread("Texture", PinType::Resource(ResourceKind::Texture), Spread::Resource(ResourceKind::Texture, vec![]))
        .input_spread("G-Buffer", PinType::Resource(ResourceKind::GBuffer), Spread::Resource(ResourceKind::GBuffer, vec![]))
        .input("Zenith", color(d.zenith))
        .input("Horizon", color(d.horizon))
        .input("Ground", color(d.ground))
        .input("Intensity", 1.0f32)
        .input("Sun Direction", d.sun_direction)
        .input("Sun Color", Color::WHITE)
        .input("Sun Intensity", 50.0f32)
        .input("Sun Radius", 0.00075f32)
        .input("Glow", d.glow)
        .output_typed("Texture", PinType::Resource(ResourceKind::Texture))
        .evaluate(|cx| {
            let renderer = renderer(cx)?;
            for pin in 2..11 {
                if let Some(slice) = cx.input(pin).first_non_finite() {
                    return Err(cx.input_error(pin, format!("slice {slice} is NaN or infinite")));
                }
            }
            let source = resources::<TextureRef>(cx, TEXTURE)?
                .into_iter()
                .next()
                .ok_or_else(|| cx.input_error(TEXTURE, "no texture connected"))?;
            let gbuffer = resources::<GBuffer>(cx, GBUFFER)?
                .into_iter()
                .next()
                .ok_or_else(|| cx.input_error(GBUFFER, "no G-buffer connected: the sky goes where it saw nothing"))?;
            let rgb = |c: &Color| Vec3::new(c.r, c.g, c.b);
            let first_color = |pin: usize| -> Result<Vec3, spreadlight_graph::NodeError> {
                Ok(cx.slices::<Color>(pin)?.first().map_or(Vec3::ONE, rgb))
            };
            let first_float = |pin: usize, fallback: f32| -> Result<f32, spreadlight_graph::NodeError> {
                Ok(cx.slices::<f32>(pin)?.first().copied().unwrap_or(fallback))
            };
            let intensity = first_float(5, 1.0)?.max(0.0);
            let settings = SkySettings {
                zenith: first_color(2)? * intensity,
                horizon: first_color(3)? * intensity,
                ground: first_color(4)? * intensity,
                sun_direction: cx.slices::<Vec3>(6)?.first().copied().unwrap_or(Vec3::NEG_Y),
                sun_color: first_color(7)? * first_float(8, 50.0)?.max(0.0),
                sun_radius: first_float(9, 0.00075)? * std::f32::consts::TAU,
                glow: first_float(10, 1.0)?,
            };
            let sky = Sky::pass(&renderer, Some(cx.node_id.0), gbuffer, (*source).clone(), settings);
            cx.set_output(0, resource_spread::<TextureRef>(ResourceKind::Texture, vec![std::sync::Arc::new(sky.texture())]));
            Ok(())
        }),
    );
}
