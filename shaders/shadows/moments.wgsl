// VSM: one shadow-map layer's depth as the first two moments of linear
// depth (normalized to the layer's near..far), box-filtered over
// (2 blur + 1)^2 texels. Filtering the moments is what softens VSM edges.
// Only `Info.region` of the layer: all of it, or where a scrolled cascade's
// new strips (and its borders, where the filter clamps) change them.
// main_layers: every region of a frame in one dispatch (the regions of
// `Region`, their workgroups one after another; SPREADLIGHT_SHADOW_LAYERS=
// together), each texel computed as `main` computes it.
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

// One region of main_layers: its layer and blur, its first workgroup and
// its width in workgroups, and its texels (origin, size).
struct Region {
    layer: u32,
    blur: u32,
    first_group: u32,
    groups_across: u32,
    region: vec4<u32>,
}

@group(0) @binding(4) var<storage, read> regions: array<Region>;
@group(0) @binding(5) var moments_layers: texture_storage_2d_array<rg32float, write>;

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

@compute @workgroup_size(8, 8)
fn main_layers(@builtin(workgroup_id) wid: vec3<u32>, @builtin(local_invocation_id) lid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    // Over 65,535 workgroups spill into y; folded back into one index.
    let group = wid.x + wid.y * groups.x;
    let count = arrayLength(&regions);
    var r = 0u;
    for (var k = 1u; k < count; k++) {
        if (regions[k].first_group <= group) {
            r = k;
        }
    }
    let region = regions[r];
    let local = group - region.first_group;
    let at = vec2<u32>(local % region.groups_across, local / region.groups_across) * 8u + lid.xy;
    let size = textureDimensions(depth);
    let id = region.region.xy + at;
    if (at.x >= region.region.z || at.y >= region.region.w || id.x >= size.x || id.y >= size.y) {
        return;
    }
    textureStore(moments_layers, id, region.layer, vec4<f32>(filtered(id, region.layer, i32(region.blur)), 0.0, 0.0));
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
