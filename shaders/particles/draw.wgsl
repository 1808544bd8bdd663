// Particles, drawing: expands every particle slot into geometry in the mesh
// arena (a GPU mesh like any other, so DeferredBase, shadow maps and the
// whole chain take it): a camera-facing quad (SPRITES) or a copy of a shape
// mesh (the job's input). Previous positions come from the particle's last
// position, so `Velocity: From Geometry` gives particles motion blur; each
// particle's slot is its geometry id ("Instance from GeomFX"). A dead slot
// collapses to a point: zero-area triangles draw nothing.
#import spreadlight::geometry::{job, vertices, indices, invocation, source_vertex}
#import spreadlight::mesh::Vertex

struct Particle {
    position: vec3<f32>,
    age: f32,
    velocity: vec3<f32>,
    lifetime: f32,
    previous: vec3<f32>,
    alive: u32,
}

struct Params {
    // Camera right and up in world space (sprites), w unused.
    right: vec4<f32>,
    up: vec4<f32>,
    // x: size, y: shrink with age (0 or 1), z: vertices per particle, w: indices per particle.
    shape: vec4<f32>,
}

@group(0) @binding(3) var<uniform> params: Params;
@group(0) @binding(4) var<storage, read> particles: array<Particle>;

fn particle_scale(p: Particle) -> f32 {
    if (p.alive == 0u) {
        return 0.0;
    }
    let t = clamp(p.age / max(p.lifetime, 1e-6), 0.0, 1.0);
    return params.shape.x * mix(1.0, 1.0 - t, params.shape.y);
}

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = invocation(id, groups);
    let per_vertex = u32(params.shape.z);
    let per_index = u32(params.shape.w);
    if (i < job.index_count) {
        let particle = i / per_index;
        let k = i % per_index;
#ifdef SPRITES
        let corner = array<u32, 6>(0u, 1u, 2u, 0u, 2u, 3u)[k];
#else
        let corner = indices[job.src_index + k];
#endif
        indices[job.dst_index + i] = particle * per_vertex + corner;
    }
    if (i >= job.vertex_count) {
        return;
    }
    let particle = particles[i / per_vertex];
    let k = i % per_vertex;
    let scale = particle_scale(particle);
#ifdef SPRITES
    let corner = array<vec2<f32>, 4>(vec2<f32>(-1.0, -1.0), vec2<f32>(1.0, -1.0), vec2<f32>(1.0, 1.0), vec2<f32>(-1.0, 1.0))[k];
    let offset = (params.right.xyz * corner.x + params.up.xyz * corner.y) * scale;
    let normal = normalize(cross(params.right.xyz, params.up.xyz));
    let uv = vec2<f32>(corner.x * 0.5 + 0.5, 0.5 - corner.y * 0.5);
    let tangent = vec4<f32>(params.right.xyz, 1.0);
#else
    let shape = source_vertex(k);
    let offset = shape.position_u.xyz * scale;
    let normal = shape.normal_v.xyz;
    let uv = vec2<f32>(shape.position_u.w, shape.normal_v.w);
    let tangent = shape.tangent;
#endif
    vertices[job.dst_vertex + i] = Vertex(
        vec4<f32>(particle.position + offset, uv.x),
        vec4<f32>(normal, uv.y),
        tangent,
        vec4<f32>(particle.previous + offset, f32(i / per_vertex)),
    );
}
