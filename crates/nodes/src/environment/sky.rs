//! `Sky`: a procedural sky where the G-buffer saw nothing, the lit image
//! elsewhere. Put it between `CompositeLight` and `Tonemap`; give it the
//! sun's direction so the disk sits where the light comes from.

use glam::Vec3;
use spreadlight_graph::{
    Color, EvalContext, NodeDef, NodeError, PinType, Registry, ResourceKind, Spread,
};
use spreadlight_render::TextureRef;
use spreadlight_render::environment::{Environment, Sky, SkySettings};
use spreadlight_render::gbuffer::GBuffer;

use crate::gpu::{renderer, resource_spread, resources};

const TEXTURE: usize = 0;
const GBUFFER: usize = 1;
const ENVIRONMENT: usize = 11;

/// The sky pins' default values, from Zenith to Glow (nine pins), as `Sky` and `Environment (Sky)` declare them.
pub(super) fn sky_pins(def: NodeDef) -> NodeDef {
    let d = SkySettings::default();
    let color = |v: Vec3| Color::rgba(v.x, v.y, v.z, 1.0);
    def.input("Zenith", color(d.zenith))
        .input("Horizon", color(d.horizon))
        .input("Ground", color(d.ground))
        .input("Intensity", 1.0f32)
        .input("Sun Direction", d.sun_direction)
        .input("Sun Color", Color::WHITE)
        .input("Sun Intensity", 50.0f32)
        .input("Sun Radius", 0.00075f32)
        .input("Glow", d.glow)
}

/// The settings from the nine sky pins starting at `first` (see [`sky_pins`]): NaN or infinity is an error naming the pin.
pub(super) fn read_sky(cx: &EvalContext<'_>, first: usize) -> Result<SkySettings, NodeError> {
    for pin in first..first + 9 {
        if let Some(slice) = cx.input(pin).first_non_finite() {
            return Err(cx.input_error(pin, format!("slice {slice} is NaN or infinite")));
        }
    }
    let rgb = |c: &Color| Vec3::new(c.r, c.g, c.b);
    let first_color = |pin: usize| -> Result<Vec3, NodeError> {
        Ok(cx.slices::<Color>(pin)?.first().map_or(Vec3::ONE, rgb))
    };
    let first_float = |pin: usize, fallback: f32| -> Result<f32, NodeError> {
        Ok(cx.slices::<f32>(pin)?.first().copied().unwrap_or(fallback))
    };
    let intensity = first_float(first + 3, 1.0)?.max(0.0);
    Ok(SkySettings {
        zenith: first_color(first)? * intensity,
        horizon: first_color(first + 1)? * intensity,
        ground: first_color(first + 2)? * intensity,
        sun_direction: cx
            .slices::<Vec3>(first + 4)?
            .first()
            .copied()
            .unwrap_or(Vec3::NEG_Y),
        sun_color: first_color(first + 5)? * first_float(first + 6, 50.0)?.max(0.0),
        sun_radius: first_float(first + 7, 0.00075)? * std::f32::consts::TAU,
        glow: first_float(first + 8, 1.0)?,
    })
}

pub fn register(r: &mut Registry) {
    r.add(
        sky_pins(NodeDef::new(
            "Sky",
            super::CATEGORY,
            "A procedural sky behind the scene: where the G-buffer saw nothing, a gradient from Ground (below the \
             horizon) through Horizon to Zenith (linear radiance, times Intensity), and a sun disk of Sun Radius \
             (cycles; ours is 0.00075) and Sun Color x Sun Intensity opposite Sun Direction (the way the light \
             travels, as AddLight (Sun) takes it), with a Glow around it. With an Environment connected, that environment \
             (unblurred) is the background instead. Elsewhere Texture passes through.",
        )
        .input_spread("Texture", PinType::Resource(ResourceKind::Texture), Spread::Resource(ResourceKind::Texture, vec![]))
        .input_spread("G-Buffer", PinType::Resource(ResourceKind::GBuffer), Spread::Resource(ResourceKind::GBuffer, vec![])))
        .input_spread(
            "Environment",
            PinType::Resource(ResourceKind::Environment),
            Spread::Resource(ResourceKind::Environment, vec![]),
        )
        .output_typed("Texture", PinType::Resource(ResourceKind::Texture))
        .evaluate(|cx| {
            let renderer = renderer(cx)?;
            let source = resources::<TextureRef>(cx, TEXTURE)?
                .into_iter()
                .next()
                .ok_or_else(|| cx.input_error(TEXTURE, "no texture connected"))?;
            let gbuffer = resources::<GBuffer>(cx, GBUFFER)?
                .into_iter()
                .next()
                .ok_or_else(|| cx.input_error(GBUFFER, "no G-buffer connected: the sky goes where it saw nothing"))?;
            let settings = read_sky(cx, 2)?;
            let environment = resources::<Environment>(cx, ENVIRONMENT)?.into_iter().next();
            let sky = Sky::with_environment(&renderer, Some(cx.node_id.0), gbuffer, (*source).clone(), settings, environment);
            cx.set_output(0, resource_spread::<TextureRef>(ResourceKind::Texture, vec![std::sync::Arc::new(sky.texture())]));
            Ok(())
        }),
    );
}
