//! `Tube` and `Ribbon`: a uniform Catmull-Rom or Bezier spline through the
//! whole Points spread, swept on the GPU (`render::geometry::spline`) into a
//! tube with a radius per point or a flat ribbon with a half width per
//! point; and `Spline`, the same curve's points on the CPU as a spread.

use glam::{Vec3, Vec4};
use spreadlight_graph::{
    EnumDef, EvalContext, Node, NodeDef, NodeError, PinType, Registry, ResourceKind, Spread,
};
use spreadlight_render::geometry::{Curve, Sweep, curve_point, spline};

use super::continuity::{Continuity, signature};
use crate::gpu::{renderer, resource_spread};

fn points() -> Vec<Vec3> {
    vec![
        Vec3::ZERO,
        Vec3::new(1.0, 0.5, 0.0),
        Vec3::new(2.0, 0.0, 0.5),
    ]
}

pub static CURVE: EnumDef = EnumDef {
    name: "Curve",
    options: &["Catmull-Rom", "Bezier"],
};

fn curve(cx: &EvalContext<'_>, pin: usize) -> Result<Curve, NodeError> {
    Ok(match cx.enum_slices(pin)?.first().map(String::as_str) {
        Some("Bezier") => Curve::Bezier,
        _ => Curve::CatmullRom,
    })
}

const CURVE_HELP: &str = "Curve Catmull-Rom passes through every point; Curve Bezier takes cubic spans (anchor, handle, \
     handle, anchor, handle, ...: 3k + 1 points) and passes through the anchors.";

pub fn register(r: &mut Registry) {
    r.add(
        NodeDef::new(
            "Tube",
            super::CATEGORY,
            format!(
                "A tube along the spline through all of Points, Radius slice i at point i (cycled, interpolated \
                 along the curve like the points), Segments (1..1024) rings a span, Sides (3..1024) around. \
                 {CURVE_HELP} Made on the GPU; animated points give previous positions for Velocity From Geometry."
            ),
        )
        .input_spread("Points", PinType::Vec3, spreadlight_graph::Spread::Vec3(points()))
        .input("Radius", 0.1f32)
        .input("Segments", 8i64)
        .input("Sides", 12i64)
        .input_enum("Curve", &CURVE, "Catmull-Rom")
        .output_typed("Mesh", PinType::Resource(ResourceKind::Mesh))
        .construct(|| SplineNode::new(true)),
    );
    r.add(
        NodeDef::new(
            "Ribbon",
            super::CATEGORY,
            format!(
                "A flat ribbon along the spline through all of Points, Width slice i (half width) at point i \
                 (cycled), Segments (1..1024) a span, facing the curve's normal. {CURVE_HELP} Made on the GPU."
            ),
        )
        .input_spread("Points", PinType::Vec3, spreadlight_graph::Spread::Vec3(points()))
        .input("Width", 0.1f32)
        .input("Segments", 8i64)
        .input_enum("Curve", &CURVE, "Catmull-Rom")
        .output_typed("Mesh", PinType::Resource(ResourceKind::Mesh))
        .construct(|| SplineNode::new(false)),
    );
    r.add(
        NodeDef::new(
            "Spline",
            super::CATEGORY,
            format!(
                "Points along the spline through all of Points: Segments (1..1024) a span, from the first point to \
                 the last, with the curve's unit Tangent at each. {CURVE_HELP} The same curve Tube and Ribbon \
                 sweep, on the CPU."
            ),
        )
        .input_spread("Points", PinType::Vec3, Spread::Vec3(points()))
        .input("Segments", 8i64)
        .input_enum("Curve", &CURVE, "Catmull-Rom")
        .output::<Vec3>("Output")
        .output::<Vec3>("Tangent")
        .evaluate(|cx| {
            let points = cx.slices::<Vec3>(0)?.to_vec();
            let segments = cx.slices::<i64>(1)?.first().copied().unwrap_or(8);
            if !(1..=1024).contains(&segments) {
                return Err(cx.input_error(1, format!("{segments} is not within 1..1024")));
            }
            let curve = curve(cx, 2)?;
            let spans = curve.spans(points.len()).map_err(|e| cx.input_error(0, e))?;
            if let Some(i) = points.iter().position(|p| !p.is_finite()) {
                return Err(cx.input_error(0, format!("slice {i} is NaN or infinite")));
            }
            let controls: Vec<Vec4> = points.iter().map(|p| p.extend(0.0)).collect();
            let steps = spans as usize * segments as usize;
            let (mut out, mut tangents) = (Vec::with_capacity(steps + 1), Vec::with_capacity(steps + 1));
            for k in 0..=steps {
                let (p, d) = curve_point(&controls, curve, k as f32 / segments as f32);
                out.push(p.truncate());
                tangents.push(d.truncate().normalize_or_zero());
            }
            cx.set_output(0, Spread::Vec3(out));
            cx.set_output(1, Spread::Vec3(tangents));
            Ok(())
        }),
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
        let curve_pin = if self.tube { 4 } else { 3 };
        let curve = curve(cx, curve_pin)?;
        curve
            .spans(points.len())
            .map_err(|e| cx.input_error(0, e))?;
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
        values.extend([segments as f32, sides as f32, curve as u8 as f32]);
        let renderer = renderer(cx)?;
        let segments = segments.clamp(1, 1024) as u32;
        let out = self
            .continuity
            .run(cx, vec![signature(None, &values)], |_, previous| {
                spline(&renderer, &points, &radii, curve, segments, sweep, previous)
            })?;
        cx.set_output(0, resource_spread(ResourceKind::Mesh, out));
        Ok(())
    }
}
