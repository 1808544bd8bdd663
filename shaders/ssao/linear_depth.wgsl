// SAO's view-depth chain. Level 0: the positive view distance of each
// pixel (0 where depth is empty, the sky). DOWNSAMPLE: each texel of a
// level takes one texel of the level above by McGuire's rotated grid
// (not an average: averaging depths across an edge invents surfaces).
#import spreadlight::camera::Camera
#ifndef DOWNSAMPLE
#import spreadlight::screen::view_position
#endif

@group(0) @binding(0) var<uniform> camera: Camera;
@group(0) @binding(1) var source: texture_2d<f32>;
@group(0) @binding(2) var output: texture_storage_2d<r32float, write>;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(output);
    if (id.x >= size.x || id.y >= size.y) {
        return;
    }
#ifdef DOWNSAMPLE
    let above = textureDimensions(source);
    let p = min(id.xy * 2u + vec2<u32>((id.y & 1u) ^ 1u, (id.x & 1u) ^ 1u), above - 1u);
    let z = textureLoad(source, p, 0).r;
#else
    let d = textureLoad(source, id.xy, 0).r;
    var z = 0.0;
    if (d > 0.0) {
        z = max(-view_position(camera, id.xy, d).z, 0.0);
    }
#endif
    textureStore(output, id.xy, vec4<f32>(z, 0.0, 0.0, 0.0));
}
