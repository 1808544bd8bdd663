//! `Sky`: a procedural sky where the G-buffer saw nothing, the lit image
//! elsewhere. Put it between `CompositeLight` and `Tonemap`; give it the
//! sun's direction so the disk sits where the light comes from.

use glam::Vec3;
use spreadlight_graph::{Color, EvalContext, In, NodeDef, NodeError, Pins, Registry, ResourceKind};
use spreadlight_render::environment::{Environment, Sky, SkySettings};

use crate::gpu::renderer;
use crate::lighting::require_finite;
use crate::post::{gbuffer_input, set_texture, texture_input, texture_output};

/// The nine sky pins, from Zenith to Glow, as `Sky` and `Environment (Sky)` declare them.
#[derive(Clone, Copy)]
pub(super) struct SkyPins {
    zenith: In<Color>,
    horizon: In<Color>,
    ground: In<Color>,
    intensity: In<f32>,
    sun_direction: In<Vec3>,
    sun_color: In<Color>,
    sun_intensity: In<f32>,
    sun_radius: In<f32>,
    glow: In<f32>,
}

impl SkyPins {
    /// The pins with their default values.
    pub(super) fn declare(p: &mut Pins<'_>) -> Self {
        let d = SkySettings::default();
        let color = |v: Vec3| Color::rgba(v.x, v.y, v.z, 1.0);
        SkyPins {
            zenith: p.input("Zenith", color(d.zenith)),
            horizon: p.input("Horizon", color(d.horizon)),
            ground: p.input("Ground", color(d.ground)),
            intensity: p.input("Intensity", 1.0f32),
            sun_direction: p.input("Sun Direction", d.sun_direction),
            sun_color: p.input("Sun Color", Color::WHITE),
            sun_intensity: p.input("Sun Intensity", 50.0f32),
            sun_radius: p.input("Sun Radius", 0.00075f32),
            glow: p.input("Glow", d.glow),
        }
    }

    /// The settings the pins give: NaN or infinity is an error naming the pin.
    pub(super) fn read(self, cx: &EvalContext<'_>) -> Result<SkySettings, NodeError> {
        for pin in [self.zenith, self.horizon, self.ground] {
            require_finite(cx, pin)?;
        }
        require_finite(cx, self.intensity)?;
        require_finite(cx, self.sun_direction)?;
        require_finite(cx, self.sun_color)?;
        for pin in [self.sun_intensity, self.sun_radius, self.glow] {
            require_finite(cx, pin)?;
        }
        let rgb = |c: &Color| Vec3::new(c.r, c.g, c.b);
        let first_color = |pin: In<Color>| -> Result<Vec3, NodeError> {
            Ok(cx.get(pin)?.first().map_or(Vec3::ONE, rgb))
        };
        let intensity = cx.first(self.intensity, 1.0)?.max(0.0);
        Ok(SkySettings {
            zenith: first_color(self.zenith)? * intensity,
            horizon: first_color(self.horizon)? * intensity,
            ground: first_color(self.ground)? * intensity,
            sun_direction: cx.first(self.sun_direction, Vec3::NEG_Y)?,
            sun_color: first_color(self.sun_color)? * cx.first(self.sun_intensity, 50.0)?.max(0.0),
            sun_radius: cx.first(self.sun_radius, 0.00075)? * std::f32::consts::TAU,
            glow: cx.first(self.glow, 1.0)?,
        })
    }
}

pub fn register(r: &mut Registry) {
    r.add(
        NodeDef::new(
            "Sky",
            super::CATEGORY,
            "A procedural sky behind the scene: where the G-buffer saw nothing, a gradient from Ground (below the \
             horizon) through Horizon to Zenith (linear radiance, times Intensity), and a sun disk of Sun Radius \
             (cycles; ours is 0.00075) and Sun Color x Sun Intensity opposite Sun Direction (the way the light \
             travels, as AddLight (Sun) takes it), with a Glow around it. With an Environment connected, that environment \
             (unblurred) is the background instead. Elsewhere Texture passes through.",
        )
        .with_pins(|p| {
            let texture = texture_input(p, "Texture");
            let g_buffer = gbuffer_input(p);
            let sky = SkyPins::declare(p);
            let environment = p.input_resource::<Environment>("Environment", ResourceKind::Environment);
            let out = texture_output(p, "Texture");
            move |cx| {
                let renderer = renderer(cx)?;
                let source = crate::post::texture(cx, texture)?;
                let gbuffer = cx
                    .first_resource(g_buffer)?
                    .ok_or_else(|| cx.error(g_buffer, "no G-buffer connected: the sky goes where it saw nothing"))?;
                let settings = sky.read(cx)?;
                let environment = cx.first_resource(environment)?;
                let sky = Sky::with_environment(&renderer, Some(cx.node_id.0), gbuffer, source, settings, environment);
                set_texture(cx, out, sky.texture());
                Ok(())
            }
        }),
    );
}
