// A separable Gaussian blur at half resolution: a horizontal pass into a
// half-size temporary target, then a vertical pass back to full size.
// @category Filter
// @help Separable Gaussian blur: a horizontal pass into a half-size temporary, a vertical pass back to full size.
// @input source "Texture"
// @sampler smp clamp
// @target half temporary rgba16float scale=0.5
// @output half
// @target blurred temporary rgba16float scale=1
// @pass horizontal -> half
// @pass vertical -> blurred

struct Params {
    // @pin "Radius" default=4 min=0 max=32
    radius: f32,
    size: vec2<f32>,
    texel: vec2<f32>,
}

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var source: texture_2d<f32>;
@group(0) @binding(2) var smp: sampler;
@group(0) @binding(3) var half: texture_2d<f32>;
@group(0) @binding(4) var half_out: texture_storage_2d<rgba16float, write>;
@group(0) @binding(5) var blurred: texture_storage_2d<rgba16float, write>;

const TAPS: i32 = 8;

// Gaussian weights over -TAPS..TAPS with sigma = radius / 2, in pixels of
// the destination, normalised.
fn blur(tex: texture_2d<f32>, uv: vec2<f32>, step: vec2<f32>) -> vec4<f32> {
    let sigma = max(params.radius * 0.5, 1e-3);
    var sum = vec4<f32>(0.0);
    var weight = 0.0;
    for (var i = -TAPS; i <= TAPS; i++) {
        let x = f32(i) * params.radius / f32(TAPS);
        let w = exp(-0.5 * x * x / (sigma * sigma));
        sum += w * textureSampleLevel(tex, smp, uv + step * x, 0.0);
        weight += w;
    }
    return sum / weight;
}

@compute @workgroup_size(8, 8)
fn horizontal(@builtin(global_invocation_id) id: vec3<u32>) {
    if (f32(id.x) >= params.size.x || f32(id.y) >= params.size.y) {
        return;
    }
    let uv = (vec2<f32>(id.xy) + 0.5) * params.texel;
    // Half resolution: a destination pixel spans two of the source's.
    textureStore(half_out, id.xy, blur(source, uv, vec2<f32>(params.texel.x * 0.5, 0.0)));
}

@compute @workgroup_size(8, 8)
fn vertical(@builtin(global_invocation_id) id: vec3<u32>) {
    if (f32(id.x) >= params.size.x || f32(id.y) >= params.size.y) {
        return;
    }
    let uv = (vec2<f32>(id.xy) + 0.5) * params.texel;
    textureStore(blurred, id.xy, blur(half, uv, vec2<f32>(0.0, params.texel.y)));
}
