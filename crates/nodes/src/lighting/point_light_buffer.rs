//! `PointLightBuffer`: a spread of point lights, one per slice, uploaded
//! once when its inputs change. A NaN or infinity on a pin is an error on
//! this node that names the pin and slice; it never reaches the image.

use glam::Vec3;
use spreadlight_graph::spread::{cycled, slice_count};
use spreadlight_graph::{Color, NodeDef, PinType, Registry, ResourceKind};
use spreadlight_render::lighting::{PointLight, PointLights};

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
            let mut lights = Vec::with_capacity(n);
            let pins = cycled(positions, n).zip(cycled(colors, n)).zip(cycled(intensities, n)).zip(cycled(ranges, n));
            for (slice, (((position, color), intensity), range)) in pins.enumerate() {
                let bad = |pin: usize| cx.input_error(pin, format!("slice {slice} is NaN or infinite"));
                if !position.is_finite() {
                    return Err(bad(0));
                }
                if !color.to_vec4().is_finite() {
                    return Err(bad(1));
                }
                if !intensity.is_finite() {
                    return Err(bad(2));
                }
                if !range.is_finite() {
                    return Err(bad(3));
                }
                lights.push(PointLight {
                    position: *position,
                    color: Vec3::new(color.r, color.g, color.b).max(Vec3::ZERO),
                    intensity: intensity.max(0.0),
                    range: range.max(0.0),
                });
            }
            let lights = PointLights::new(&renderer, lights);
            cx.set_output(0, resource_spread(ResourceKind::LightWorld, vec![lights]));
            Ok(())
        }),
    );
}
