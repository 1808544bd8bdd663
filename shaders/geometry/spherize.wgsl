// Spherize: blends every vertex towards the sphere of `radius` around
// `center` along the ray from the centre (Amount 0: the mesh, 1: on the
// sphere). Normals and tangents go through the map's Jacobian
// J = (1 - a) I + a r / |p| (I - d dT), exact for any amount; UVs are kept.
#import spreadlight::geometry::{job, invocation, source_vertex, write_vertex, copy_index, unit_or, orthogonal_tangent}

struct Params {
    center: vec3<f32>,
    radius: f32,
    amount: f32,
    pad_a: f32,
    pad_b: f32,
    pad_c: f32,
}

@group(0) @binding(3) var<uniform> params: Params;

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
    let n = v.normal_v.xyz;
    let p = v.position_u.xyz - params.center;
    let len = length(p);
    // A vertex at the centre has no direction: push it along its normal.
    let d = unit_or(p, unit_or(n, vec3<f32>(0.0, 1.0, 0.0)));
    let a = clamp(params.amount, 0.0, 1.0);
    let position = params.center + mix(p, d * params.radius, a);
    // Eigenvalues of J: (1 - a) along d, s across it.
    let s = (1.0 - a) + a * params.radius / max(len, 1e-6);
    let along = dot(n, d);
    // J^-T n, scaled by (1 - a) s so that a = 1 stays finite.
    let normal = unit_or(s * along * d + (1.0 - a) * (n - along * d), d * select(-1.0, 1.0, along >= 0.0));
    let t = v.tangent.xyz;
    let moved_tangent = (1.0 - a) * dot(t, d) * d + s * (t - dot(t, d) * d);
    let tangent = orthogonal_tangent(vec4<f32>(moved_tangent, v.tangent.w), normal);
    write_vertex(i, position, normal, vec2<f32>(v.position_u.w, v.normal_v.w), tangent, v.previous_position.w);
}
