// Tonemap: HDR radiance to display-referred linear 0..1 with exposure and
// one of Emeshe's operators (plus ACES and AgX). Non-finite input never
// passes: it is treated as black.
//
// EYE_ADAPTATION: exposure = Exposure * key / adapted luminance, the adapted
// luminance read from a 1x1 texture (EyeAdaptation's output); one that is
// not positive and finite leaves the exposure fixed.
#import spreadlight::tonemap::{tonemap, MIN_LUMINANCE}

struct Params {
    op: u32,
    exposure: f32,
    // the operator's parameter (white point, max luminance), where it has one
    param: f32,
    // the middle grey the adapted luminance maps to (EYE_ADAPTATION)
    key: f32,
}

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var source: texture_2d<f32>;
@group(0) @binding(2) var output: texture_storage_2d<rgba16float, write>;
#ifdef EYE_ADAPTATION
@group(0) @binding(3) var adaptation: texture_2d<f32>;
#endif

fn exposure() -> f32 {
#ifdef EYE_ADAPTATION
    let adapted = textureLoad(adaptation, vec2<u32>(0u), 0).r;
    if (adapted > 0.0 && adapted <= 3.0e38) {
        // Capped so 0 * exposure stays 0 (never 0 * infinity).
        return min(params.exposure * params.key / max(adapted, MIN_LUMINANCE), 1.0e30);
    }
#endif
    return params.exposure;
}

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(output);
    if (id.x >= size.x || id.y >= size.y) {
        return;
    }
    var c = textureLoad(source, id.xy, 0).rgb;
    // NaN compares false everywhere: keep only values that are >= 0 and finite.
    c = select(vec3<f32>(0.0), c, c >= vec3<f32>(0.0) & c <= vec3<f32>(3.0e38));
    textureStore(output, id.xy, vec4<f32>(tonemap(c, params.op, exposure(), params.param), 1.0));
}
