// PN Triangles (Vlachos et al. 2001), and with FLAT plain subdivision: each
// input triangle becomes a grid of level² triangles. PN places the grid on
// the cubic Bezier patch its corners' positions and normals define (normals
// on the quadratic patch), which depends only on an edge's two vertices
// along that edge: neighbours sharing positions and normals stay crack-free.
// Grid point (row r, column c) has barycentrics (1 - (c + r) / n, c / n, r / n).
#import spreadlight::geometry::{job, invocation, indices, source_vertex, write_vertex, unit_or, orthogonal_tangent}
#import spreadlight::mesh::Vertex

struct Params {
    // x: level (segments an edge).
    level: vec4<u32>,
}

@group(0) @binding(3) var<uniform> params: Params;

fn corner(face: u32, k: u32) -> Vertex {
    return source_vertex(indices[job.src_index + face * 3u + k]);
}

// First vertex of grid row r.
fn row_start(r: u32, n: u32) -> u32 {
    return r * (n + 1u) - (r * (r - 1u)) / 2u * select(0u, 1u, r > 0u);
}

fn pn_position(p1: vec3<f32>, p2: vec3<f32>, p3: vec3<f32>, n1: vec3<f32>, n2: vec3<f32>, n3: vec3<f32>, w: vec3<f32>) -> vec3<f32> {
    let b210 = (2.0 * p1 + p2 - dot(p2 - p1, n1) * n1) / 3.0;
    let b120 = (2.0 * p2 + p1 - dot(p1 - p2, n2) * n2) / 3.0;
    let b021 = (2.0 * p2 + p3 - dot(p3 - p2, n2) * n2) / 3.0;
    let b012 = (2.0 * p3 + p2 - dot(p2 - p3, n3) * n3) / 3.0;
    let b102 = (2.0 * p3 + p1 - dot(p1 - p3, n3) * n3) / 3.0;
    let b201 = (2.0 * p1 + p3 - dot(p3 - p1, n1) * n1) / 3.0;
    let e = (b210 + b120 + b021 + b012 + b102 + b201) / 6.0;
    let v = (p1 + p2 + p3) / 3.0;
    let b111 = e + (e - v) * 0.5;
    let u = w.x;
    let s = w.y;
    let t = w.z;
    return p1 * u * u * u + p2 * s * s * s + p3 * t * t * t
        + 3.0 * (b210 * u * u * s + b120 * u * s * s + b201 * u * u * t
        + b021 * s * s * t + b102 * u * t * t + b012 * s * t * t)
        + 6.0 * b111 * u * s * t;
}

fn edge_normal(pa: vec3<f32>, pb: vec3<f32>, na: vec3<f32>, nb: vec3<f32>) -> vec3<f32> {
    let d = pb - pa;
    let dd = max(dot(d, d), 1e-20);
    return unit_or(na + nb - 2.0 * dot(d, na + nb) / dd * d, unit_or(na + nb, na));
}

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = invocation(id, groups);
    let n = max(params.level.x, 1u);
    let per_face_vertices = (n + 1u) * (n + 2u) / 2u;
    let per_face_triangles = n * n;
    if (i < job.index_count) {
        let face = i / (per_face_triangles * 3u);
        var q = (i / 3u) % per_face_triangles;
        var r = 0u;
        loop {
            let in_row = 2u * (n - r) - 1u;
            if (q < in_row) {
                break;
            }
            q -= in_row;
            r += 1u;
        }
        let base = face * per_face_vertices;
        let here = row_start(r, n);
        let next = row_start(r + 1u, n);
        var tri: array<u32, 3>;
        if (q % 2u == 0u) {
            let c = q / 2u;
            tri = array<u32, 3>(here + c, here + c + 1u, next + c);
        } else {
            let c = q / 2u;
            tri = array<u32, 3>(here + c + 1u, next + c + 1u, next + c);
        }
        indices[job.dst_index + i] = base + tri[i % 3u];
    }
    if (i >= job.vertex_count) {
        return;
    }
    let face = i / per_face_vertices;
    var l = i % per_face_vertices;
    var r = 0u;
    loop {
        let in_row = n + 1u - r;
        if (l < in_row) {
            break;
        }
        l -= in_row;
        r += 1u;
    }
    let w = vec3<f32>(f32(n - r - l), f32(l), f32(r)) / f32(n);
    let a = corner(face, 0u);
    let b = corner(face, 1u);
    let c = corner(face, 2u);
    let n1 = unit_or(a.normal_v.xyz, vec3<f32>(0.0, 1.0, 0.0));
    let n2 = unit_or(b.normal_v.xyz, n1);
    let n3 = unit_or(c.normal_v.xyz, n1);
    let linear_normal = n1 * w.x + n2 * w.y + n3 * w.z;
#ifdef FLAT
    let position = a.position_u.xyz * w.x + b.position_u.xyz * w.y + c.position_u.xyz * w.z;
    let normal = unit_or(linear_normal, n1);
#else
    let position = pn_position(a.position_u.xyz, b.position_u.xyz, c.position_u.xyz, n1, n2, n3, w);
    let n110 = edge_normal(a.position_u.xyz, b.position_u.xyz, n1, n2);
    let n011 = edge_normal(b.position_u.xyz, c.position_u.xyz, n2, n3);
    let n101 = edge_normal(c.position_u.xyz, a.position_u.xyz, n3, n1);
    let normal = unit_or(
        n1 * w.x * w.x + n2 * w.y * w.y + n3 * w.z * w.z
            + n110 * w.x * w.y + n011 * w.y * w.z + n101 * w.x * w.z,
        unit_or(linear_normal, n1),
    );
#endif
    let uv = vec2<f32>(
        dot(w, vec3<f32>(a.position_u.w, b.position_u.w, c.position_u.w)),
        dot(w, vec3<f32>(a.normal_v.w, b.normal_v.w, c.normal_v.w)),
    );
    let tangent = orthogonal_tangent(a.tangent * w.x + b.tangent * w.y + c.tangent * w.z, normal);
    write_vertex(i, position, normal, uv, tangent, a.previous_position.w);
}
