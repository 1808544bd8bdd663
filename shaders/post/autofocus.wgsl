// Autofocus: the inverse view depth under a screen point (the mean over a
// 5x5 pixel window, so one noisy pixel does not pull focus), blended over
// time into a persistent 1x1 target by `rate` = 1 - exp(-dt * speed). The
// blend is in inverse distance, as a focus ring turns in diopters: the sky
// is 0 (infinity), never an overflow. A fresh target takes the measurement.
#import spreadlight::camera::Camera
#import spreadlight::post::{inverse_view_depth, sanitize_scalar}

struct Params {
    // xy: the point in UV (0..1, y down), z: blend rate, w: 1 when the target is fresh
    point: vec4<f32>,
}

@group(0) @binding(0) var<uniform> camera: Camera;
@group(0) @binding(1) var<uniform> params: Params;
@group(0) @binding(2) var depth: texture_2d<f32>;
@group(0) @binding(3) var previous: texture_2d<f32>;
@group(0) @binding(4) var output: texture_storage_2d<r32float, write>;

@compute @workgroup_size(1, 1)
fn main() {
    let size = vec2<i32>(textureDimensions(depth));
    let center = vec2<i32>(clamp(params.point.xy, vec2<f32>(0.0), vec2<f32>(1.0)) * vec2<f32>(size));
    var sum = 0.0;
    for (var y = -2; y <= 2; y++) {
        for (var x = -2; x <= 2; x++) {
            let p = clamp(center + vec2<i32>(x, y), vec2<i32>(0), size - 1);
            sum += inverse_view_depth(camera.projection_inverse, textureLoad(depth, p, 0).r);
        }
    }
    let measured = sum / 25.0;
    let last = sanitize_scalar(textureLoad(previous, vec2<i32>(0), 0).r);
    var value = mix(max(last, 0.0), measured, clamp(params.point.z, 0.0, 1.0));
    if (params.point.w > 0.5) {
        value = measured;
    }
    textureStore(output, vec2<i32>(0), vec4<f32>(value, 0.0, 0.0, 0.0));
}
