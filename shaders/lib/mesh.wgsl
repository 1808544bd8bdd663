// Mesh and instance records as the G-buffer passes read them from storage
// buffers (no vertex buffers: the visibility pass fetches by index).
#define_import_path spreadlight::mesh

// 64 bytes. Matches `GpuVertex` in crates/render/src/mesh_arena.rs.
struct Vertex {
    position_u: vec4<f32>,
    normal_v: vec4<f32>,
    tangent: vec4<f32>,
    previous_position: vec4<f32>,
}

// 16 bytes, a stream beside the vertices (same index). Matches
// `GpuVertexExtra` in crates/render/src/mesh_arena.rs: the second UV set
// (TEXCOORD_1, or TEXCOORD_0 where the mesh has none) and the vertex colour
// (COLOR_0, white where none) as four unorm16, linear RGBA.
struct VertexExtra {
    second_uv: vec2<f32>,
    color: vec2<u32>,
}

fn vertex_color(e: VertexExtra) -> vec4<f32> {
    return vec4<f32>(unpack2x16unorm(e.color.x), unpack2x16unorm(e.color.y));
}

// The extras of a vertex that has none stored (a procedural mesh's
// corner): its first UV set as the second, white, as the arena's defaults.
fn default_extra(v: Vertex) -> VertexExtra {
    return VertexExtra(vec2<f32>(v.position_u.w, v.normal_v.w), vec2<u32>(0xffffffffu, 0xffffffffu));
}

// Matches `GpuInstance` in crates/render/src/gbuffer/instances.rs.
struct Instance {
    model: mat4x4<f32>,
    previous_model: mat4x4<f32>,
    // Inverse transpose of the model matrix (upper 3x3 used).
    normal_matrix: mat4x4<f32>,
    color: vec4<f32>,
    // first index, base vertex, material id, object id
    info: vec4<u32>,
}
