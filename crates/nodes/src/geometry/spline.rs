//! `Tube` and `Ribbon`: a uniform Catmull-Rom spline through the whole
//! Points spread, swept on the GPU (`render::geometry::spline`) into a tube
//! with a radius per point or a flat ribbon with a half width per point.

use glam::Vec3;
use spreadlight_graph::{EvalContext, Node, NodeDef, NodeError, PinType, Registry, ResourceKind};
use spreadlight_render::geometry::{Sweep, spline};

use super::continuity::{Continuity, signature};
use crate::gpu::{renderer, resource_spread};

fn points() -> Vec<Vec3> {
    vec![
        Vec3::ZERO,
        Vec3::new(1.0, 0.5, 0.0),
        Vec3::new(2.0, 0.0, 0.5),
    ]
}

pub fn register(r: &mut Registry) {
    r.add(
        NodeDef::new(
            "Tube",
            super::CATEGORY,
            "A tube along the Catmull-Rom spline through all of Points (it passes through each), Radius slice i at \
             point i (cycled), Segments rings a span, Sides around. Made on the GPU; animated points give previous \
             positions for Velocity From Geometry.",
        )
        .input_spread("Points", PinType::Vec3, spreadlight_graph::Spread::Vec3(points()))
        .input("Radius", 0.1f32)
        .input("Segments", 8i64)
        .input("Sides", 12i64)
        .output_typed("Mesh", PinType::Resource(ResourceKind::Mesh))
        .construct(|| SplineNode::new(true)),
    );
    r.add(
        NodeDef::new(
            "Ribbon",
            super::CATEGORY,
            "A flat ribbon along the Catmull-Rom spline through all of Points, Width slice i (half width) at point i \
             (cycled), Segments a span, facing the curve's normal. Made on the GPU.",
        )
        .input_spread("Points", PinType::Vec3, spreadlight_graph::Spread::Vec3(points()))
        .input("Width", 0.1f32)
        .input("Segments", 8i64)
        .output_typed("Mesh", PinType::Resource(ResourceKind::Mesh))
        .construct(|| SplineNode::new(false)),
    );
}

struct SplineNode {
    tube: bool,
    continuity: Continuity,
}

impl SplineNode {
    fn new(tube: bool) -> Self {
        SplineNode {
            tube,
            continuity: Continuity::default(),
        }
    }
}

impl Node for SplineNode {
    fn evaluate(&mut self, cx: &mut EvalContext<'_>) -> Result<(), NodeError> {
        let points = cx.slices::<Vec3>(0)?.to_vec();
        let radii = cx.slices::<f32>(1)?.to_vec();
        let segments = cx.slices::<i64>(2)?.first().copied().unwrap_or(8);
        let sides = if self.tube {
            cx.slices::<i64>(3)?.first().copied().unwrap_or(12)
        } else {
            1
        };
        if points.len() < 2 {
            return Err(cx.input_error(0, "a spline needs at least 2 points"));
        }
        if let Some(i) = points.iter().position(|p| !p.is_finite()) {
            return Err(cx.input_error(0, format!("slice {i} is NaN or infinite")));
        }
        let sweep = if self.tube {
            Sweep::Tube {
                sides: sides.clamp(3, 1024) as u32,
            }
        } else {
            Sweep::Ribbon
        };
        let mut values: Vec<f32> = points.iter().flat_map(|p| p.to_array()).collect();
        values.extend(&radii);
        values.extend([segments as f32, sides as f32]);
        let renderer = renderer(cx)?;
        let segments = segments.clamp(1, 1024) as u32;
        let out = self
            .continuity
            .run(cx, vec![signature(None, &values)], |_, previous| {
                spline(&renderer, &points, &radii, segments, sweep, previous)
            })?;
        cx.set_output(0, resource_spread(ResourceKind::Mesh, out));
        Ok(())
    }
}
