// Sobel edge detection on luminance, tinted; Bypass skips the pass (the input
// passes through) and the INVERT switch compiles a second permutation.
// @category Filter
// @help Sobel edges of the image's luminance, times Strength, in Tint. Bypass passes the image on; Invert draws dark edges on white.
// @input source "Texture"
// @switch INVERT "Invert"
// @target edges temporary rgba16float scale=1
// @pass sobel -> edges skip=Bypass

struct Params {
    strength: f32, // @pin default=1 min=0 max=10
    threshold: f32, // @pin default=0 min=0 max=1
    // @pin color default=1,1,1,1
    tint: vec4<f32>,
    bypass: u32, // @pin bool default=0
    size: vec2<f32>,
}

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var source: texture_2d<f32>;
@group(0) @binding(2) var edges: texture_storage_2d<rgba16float, write>;

fn luma(p: vec2<i32>) -> f32 {
    let s = vec2<i32>(textureDimensions(source)) - 1;
    let c = textureLoad(source, clamp(p, vec2<i32>(0), s), 0).rgb;
    return dot(max(c, vec3<f32>(0.0)), vec3<f32>(0.2126, 0.7152, 0.0722));
}

@compute @workgroup_size(8, 8)
fn sobel(@builtin(global_invocation_id) id: vec3<u32>) {
    if (f32(id.x) >= params.size.x || f32(id.y) >= params.size.y) {
        return;
    }
    let p = vec2<i32>(id.xy);
    let gx = luma(p + vec2(1, -1)) + 2.0 * luma(p + vec2(1, 0)) + luma(p + vec2(1, 1))
        - luma(p + vec2(-1, -1)) - 2.0 * luma(p + vec2(-1, 0)) - luma(p + vec2(-1, 1));
    let gy = luma(p + vec2(-1, 1)) + 2.0 * luma(p + vec2(0, 1)) + luma(p + vec2(1, 1))
        - luma(p + vec2(-1, -1)) - 2.0 * luma(p + vec2(0, -1)) - luma(p + vec2(1, -1));
    var e = max(sqrt(gx * gx + gy * gy) * params.strength - params.threshold, 0.0);
    e = min(e, 1.0);
#ifdef INVERT
    e = 1.0 - e;
#endif
    textureStore(edges, id.xy, vec4<f32>(params.tint.rgb * e, 1.0));
}
