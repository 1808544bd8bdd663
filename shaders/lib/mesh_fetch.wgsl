// Pulling triangles from the mesh arena, for every pass that draws meshes
// (the G-buffer's visibility, compute raster and resolve, shadow depth,
// transparency): bindings 1 to 3 (the arena's vertices and indices, the
// instances) and one function that gives a triangle's corner.
//
// An instance whose first-index word has PROCEDURAL set draws a particle
// system straight from its records (header at the base vertex, then one
// record a particle, shaders/lib/particle.wgsl): two triangles a particle
// facing the drawing view (sprites), or a copy of a shape mesh a particle.
// Nothing is expanded into the arena, so ten million particles cost their
// 640 MB of state, not 2.5 GB of quads; previous positions (for velocity)
// and the slot as geometry id come from the record as an expanded mesh's
// would.
#define_import_path spreadlight::mesh_fetch

#import spreadlight::mesh::{Vertex, Instance}
#import spreadlight::particle::{Particle, ParticleHeader, unpack_particle, unpack_header, particle_scale}

@group(0) @binding(1) var<storage, read> vertices: array<Vertex>;
@group(0) @binding(2) var<storage, read> indices: array<u32>;
@group(0) @binding(3) var<storage, read> instances: array<Instance>;

// Matches `PROCEDURAL_FLAG` in crates/render/src/mesh_arena.rs.
const PROCEDURAL: u32 = 0x80000000u;

// A view matrix's right and up axes in world space (its first two rows);
// for a view-projection they point the same way (unnormalized).
fn view_right(m: mat4x4<f32>) -> vec3<f32> {
    return vec3<f32>(m[0].x, m[1].x, m[2].x);
}

fn view_up(m: mat4x4<f32>) -> vec3<f32> {
    return vec3<f32>(m[0].y, m[1].y, m[2].y);
}

fn unit_or(v: vec3<f32>, fallback: vec3<f32>) -> vec3<f32> {
    let len2 = dot(v, v);
    if (len2 > 1e-20) {
        return v * inverseSqrt(len2);
    }
    return fallback;
}

// Corner `corner` (0 to 2) of triangle `triangle` of instance `instance`, in
// object space. `right` and `up`: the drawing view's axes in world space,
// which sprites face.
fn triangle_vertex(instance: u32, triangle: u32, corner: u32, right: vec3<f32>, up: vec3<f32>) -> Vertex {
    let info = instances[instance].info;
    if ((info.x & PROCEDURAL) == 0u) {
        return vertices[indices[info.x + triangle * 3u + corner] + info.y];
    }
    return particle_vertex(instance, info.y, triangle, corner, right, up);
}

// A mesh corner's object-space position alone, for a pass whose draws hold
// no particle system (the compute raster's MESHES_ONLY, which CPU adapters
// take: adapter_class.rs). A CPU adapter runs both sides of a branch its
// lanes do not all take alike and loads a struct read whole member by
// member, lane by lane: through triangle_vertex every corner paid for the
// particle path and 16 loads where the raster needs 3.
fn mesh_position(instance: u32, triangle: u32, corner: u32) -> vec3<f32> {
    let info = instances[instance].info;
    return vertices[indices[info.x + triangle * 3u + corner] + info.y].position_u.xyz;
}

// The arena index of a triangle's corner, for streams kept beside the
// vertices (the extras of shaders/lib/mesh.wgsl), or NO_VERTEX for a
// procedural mesh, whose corners are made here, not stored.
const NO_VERTEX: u32 = 0xffffffffu;

fn triangle_vertex_index(instance: u32, triangle: u32, corner: u32) -> u32 {
    let info = instances[instance].info;
    if ((info.x & PROCEDURAL) != 0u) {
        return NO_VERTEX;
    }
    return indices[info.x + triangle * 3u + corner] + info.y;
}

fn particle_vertex(instance: u32, base: u32, triangle: u32, corner: u32, right_world: vec3<f32>, up_world: vec3<f32>) -> Vertex {
    let h = unpack_header(vertices[base]);
    if (h.shape == 0u) {
        let slot = triangle / 2u;
        let p = unpack_particle(vertices[base + 1u + slot]);
        let scale = particle_scale(p, h);
        // The view's axes in object space: the model's inverse is the
        // transpose of its normal matrix (an inverse transpose).
        let n = instances[instance].normal_matrix;
        let to_object = transpose(mat3x3<f32>(n[0].xyz, n[1].xyz, n[2].xyz));
        let right = unit_or(to_object * right_world, vec3<f32>(1.0, 0.0, 0.0));
        let up = unit_or(to_object * up_world, vec3<f32>(0.0, 1.0, 0.0));
        // Quad corners 0 1 2 3 counter-clockwise, triangles (0 1 2) and (0 2 3).
        let k = array<u32, 6>(0u, 1u, 2u, 0u, 2u, 3u)[(triangle % 2u) * 3u + corner];
        let c = array<vec2<f32>, 4>(vec2<f32>(-1.0, -1.0), vec2<f32>(1.0, -1.0), vec2<f32>(1.0, 1.0), vec2<f32>(-1.0, 1.0))[k];
        let offset = (right * c.x + up * c.y) * scale;
        let normal = unit_or(cross(right, up), vec3<f32>(0.0, 0.0, 1.0));
        return Vertex(
            vec4<f32>(p.position + offset, c.x * 0.5 + 0.5),
            vec4<f32>(normal, 0.5 - c.y * 0.5),
            vec4<f32>(right, 1.0),
            vec4<f32>(p.previous + offset, f32(slot)),
        );
    }
    let per = max(h.triangles, 1u);
    let slot = triangle / per;
    let p = unpack_particle(vertices[base + 1u + slot]);
    let scale = particle_scale(p, h);
    let v = vertices[indices[h.first_index + (triangle % per) * 3u + corner] + h.base_vertex];
    let offset = v.position_u.xyz * scale;
    return Vertex(
        vec4<f32>(p.position + offset, v.position_u.w),
        v.normal_v,
        v.tangent,
        vec4<f32>(p.previous + offset, f32(slot)),
    );
}
