//! `SpotLightBuffer`: spot lights, one per slice: a point light limited to a
//! cone, fading from the inner to the outer angle. Cones of 0 and 180 degrees work.

use glam::Vec3;
use spreadlight_graph::spread::{cycled, slice_count};
use spreadlight_graph::{Color, NodeDef, PinType, Registry, ResourceKind};
use spreadlight_render::lighting::{LightBuffer, SpotLight};

use crate::gpu::{renderer, resource_spread};

pub fn register(r: &mut Registry) {
    r.add(
        NodeDef::new(
            "SpotLightBuffer",
            super::CATEGORY,
            "Spot lights, one per slice: position, the direction the light shines, linear colour, luminous \
             intensity (cd), range, and the cone's inner and outer half-angles in cycles (0.125 = 45 degrees).",
        )
        .input("Position", Vec3::new(0.0, 4.0, 0.0))
        .input("Direction", Vec3::NEG_Y)
        .input("Color", Color::WHITE)
        .input("Intensity", 500.0f32)
        .input("Range", 15.0f32)
        .input("Inner Angle", 0.05f32)
        .input("Outer Angle", 0.08f32)
        .output_typed("Lights", PinType::Resource(ResourceKind::LightWorld))
        .evaluate(|cx| {
            let renderer = renderer(cx)?;
            super::require_finite(cx, 0..7)?;
            let (positions, directions, colors) = (cx.slices::<Vec3>(0)?, cx.slices::<Vec3>(1)?, cx.slices::<Color>(2)?);
            let (intensities, ranges) = (cx.slices::<f32>(3)?, cx.slices::<f32>(4)?);
            let (inner, outer) = (cx.slices::<f32>(5)?, cx.slices::<f32>(6)?);
            let n = slice_count([
                positions.len(),
                directions.len(),
                colors.len(),
                intensities.len(),
                ranges.len(),
                inner.len(),
                outer.len(),
            ]);
            let tau = std::f32::consts::TAU;
            let placement = cycled(positions, n).zip(cycled(directions, n)).zip(cycled(colors, n));
            let strength = cycled(intensities, n).zip(cycled(ranges, n)).zip(cycled(inner, n).zip(cycled(outer, n)));
            let lights: Vec<SpotLight> = placement
                .zip(strength)
                .map(|(((position, direction), color), ((intensity, range), (inner, outer)))| SpotLight {
                    position: *position,
                    direction: *direction,
                    color: Vec3::new(color.r, color.g, color.b),
                    intensity: *intensity,
                    range: *range,
                    inner_angle: inner * tau,
                    outer_angle: outer * tau,
                })
                .collect();
            let lights = LightBuffer::spots(&renderer, &lights);
            cx.set_output(0, resource_spread(ResourceKind::LightWorld, vec![lights]));
            Ok(())
        }),
    );
}
