// VSM: one shadow-map layer's depth as the first two moments of linear
// depth (normalized to the layer's near..far), box-filtered over
// (2 blur + 1)^2 texels. Filtering the moments is what softens VSM edges.
// Only `Info.region` of the layer: all of it, or where a scrolled cascade's
// new strips (and its borders, where the filter clamps) change them.
#import spreadlight::shadow_sampling::{ShadowView, linear_depth}

struct Info {
    // x: layer, y: blur radius in texels
    layer_blur: vec4<u32>,
    // The texels written: origin (x, y) and size (z, w)
    region: vec4<u32>,
}

@group(0) @binding(0) var depth: texture_2d_array<f32>;
@group(0) @binding(1) var<storage, read> views: array<ShadowView>;
@group(0) @binding(2) var<uniform> info: Info;
@group(0) @binding(3) var moments: texture_storage_2d<rg32float, write>;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) global: vec3<u32>) {
    let size = textureDimensions(depth);
    let id = info.region.xy + global.xy;
    if (global.x >= info.region.z || global.y >= info.region.w || id.x >= size.x || id.y >= size.y) {
        return;
    }
    let layer = info.layer_blur.x;
    textureStore(moments, id.xy, vec4<f32>(filtered(id, layer, i32(info.layer_blur.y)), 0.0, 0.0));
}

// The blurred moments of linear depth at texel `id` of `layer`.
fn filtered(id: vec2<u32>, layer: u32, blur: i32) -> vec2<f32> {
    let size = textureDimensions(depth);
    let view = views[layer];
    let range = max(view.depth.y - view.depth.x, 1e-12);
    var m = vec2<f32>(0.0);
    var n = 0.0;
    for (var y = -blur; y <= blur; y++) {
        for (var x = -blur; x <= blur; x++) {
            let texel = clamp(vec2<i32>(id.xy) + vec2<i32>(x, y), vec2<i32>(0), vec2<i32>(size) - 1);
            let d = textureLoad(depth, texel, i32(layer), 0).r;
            let t = clamp((linear_depth(view, d) - view.depth.x) / range, 0.0, 1.0);
            m += vec2<f32>(t, t * t);
            n += 1.0;
        }
    }
    return m / n;
}
