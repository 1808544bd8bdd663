// ShadowMap's depth pass on the raster hardware (where the compute
// rasterizer cannot run): the casters from one layer's view, depth only.
// Vertices are pulled from the mesh arena by index and instances are the
// G-buffer's, as the visibility pass reads them; the view comes per layer
// from a slot of a uniform buffer.
#import spreadlight::mesh::{Vertex, Instance}

@group(0) @binding(0) var<uniform> view_projection: mat4x4<f32>;
@group(0) @binding(1) var<storage, read> vertices: array<Vertex>;
@group(0) @binding(2) var<storage, read> indices: array<u32>;
@group(0) @binding(3) var<storage, read> instances: array<Instance>;

@vertex
fn vs(@builtin(vertex_index) vertex: u32, @builtin(instance_index) instance: u32) -> @builtin(position) vec4<f32> {
    let info = instances[instance].info;
    let position = vertices[indices[info.x + vertex] + info.y].position_u.xyz;
    return view_projection * instances[instance].model * vec4<f32>(position, 1.0);
}
