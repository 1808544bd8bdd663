// Fog: distance and height fog over the lit image (spreadlight::fog).
#import spreadlight::camera::Camera
#import spreadlight::fog::{Fog, fogged}

@group(0) @binding(0) var<uniform> camera: Camera;
@group(0) @binding(1) var<uniform> fog: Fog;
@group(0) @binding(2) var source: texture_2d<f32>;
@group(0) @binding(3) var depth: texture_2d<f32>;
@group(0) @binding(4) var output: texture_storage_2d<rgba16float, write>;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = vec2<u32>(camera.size.xy);
    if (id.x >= size.x || id.y >= size.y) {
        return;
    }
    let pixel = id.xy;
    let lit = textureLoad(source, pixel, 0);
    textureStore(output, pixel, fogged(camera, fog, lit, pixel, textureLoad(depth, pixel, 0).r));
}
