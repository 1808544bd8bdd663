// Skinning and morph targets (crates/render/src/geometry/skinning.rs): one
// dispatch deforms every deformed instance of a glTF scene. Each job reads a
// rest mesh in the arena, adds its morph targets' deltas (weighted), blends
// up to 8 joint matrices, and writes a new mesh in the arena with last
// frame's positions as previous positions (so velocity sees the motion),
// and the rest vertex's extras (its colour and second UV set) beside it.
// Threads are numbered across jobs; a thread finds its job by binary search
// over the jobs' first threads.
#import spreadlight::geometry::{vertices, extras, indices, invocation, unit_or, orthogonal_tangent}
#import spreadlight::mesh::Vertex

// Matches `GpuJob` in skinning.rs.
struct Job {
    src_vertex: u32,
    src_index: u32,
    dst_vertex: u32,
    dst_index: u32,
    vertex_count: u32,
    index_count: u32,
    previous_vertex: u32,
    has_previous: u32,
    // Into `influences`; NONE for a mesh without a skin.
    influence_offset: u32,
    // Into `targets` (three vec4 per vertex and target: position, normal, tangent deltas).
    target_offset: u32,
    target_count: u32,
    palette_offset: u32,
    // Joints of the skin; the palette holds one more: the skinned node's transform.
    joint_count: u32,
    weight_offset: u32,
    first_thread: u32,
    spare: u32,
}

// 8 joint indices as 16-bit pairs, and their weights (summing to 1).
struct Influence {
    joints: vec4<u32>,
    weights_a: vec4<f32>,
    weights_b: vec4<f32>,
}

struct Dispatch {
    jobs: u32,
    threads: u32,
    spare_a: u32,
    spare_b: u32,
}

@group(0) @binding(3) var<uniform> work: Dispatch;
@group(0) @binding(4) var<storage, read> jobs: array<Job>;
@group(0) @binding(5) var<storage, read> palette: array<mat4x4<f32>>;
@group(0) @binding(6) var<storage, read> influences: array<Influence>;
@group(0) @binding(7) var<storage, read> targets: array<vec4<f32>>;
@group(0) @binding(8) var<storage, read> morph_weights: array<f32>;

const NONE: u32 = 0xffffffffu;
const UNSKINNED: u32 = 0xffffu;

// The last job whose first thread is at or before `t`.
fn find_job(t: u32) -> u32 {
    var lo = 0u;
    var hi = work.jobs;
    while (hi - lo > 1u) {
        let mid = (lo + hi) / 2u;
        if (jobs[mid].first_thread <= t) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    return lo;
}

// Influence slot `k` (0..8) of `joints`: its palette matrix.
fn joint_matrix(job: Job, joints: vec4<u32>, k: u32) -> mat4x4<f32> {
    let j = (joints[k / 2u] >> (16u * (k % 2u))) & 0xffffu;
    // Weightless vertices (UNSKINNED) follow the node: the palette's last.
    let index = select(min(j, job.joint_count), job.joint_count, j == UNSKINNED);
    return palette[job.palette_offset + index];
}

// det(m) m^-T: transforms normals for any invertible m, also non-uniform scale.
fn cofactor(m: mat3x3<f32>) -> mat3x3<f32> {
    return mat3x3<f32>(cross(m[1], m[2]), cross(m[2], m[0]), cross(m[0], m[1]));
}

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let t = invocation(id, groups);
    if (t >= work.threads) {
        return;
    }
    let job = jobs[find_job(t)];
    let i = t - job.first_thread;
    if (i < job.index_count) {
        indices[job.dst_index + i] = indices[job.src_index + i];
    }
    if (i >= job.vertex_count) {
        return;
    }
    let v = vertices[job.src_vertex + i];
    var p = v.position_u.xyz;
    var n = v.normal_v.xyz;
    var tangent = v.tangent.xyz;
    for (var k = 0u; k < job.target_count; k++) {
        let w = morph_weights[job.weight_offset + k];
        if (w != 0.0) {
            let at = job.target_offset + (k * job.vertex_count + i) * 3u;
            p += w * targets[at].xyz;
            n += w * targets[at + 1u].xyz;
            tangent += w * targets[at + 2u].xyz;
        }
    }
    if (job.influence_offset != NONE) {
        let influence = influences[job.influence_offset + i];
        var m = mat4x4<f32>(vec4<f32>(0.0), vec4<f32>(0.0), vec4<f32>(0.0), vec4<f32>(0.0));
        for (var k = 0u; k < 4u; k++) {
            let wa = influence.weights_a[k];
            if (wa != 0.0) {
                m += joint_matrix(job, influence.joints, k) * wa;
            }
            let wb = influence.weights_b[k];
            if (wb != 0.0) {
                m += joint_matrix(job, influence.joints, k + 4u) * wb;
            }
        }
        p = (m * vec4<f32>(p, 1.0)).xyz;
        let linear = mat3x3<f32>(m[0].xyz, m[1].xyz, m[2].xyz);
        let det = dot(linear[0], cross(linear[1], linear[2]));
        n = cofactor(linear) * n * select(-1.0, 1.0, det >= 0.0);
        tangent = linear * tangent;
    }
    let normal = unit_or(n, v.normal_v.xyz);
    var before = p;
    if (job.has_previous == 1u) {
        before = vertices[job.previous_vertex + i].position_u.xyz;
    }
    vertices[job.dst_vertex + i] = Vertex(
        vec4<f32>(p, v.position_u.w),
        vec4<f32>(normal, v.normal_v.w),
        orthogonal_tangent(vec4<f32>(tangent, v.tangent.w), normal),
        vec4<f32>(before, v.previous_position.w),
    );
    extras[job.dst_vertex + i] = extras[job.src_vertex + i];
}
