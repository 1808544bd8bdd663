//! Spline geometry: a Catmull-Rom or Bezier spline through a spread of
//! points swept into a tube or a ribbon (shaders/geometry/spline.wgsl), made
//! on the GPU; and the same curve on the CPU ([`curve_point`]) for nodes that
//! want its points and for tests.

use std::sync::Arc;

use glam::{Vec3, Vec4};
use wgpu::util::DeviceExt;

use super::{Op, run};
use crate::error::RenderError;
use crate::mesh::Aabb;
use crate::mesh_arena::{GpuMesh, MeshLayout};
use crate::renderer::Renderer;
use crate::shaders::Permutation;

pub use super::spline_key::SplineKey;

/// What the spline is swept into.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Sweep {
    /// A ring of this many sides (at least 3) around the curve.
    Tube { sides: u32 },
    /// A flat strip twice the radius wide, facing the curve's normal.
    Ribbon,
}

/// Which curve goes through the points.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Curve {
    /// Uniform Catmull-Rom through every point (the ends repeated).
    CatmullRom,
    /// Cubic Bezier spans: anchor, handle, handle, anchor, handle, handle,
    /// anchor... (3 k + 1 points); the curve passes through the anchors.
    Bezier,
}

impl Curve {
    /// Spans of the curve through `points` points, or why there are none.
    pub fn spans(self, points: usize) -> Result<u32, String> {
        let spans = match self {
            Curve::CatmullRom if points >= 2 => points - 1,
            Curve::CatmullRom => {
                return Err(format!(
                    "a Catmull-Rom spline needs at least 2 points, got {points}"
                ));
            }
            Curve::Bezier if points >= 4 && (points - 1).is_multiple_of(3) => (points - 1) / 3,
            Curve::Bezier => {
                return Err(format!(
                    "a Bezier spline needs 3 k + 1 points (anchor, handle, handle, anchor, ...), got {points}"
                ));
            }
        };
        u32::try_from(spans).map_err(|_| "too many points".to_owned())
    }
}

/// Position (xyz; w: the radius, interpolated alike) and derivative of the
/// curve through `points` at parameter `t` in 0..=spans (a span per unit).
/// The CPU twin of `curve` in shaders/geometry/spline.wgsl. `points` must
/// have a valid count for `curve` ([`Curve::spans`]).
pub fn curve_point(points: &[Vec4], curve: Curve, t: f32) -> (Vec4, Vec4) {
    let last = points.len() as i64 - 1;
    let point = |i: i64| points[i.clamp(0, last) as usize];
    match curve {
        Curve::Bezier => {
            let spans = (points.len() as f32 - 1.0) / 3.0;
            let span = t.floor().min(spans - 1.0).max(0.0);
            let u = t - span;
            let i = 3 * span as i64;
            let (p0, p1, p2, p3) = (point(i), point(i + 1), point(i + 2), point(i + 3));
            let s = 1.0 - u;
            let position = p0 * (s * s * s)
                + p1 * (3.0 * s * s * u)
                + p2 * (3.0 * s * u * u)
                + p3 * (u * u * u);
            let derivative =
                3.0 * ((p1 - p0) * (s * s) + 2.0 * (p2 - p1) * (s * u) + (p3 - p2) * (u * u));
            (position, derivative)
        }
        Curve::CatmullRom => {
            let span = t.floor().min((last as f32 - 1.0).max(0.0)).max(0.0);
            let u = t - span;
            let i = span as i64;
            let (p0, p1, p2, p3) = (point(i - 1), point(i), point(i + 1), point(i + 2));
            let (u2, u3) = (u * u, u * u * u);
            let position = 0.5
                * ((2.0 * p1)
                    + (-p0 + p2) * u
                    + (2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3) * u2
                    + (-p0 + 3.0 * p1 - 3.0 * p2 + p3) * u3);
            let derivative = 0.5
                * ((-p0 + p2)
                    + 2.0 * (2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3) * u
                    + 3.0 * (-p0 + 3.0 * p1 - 3.0 * p2 + p3) * u2);
            (position, derivative)
        }
    }
}

/// The sweep of the spline (`curve`) through `points`, radius
/// `radii[i % len]` at point i, `segments` rings a span.
pub fn spline(
    renderer: &Renderer,
    points: &[Vec3],
    radii: &[f32],
    curve: Curve,
    segments: u32,
    sweep: Sweep,
    previous: Option<&GpuMesh>,
) -> Result<Arc<GpuMesh>, RenderError> {
    let bad = |message: String| RenderError::Pass {
        pass: "Spline".to_owned(),
        message,
    };
    let spans = curve.spans(points.len()).map_err(bad)?;
    if !points.iter().all(|p| p.is_finite()) {
        return Err(bad("every point must be finite".to_owned()));
    }
    let radius = |i: usize| {
        let r = radii.get(i % radii.len().max(1)).copied().unwrap_or(0.1);
        if r.is_finite() { r.max(0.0) } else { 0.0 }
    };
    let gpu_points: Vec<[f32; 4]> = points
        .iter()
        .enumerate()
        .map(|(i, p)| p.extend(radius(i)).into())
        .collect();
    let segments = segments.clamp(1, 1024);
    let sides = match sweep {
        Sweep::Tube { sides } => sides.clamp(3, 1024),
        Sweep::Ribbon => 1,
    };
    let rings = spans
        .checked_mul(segments)
        .and_then(|r| r.checked_add(1))
        .ok_or_else(|| bad("too many points".to_owned()))?;
    let vertex_count = rings
        .checked_mul(sides + 1)
        .ok_or_else(|| bad("too many rings".to_owned()))?;
    let index_count = (rings - 1)
        .checked_mul(sides * 6)
        .ok_or_else(|| bad("too many rings".to_owned()))?;
    let buffer = renderer
        .gpu
        .device
        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("spline points"),
            contents: bytemuck::cast_slice(&gpu_points),
            usage: wgpu::BufferUsages::STORAGE,
        });
    let params = [points.len() as u32, segments, sides, rings];
    // Catmull-Rom overshoots its hull by at most half a span's chord, plus the
    // radius; a Bezier span stays inside its control points' hull.
    let hull = Aabb::from_points(points.iter().copied());
    let span = points
        .windows(2)
        .map(|w| w[0].distance(w[1]))
        .fold(0.0f32, f32::max);
    let reach = span + gpu_points.iter().map(|p| p[3]).fold(0.0f32, f32::max);
    let key = SplineKey {
        ribbon: matches!(sweep, Sweep::Ribbon),
        bezier: curve == Curve::Bezier,
    };
    run(
        renderer,
        Op {
            key: key.key(),
            input: None,
            previous,
            vertex_count,
            index_count,
            threads: vertex_count.max(index_count),
            params: bytemuck::cast_slice(&params),
            extra: vec![("points", buffer.as_entire_binding())],
            layout: MeshLayout {
                bounds: Aabb {
                    min: hull.min - Vec3::splat(reach),
                    max: hull.max + Vec3::splat(reach),
                },
                has_uvs: true,
                has_tangents: true,
            },
        },
    )
}
