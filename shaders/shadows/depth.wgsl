// ShadowMap's depth pass on the raster hardware (where the compute
// rasterizer cannot run): the casters from one layer's view, depth only.
// Vertices are pulled from the mesh arena by index and instances are the
// G-buffer's, as the visibility pass reads them; the view comes per layer
// from a slot of a uniform buffer.
#import spreadlight::mesh_fetch::{instances, triangle_vertex, view_right, view_up}

@group(0) @binding(0) var<uniform> view_projection: mat4x4<f32>;

@vertex
fn vs(@builtin(vertex_index) vertex: u32, @builtin(instance_index) instance: u32) -> @builtin(position) vec4<f32> {
    // Sprites face the light (the view-projection's rows point along its view's axes).
    let position = triangle_vertex(instance, vertex / 3u, vertex % 3u, view_right(view_projection), view_up(view_projection)).position_u.xyz;
    return view_projection * instances[instance].model * vec4<f32>(position, 1.0);
}
