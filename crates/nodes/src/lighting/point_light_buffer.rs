//! `PointLightBuffer`: a spread of point lights, one per slice, uploaded
//! once when its inputs change. A NaN or infinity on a pin is an error on
//! this node that names the pin and slice; it never reaches the image.

use glam::Vec3;
use spreadlight_graph::spread::{cycled, slice_count};
use spreadlight_graph::{Color, NodeDef, PinType, Registry, ResourceKind};
use spreadlight_render::lighting::{LightBuffer, PointLight};

use crate::gpu::{renderer, resource_spread};

pub fn register(r: &mut Registry) {
    r.add(
        NodeDef::new(
            "PointLightBuffer",
            super::CATEGORY,
            "Point lights, one per slice: position, linear colour, luminous intensity in candela (a power in \
             lumens divided by 4 pi) and range, where the light fades smoothly to zero.",
        )
        .input("Position", Vec3::new(0.0, 2.0, 0.0))
        .input("Color", Color::WHITE)
        .input("Intensity", 100.0f32)
        .input("Range", 10.0f32)
        .output_typed("Lights", PinType::Resource(ResourceKind::LightWorld))
        .evaluate(|cx| {
            let renderer = renderer(cx)?;
            let (positions, colors) = (cx.slices::<Vec3>(0)?, cx.slices::<Color>(1)?);
            let (intensities, ranges) = (cx.slices::<f32>(2)?, cx.slices::<f32>(3)?);
            let n = slice_count([positions.len(), colors.len(), intensities.len(), ranges.len()]);
            super::require_finite(cx, 0..4)?;
            let lights: Vec<PointLight> = cycled(positions, n)
                .zip(cycled(colors, n))
                .zip(cycled(intensities, n))
                .zip(cycled(ranges, n))
                .map(|(((position, color), intensity), range)| PointLight {
                    position: *position,
                    color: Vec3::new(color.r, color.g, color.b),
                    intensity: *intensity,
                    range: *range,
                })
                .collect();
            let lights = LightBuffer::points(&renderer, &lights);
            cx.set_output(0, resource_spread(ResourceKind::LightWorld, vec![lights]));
            Ok(())
        }),
    );
}
