//! `Autofocus`: the focus distance under a screen point, eased over time, on
//! the GPU (a 1x1 texture `DOF` reads; no readback).

use glam::Vec2;
use spreadlight_graph::{NodeDef, PinType, Registry, ResourceKind, Spread};
use spreadlight_render::post::Autofocus;

use super::{float, gbuffer, set_texture};
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
        .input_spread("G-Buffer", PinType::Resource(ResourceKind::GBuffer), Spread::Resource(ResourceKind::GBuffer, vec![]))
        .input("Point", Vec2::splat(0.5))
        .input("Speed", 5.0f32)
        .output_typed("Focus", PinType::Resource(ResourceKind::Texture))
        .time_dependent()
        .stateful()
        .evaluate(|cx| {
            let renderer = renderer(cx)?;
            let g = gbuffer(cx, 0, "autofocus reads the depth under its point")?;
            let point = cx.slices::<Vec2>(1)?.first().copied().unwrap_or(Vec2::splat(0.5));
            if !point.is_finite() {
                return Err(cx.input_error(1, "slice 0 is NaN or infinite"));
            }
            let speed = float(cx, 2, 5.0, true)?;
            if speed < 0.0 {
                return Err(cx.input_error(2, "is negative"));
            }
            let af = Autofocus::new(&renderer, Some(cx.node_id.0), g, point, speed, cx.clock.delta);
            set_texture(cx, af.texture());
            Ok(())
        }),
    );
}
