//! `Autofocus`: the focus distance under a screen point, eased over time, on
//! the GPU (a 1x1 texture `DOF` reads; no readback).

use glam::Vec2;
use spreadlight_graph::{NodeDef, Registry};
use spreadlight_render::post::Autofocus;

use super::{float, gbuffer, gbuffer_input, set_texture, texture_output};
use crate::gpu::renderer;

pub fn register(r: &mut Registry) {
    r.add(
        NodeDef::new(
            "Autofocus",
            "Post",
            "The distance to what lies under Point (UV: 0..1 across, 0..1 down; the mean over 5x5 pixels), eased over \
             time: each frame it moves 1 - exp(-dt * Speed) of the way, in inverse distance (as a focus ring turns); \
             an infinite Speed follows at once. The first frame, and after a cut, take the measurement as it is. \
             Output: a 1x1 texture for DOF's Focus pin (the inverse distance, on the GPU).",
        )
        .time_dependent()
        .stateful()
        .with_pins(|p| {
            let g_buffer = gbuffer_input(p);
            let point = p.input("Point", Vec2::splat(0.5));
            let speed = p.input("Speed", 5.0f32);
            let out = texture_output(p, "Focus");
            move |cx| {
                let renderer = renderer(cx)?;
                let g = gbuffer(cx, g_buffer, "autofocus reads the depth under its point")?;
                let point_value = cx.first(point, Vec2::splat(0.5))?;
                if !point_value.is_finite() {
                    return Err(cx.error(point, "slice 0 is NaN or infinite"));
                }
                let speed_value = float(cx, speed, 5.0, true)?;
                if speed_value < 0.0 {
                    return Err(cx.error(speed, "is negative"));
                }
                let af = Autofocus::new(&renderer, Some(cx.node_id.0), g, point_value, speed_value, cx.clock.delta);
                set_texture(cx, out, af.texture());
                Ok(())
            }
        }),
    );
}
