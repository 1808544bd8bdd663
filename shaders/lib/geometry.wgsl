// What every GPU geometry pass shares (crates/render/src/geometry/): the
// mesh arena read-write, the job (where the input, the output and last
// frame's output live in the arena), and writing an output vertex with its
// previous-frame position, so `Velocity: From Geometry` sees deformation,
// and its extras (the second UV set and the colour), which no CPU writes
// for a mesh a pass makes.
#define_import_path spreadlight::geometry

#import spreadlight::mesh::{Vertex, VertexExtra}

// Matches `GpuJob` in crates/render/src/geometry/mod.rs.
struct Job {
    src_vertex: u32,
    src_index: u32,
    dst_vertex: u32,
    dst_index: u32,
    vertex_count: u32,
    index_count: u32,
    // Last frame's output: used when it has as many vertices as this one.
    previous_vertex: u32,
    has_previous: u32,
    src_vertex_count: u32,
    src_index_count: u32,
    spare_a: u32,
    spare_b: u32,
}

@group(0) @binding(0) var<storage, read_write> vertices: array<Vertex>;
@group(0) @binding(1) var<storage, read_write> indices: array<u32>;
@group(0) @binding(2) var<uniform> job: Job;
// Parallel to `vertices` (the arena's extra stream); 9, past every pass's own bindings.
@group(0) @binding(9) var<storage, read_write> extras: array<VertexExtra>;

// The flat invocation index of a dispatch spread over x and y (64 a group).
fn invocation(id: vec3<u32>, groups: vec3<u32>) -> u32 {
    return id.x + id.y * groups.x * 64u;
}

fn source_vertex(i: u32) -> Vertex {
    return vertices[job.src_vertex + i];
}

// Output vertex `i`. Its previous position is vertex `i` of last frame's
// output when there is one of the same size, else its own (no motion). Its
// extras are what an uploaded mesh without the streams gets (mesh_arena.rs):
// the first UV set as the second, and white.
fn write_vertex(i: u32, position: vec3<f32>, normal: vec3<f32>, uv: vec2<f32>, tangent: vec4<f32>, geometry_id: f32) {
    var before = position;
    if (job.has_previous == 1u) {
        before = vertices[job.previous_vertex + i].position_u.xyz;
    }
    vertices[job.dst_vertex + i] = Vertex(
        vec4<f32>(position, uv.x),
        vec4<f32>(normal, uv.y),
        tangent,
        vec4<f32>(before, geometry_id),
    );
    extras[job.dst_vertex + i] = VertexExtra(uv, vec2<u32>(0xffffffffu, 0xffffffffu));
}

// For passes that keep the topology: index `i` of the output is the input's.
fn copy_index(i: u32) {
    indices[job.dst_index + i] = indices[job.src_index + i];
}

// `v` made unit length, or `fallback` when it has none (never NaN).
fn unit_or(v: vec3<f32>, fallback: vec3<f32>) -> vec3<f32> {
    let l = length(v);
    if (l > 1e-20 && l < 3.0e38) {
        return v / l;
    }
    return fallback;
}

// A tangent made perpendicular to `normal` (Gram-Schmidt), keeping its handedness.
fn orthogonal_tangent(tangent: vec4<f32>, normal: vec3<f32>) -> vec4<f32> {
    var t = tangent.xyz - normal * dot(normal, tangent.xyz);
    var fallback = cross(normal, vec3<f32>(0.0, 1.0, 0.0));
    if (length(fallback) < 1e-3) {
        fallback = cross(normal, vec3<f32>(1.0, 0.0, 0.0));
    }
    return vec4<f32>(unit_or(t, normalize(fallback)), select(-1.0, 1.0, tangent.w >= 0.0));
}
