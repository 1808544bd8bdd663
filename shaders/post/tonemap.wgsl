// Tonemap: HDR radiance to display-referred linear 0..1 with exposure and
// one of Emeshe's operators (plus ACES and AgX). Non-finite input never
// passes: it is treated as black.
#import spreadlight::tonemap::tonemap

struct Params {
    op: u32,
    exposure: f32,
    // the operator's parameter (white point, max luminance), where it has one
    param: f32,
    _pad: f32,
}

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var source: texture_2d<f32>;
@group(0) @binding(2) var output: texture_storage_2d<rgba16float, write>;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(output);
    if (id.x >= size.x || id.y >= size.y) {
        return;
    }
    var c = textureLoad(source, id.xy, 0).rgb;
    // NaN compares false everywhere: keep only values that are >= 0 and finite.
    c = select(vec3<f32>(0.0), c, c >= vec3<f32>(0.0) & c <= vec3<f32>(3.0e38));
    textureStore(output, id.xy, vec4<f32>(tonemap(c, params.op, params.exposure, params.param), 1.0));
}
