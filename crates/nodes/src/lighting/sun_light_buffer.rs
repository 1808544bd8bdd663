//! `SunLightBuffer`: parallel lights, one per slice: the direction the light
//! travels, linear colour, illuminance in lux.

use glam::Vec3;
use spreadlight_graph::spread::{cycled, slice_count};
use spreadlight_graph::{Color, NodeDef, PinType, Registry, ResourceKind};
use spreadlight_render::lighting::{LightBuffer, SunLight};

use crate::gpu::{renderer, resource_spread};

pub fn register(r: &mut Registry) {
    r.add(
        NodeDef::new(
            "SunLightBuffer",
            super::CATEGORY,
            "Sun lights, one per slice: the direction the light travels (from the sun towards the scene), \
             linear colour and illuminance in lux.",
        )
        .input("Direction", Vec3::new(-0.5, -1.0, -0.25))
        .input("Color", Color::WHITE)
        .input("Illuminance", 400.0f32)
        .output_typed("Lights", PinType::Resource(ResourceKind::LightWorld))
        .evaluate(|cx| {
            let renderer = renderer(cx)?;
            super::require_finite(cx, 0..3)?;
            let (directions, colors, lux) = (cx.slices::<Vec3>(0)?, cx.slices::<Color>(1)?, cx.slices::<f32>(2)?);
            let n = slice_count([directions.len(), colors.len(), lux.len()]);
            let lights: Vec<SunLight> = cycled(directions, n)
                .zip(cycled(colors, n))
                .zip(cycled(lux, n))
                .map(|((direction, color), lux)| SunLight {
                    direction: *direction,
                    color: Vec3::new(color.r, color.g, color.b),
                    illuminance: *lux,
                })
                .collect();
            let lights = LightBuffer::suns(&renderer, &lights);
            cx.set_output(0, resource_spread(ResourceKind::LightWorld, vec![lights]));
            Ok(())
        }),
    );
}
