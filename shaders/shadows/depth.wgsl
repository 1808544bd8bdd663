// ShadowMap's depth pass: the casters from one layer's view, depth only.
// Vertices are pulled from the mesh arena by index, as the G-buffer does;
// the view comes per layer from a slot of a uniform buffer.
#import spreadlight::mesh::Vertex

// Matches `GpuCaster` in crates/render/src/shadows/mod.rs.
struct Caster {
    model: mat4x4<f32>,
    // first index, base vertex
    info: vec4<u32>,
}

@group(0) @binding(0) var<uniform> view_projection: mat4x4<f32>;
@group(0) @binding(1) var<storage, read> vertices: array<Vertex>;
@group(0) @binding(2) var<storage, read> indices: array<u32>;
@group(0) @binding(3) var<storage, read> casters: array<Caster>;

@vertex
fn vs(@builtin(vertex_index) vertex: u32, @builtin(instance_index) instance: u32) -> @builtin(position) vec4<f32> {
    let info = casters[instance].info;
    let position = vertices[indices[info.x + vertex] + info.y].position_u.xyz;
    return view_projection * casters[instance].model * vec4<f32>(position, 1.0);
}
