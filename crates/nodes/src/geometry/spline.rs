//! `Tube` and `Ribbon`: a uniform Catmull-Rom or Bezier spline through the
//! whole Points spread, swept on the GPU (`render::geometry::spline`) into a
//! tube with a radius per point or a flat ribbon with a half width per
//! point; and `Spline`, the same curve's points on the CPU as a spread.

use glam::{Vec3, Vec4};
use spreadlight_graph::{
    Choice, Choices, EvalContext, In, Node, NodeDef, NodeError, Out, Registry, Res,
};
use spreadlight_render::geometry::{Curve, Sweep, curve_point, spline};
use spreadlight_render::mesh_arena::GpuMesh;

use super::continuity::{Continuity, signature};
use crate::gpu::renderer;

fn points() -> Vec<Vec3> {
    vec![
        Vec3::ZERO,
        Vec3::new(1.0, 0.5, 0.0),
        Vec3::new(2.0, 0.0, 0.5),
    ]
}

pub static CURVE: Choices<Curve> = Choices::new(
    "Curve",
    &["Catmull-Rom", "Bezier"],
    &[Curve::CatmullRom, Curve::Bezier],
);

/// The points every spline node starts with.
fn points_input(p: &mut spreadlight_graph::Pins<'_>) -> In<Vec3> {
    p.input_spread("Points", points())
}

/// A NaN or infinite point is an error on Points naming the slice.
fn finite_points(cx: &EvalContext<'_>, pin: In<Vec3>, points: &[Vec3]) -> Result<(), NodeError> {
    match points.iter().position(|p| !p.is_finite()) {
        Some(i) => Err(cx.error(pin, format!("slice {i} is NaN or infinite"))),
        None => Ok(()),
    }
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
        .with_pins_node(|p| {
            let pins = SweepPins {
                points: points_input(p),
                radius: p.input("Radius", 0.1f32),
                segments: p.input("Segments", 8i64),
                sides: Some(p.input("Sides", 12i64)),
                curve: p.input_choice("Curve", &CURVE, Curve::CatmullRom),
                out: super::mesh_output(p, "Mesh"),
            };
            move || SplineNode::new(pins)
        }),
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
        .with_pins_node(|p| {
            let pins = SweepPins {
                points: points_input(p),
                radius: p.input("Width", 0.1f32),
                segments: p.input("Segments", 8i64),
                sides: None,
                curve: p.input_choice("Curve", &CURVE, Curve::CatmullRom),
                out: super::mesh_output(p, "Mesh"),
            };
            move || SplineNode::new(pins)
        }),
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
        .with_pins(|p| {
            let points_in = points_input(p);
            let segments_in = p.input("Segments", 8i64);
            let curve_in = p.input_choice("Curve", &CURVE, Curve::CatmullRom);
            let output = p.output::<Vec3>("Output");
            let tangent = p.output::<Vec3>("Tangent");
            move |cx| {
                let points = cx.get(points_in)?.to_vec();
                let segments = cx.first(segments_in, 8)?;
                if !(1..=1024).contains(&segments) {
                    return Err(cx.error(segments_in, format!("{segments} is not within 1..1024")));
                }
                let curve = cx.choice(curve_in)?;
                let spans = curve.spans(points.len()).map_err(|e| cx.error(points_in, e))?;
                finite_points(cx, points_in, &points)?;
                let controls: Vec<Vec4> = points.iter().map(|p| p.extend(0.0)).collect();
                let steps = spans as usize * segments as usize;
                let (mut out, mut tangents) = (Vec::with_capacity(steps + 1), Vec::with_capacity(steps + 1));
                for k in 0..=steps {
                    let (p, d) = curve_point(&controls, curve, k as f32 / segments as f32);
                    out.push(p.truncate());
                    tangents.push(d.truncate().normalize_or_zero());
                }
                cx.put(output, out);
                cx.put(tangent, tangents);
                Ok(())
            }
        }),
    );
}

/// Tube's and Ribbon's pins: Ribbon has no Sides, and its Radius is Width.
#[derive(Clone, Copy)]
struct SweepPins {
    points: In<Vec3>,
    radius: In<f32>,
    segments: In<i64>,
    sides: Option<In<i64>>,
    curve: In<Choice<Curve>>,
    out: Out<Res<GpuMesh>>,
}

struct SplineNode {
    pins: SweepPins,
    continuity: Continuity,
}

impl SplineNode {
    fn new(pins: SweepPins) -> Self {
        SplineNode {
            pins,
            continuity: Continuity::default(),
        }
    }
}

impl Node for SplineNode {
    fn evaluate(&mut self, cx: &mut EvalContext<'_>) -> Result<(), NodeError> {
        let pins = self.pins;
        let points = cx.get(pins.points)?.to_vec();
        let radii = cx.get(pins.radius)?.to_vec();
        let segments = cx.first(pins.segments, 8)?;
        let sides = match pins.sides {
            Some(sides) => cx.first(sides, 12)?,
            None => 1,
        };
        let curve = cx.choice(pins.curve)?;
        curve
            .spans(points.len())
            .map_err(|e| cx.error(pins.points, e))?;
        finite_points(cx, pins.points, &points)?;
        let sweep = if pins.sides.is_some() {
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
        cx.put_resources(pins.out, out);
        Ok(())
    }
}
