// Spline geometry: a uniform Catmull-Rom spline through `points` (xyz, w:
// radius at that point) or, with BEZIER, cubic Bezier spans (anchor,
// handle, handle, anchor, handle, ...: 3 k + 1 points, neighbours sharing
// their anchor), swept into a Tube (a ring of `sides` around the curve) or,
// with RIBBON, a flat strip as wide as twice the radius. Ring k sits at
// curve parameter k / segments (a span per unit), so every segments-th ring
// is centred on a control point (Catmull-Rom) or an anchor (Bezier): the
// spline passes through them. Must match `curve_point` in crates/render/src/geometry/spline.rs. Frame:
// T the curve's tangent, N = T x up normalized (up = Y, or X where T is
// vertical), B = T x N. UVs: u around (across for ribbons), v along the
// whole curve; tangents along the curve.
#import spreadlight::geometry::{job, invocation, indices, write_vertex, unit_or}

struct Params {
    // x: control points, y: segments a span, z: sides (ring vertices - 1), w: rings.
    counts: vec4<u32>,
}

@group(0) @binding(3) var<uniform> params: Params;
@group(0) @binding(4) var<storage, read> points: array<vec4<f32>>;

fn point(i: i32) -> vec4<f32> {
    return points[clamp(i, 0, i32(params.counts.x) - 1)];
}

#ifdef BEZIER
// Position (xyz, radius in w) and derivative at parameter t in [0, spans].
fn curve(t: f32) -> array<vec4<f32>, 2> {
    let spans = (params.counts.x - 1u) / 3u;
    let span = min(floor(t), f32(spans) - 1.0);
    let u = t - span;
    let i = 3 * i32(span);
    let p0 = point(i);
    let p1 = point(i + 1);
    let p2 = point(i + 2);
    let p3 = point(i + 3);
    let s = 1.0 - u;
    let position = p0 * (s * s * s) + p1 * (3.0 * s * s * u) + p2 * (3.0 * s * u * u) + p3 * (u * u * u);
    let derivative = 3.0 * ((p1 - p0) * (s * s) + 2.0 * (p2 - p1) * (s * u) + (p3 - p2) * (u * u));
    return array<vec4<f32>, 2>(position, derivative);
}
#else
// Position (xyz, radius in w) and derivative at parameter t in [0, points - 1].
fn curve(t: f32) -> array<vec4<f32>, 2> {
    let last = f32(params.counts.x) - 1.0;
    let span = min(floor(t), max(last - 1.0, 0.0));
    let u = t - span;
    let i = i32(span);
    let p0 = point(i - 1);
    let p1 = point(i);
    let p2 = point(i + 1);
    let p3 = point(i + 2);
    let u2 = u * u;
    let u3 = u2 * u;
    let position = 0.5 * ((2.0 * p1) + (-p0 + p2) * u + (2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3) * u2
        + (-p0 + 3.0 * p1 - 3.0 * p2 + p3) * u3);
    let derivative = 0.5 * ((-p0 + p2) + 2.0 * (2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3) * u
        + 3.0 * (-p0 + 3.0 * p1 - 3.0 * p2 + p3) * u2);
    return array<vec4<f32>, 2>(position, derivative);
}
#endif

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = invocation(id, groups);
    let sides = params.counts.z;
    let ring_size = sides + 1u;
    if (i < job.index_count) {
        let quad = i / 6u;
        let ring = quad / sides;
        let s = quad % sides;
        let a = ring * ring_size + s;
        let b = a + 1u;
        let c = a + ring_size;
        let d = c + 1u;
        indices[job.dst_index + i] = array<u32, 6>(a, b, d, a, d, c)[i % 6u];
    }
    if (i >= job.vertex_count) {
        return;
    }
    let ring = i / ring_size;
    let s = i % ring_size;
    let t = f32(ring) / f32(params.counts.y);
    let c = curve(t);
    let tangent = unit_or(c[1].xyz, vec3<f32>(0.0, 0.0, 1.0));
    var up = vec3<f32>(0.0, 1.0, 0.0);
    if (abs(tangent.y) > 0.999) {
        up = vec3<f32>(1.0, 0.0, 0.0);
    }
    let n = unit_or(cross(tangent, up), vec3<f32>(1.0, 0.0, 0.0));
    let b = cross(tangent, n);
    let radius = c[0].w;
    let spans = (params.counts.w - 1u) / params.counts.y;
    let v = t / max(f32(spans), 1.0);
#ifdef RIBBON
    // Across the strip: -1 .. 1 along B; facing N.
    let across = f32(s) / f32(sides) * 2.0 - 1.0;
    let position = c[0].xyz + b * (across * radius);
    let normal = n;
#else
    let angle = f32(s) / f32(sides) * 6.2831853;
    let normal = n * cos(angle) + b * sin(angle);
    let position = c[0].xyz + normal * radius;
#endif
    write_vertex(i, position, normal, vec2<f32>(f32(s) / f32(sides), v), vec4<f32>(tangent, 1.0), 0.0);
}
