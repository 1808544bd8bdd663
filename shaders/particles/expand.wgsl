// Reading a procedural mesh back (tests, tables): every triangle's corners
// as the drawing passes make them (shaders/lib/mesh_fetch.wgsl), for one
// instance with the identity transform, three vertices a triangle.
#import spreadlight::mesh::Vertex
#import spreadlight::mesh_fetch::triangle_vertex

struct Params {
    // xyz: the view's right axis; w: triangles.
    right: vec4<f32>,
    // xyz: the view's up axis.
    up: vec4<f32>,
}

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(4) var<storage, read_write> out: array<Vertex>;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = id.x + id.y * groups.x * 64u;
    if (i >= bitcast<u32>(params.right.w) * 3u) {
        return;
    }
    out[i] = triangle_vertex(0u, i / 3u, i % 3u, params.right.xyz, params.up.xyz);
}
