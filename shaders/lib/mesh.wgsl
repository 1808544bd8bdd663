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
