//! Spline geometry: a Catmull-Rom spline through a spread of points swept
//! into a tube or a ribbon (shaders/geometry/spline.wgsl), made on the GPU.

use std::sync::Arc;

use glam::Vec3;
use wgpu::util::DeviceExt;

use super::{Op, run};
use crate::error::RenderError;
use crate::mesh::Aabb;
use crate::mesh_arena::{GpuMesh, MeshLayout};
use crate::renderer::Renderer;
use crate::shaders::ShaderKey;

/// What the spline is swept into.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Sweep {
    /// A ring of this many sides (at least 3) around the curve.
    Tube { sides: u32 },
    /// A flat strip twice the radius wide, facing the curve's normal.
    Ribbon,
}

/// The sweep of the uniform Catmull-Rom spline through `points`, radius
/// `radii[i % len]` at point i, `segments` rings a span.
pub fn spline(
    renderer: &Renderer,
    points: &[Vec3],
    radii: &[f32],
    segments: u32,
    sweep: Sweep,
    previous: Option<&GpuMesh>,
) -> Result<Arc<GpuMesh>, RenderError> {
    let bad = |message: String| RenderError::Pass {
        pass: "Spline".to_owned(),
        message,
    };
    if points.len() < 2 || !points.iter().all(|p| p.is_finite()) {
        return Err(bad(format!(
            "a spline needs at least 2 finite points, got {}",
            points.len()
        )));
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
    let spans = points.len() as u32 - 1;
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
    // Catmull-Rom overshoots its hull by at most half a span's chord, plus the radius.
    let hull = Aabb::from_points(points.iter().copied());
    let span = points
        .windows(2)
        .map(|w| w[0].distance(w[1]))
        .fold(0.0f32, f32::max);
    let reach = span + gpu_points.iter().map(|p| p[3]).fold(0.0f32, f32::max);
    let features: &[&'static str] = match sweep {
        Sweep::Ribbon => &["RIBBON"],
        Sweep::Tube { .. } => &[],
    };
    run(
        renderer,
        Op {
            key: ShaderKey::new("geometry/spline.wgsl", features.iter().copied()),
            input: None,
            previous,
            vertex_count,
            index_count,
            threads: vertex_count.max(index_count),
            params: bytemuck::cast_slice(&params),
            extra: vec![(4, buffer.as_entire_binding())],
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
