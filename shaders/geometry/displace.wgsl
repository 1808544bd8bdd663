// Displace: every vertex moved along its normal by a texture's red channel
// at the vertex's UV, (height - midlevel) x amount; then normals recomputed
// from the moved surface. Three stages (crates/render/src/geometry/displace.rs):
// move (no feature): positions, indices copied;
// ACCUMULATE: each triangle adds its unit normal, weighted by its corner's
//   angle, to its three vertices (fixed point, atomically: WGSL has no float
//   atomics);
// NORMALS: each vertex takes the normalized sum (its input normal where the
//   sum vanishes) and a tangent made perpendicular to it again.
// Vertices shared by triangles get smooth normals; split vertices (hard
// edges, UV seams) each average their own side, as the input had them.
#import spreadlight::geometry::{job, invocation, indices, vertices, source_vertex, write_vertex, copy_index, unit_or, orthogonal_tangent}

struct Params {
    amount: f32,
    midlevel: f32,
    spare: vec2<f32>,
}

@group(0) @binding(3) var<uniform> params: Params;
@group(0) @binding(4) var height: texture_2d<f32>;
@group(0) @binding(5) var height_sampler: sampler;
@group(0) @binding(6) var<storage, read_write> normal_sums: array<atomic<i32>>;

// Fixed point of the sums: a vertex's angles add up to about 2 pi, so
// 2^20 leaves room for vertices shared by a few hundred triangles.
const SCALE: f32 = 1048576.0;

#ifdef ACCUMULATE
fn angle(at: vec3<f32>, p: vec3<f32>, q: vec3<f32>) -> f32 {
    let u = unit_or(p - at, vec3<f32>(0.0));
    let v = unit_or(q - at, vec3<f32>(0.0));
    return acos(clamp(dot(u, v), -1.0, 1.0));
}

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let face = invocation(id, groups);
    if (face * 3u >= job.index_count) {
        return;
    }
    var k = array<u32, 3>(
        indices[job.dst_index + face * 3u],
        indices[job.dst_index + face * 3u + 1u],
        indices[job.dst_index + face * 3u + 2u],
    );
    var p: array<vec3<f32>, 3>;
    for (var c = 0u; c < 3u; c++) {
        p[c] = vertices[job.dst_vertex + k[c]].position_u.xyz;
    }
    let n = unit_or(cross(p[1] - p[0], p[2] - p[0]), vec3<f32>(0.0));
    for (var c = 0u; c < 3u; c++) {
        let weighted = n * angle(p[c], p[(c + 1u) % 3u], p[(c + 2u) % 3u]) * SCALE;
        for (var axis = 0u; axis < 3u; axis++) {
            atomicAdd(&normal_sums[k[c] * 3u + axis], i32(round(weighted[axis])));
        }
    }
}
#else
#ifdef NORMALS
@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = invocation(id, groups);
    if (i >= job.vertex_count) {
        return;
    }
    let sum = vec3<f32>(
        f32(atomicLoad(&normal_sums[i * 3u])),
        f32(atomicLoad(&normal_sums[i * 3u + 1u])),
        f32(atomicLoad(&normal_sums[i * 3u + 2u])),
    );
    var v = vertices[job.dst_vertex + i];
    let normal = unit_or(sum, unit_or(v.normal_v.xyz, vec3<f32>(0.0, 1.0, 0.0)));
    v.normal_v = vec4<f32>(normal, v.normal_v.w);
    v.tangent = orthogonal_tangent(v.tangent, normal);
    vertices[job.dst_vertex + i] = v;
}
#else
@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = invocation(id, groups);
    if (i < job.index_count) {
        copy_index(i);
    }
    if (i >= job.vertex_count) {
        return;
    }
    let v = source_vertex(i);
    let uv = vec2<f32>(v.position_u.w, v.normal_v.w);
    let n = unit_or(v.normal_v.xyz, vec3<f32>(0.0, 1.0, 0.0));
    var d = (textureSampleLevel(height, height_sampler, uv, 0.0).r - params.midlevel) * params.amount;
    // A NaN or infinite texel moves nothing.
    if (!(abs(d) < 3.0e38)) {
        d = 0.0;
    }
    write_vertex(i, v.position_u.xyz + n * d, n, uv, v.tangent, v.previous_position.w);
}
#endif
#endif
