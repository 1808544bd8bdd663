// Glare: bloom through a mip-like chain, with chromatic aberration.
//   `bright`:    the source at half size (2x2 box), less the threshold (by
//                luminance, keeping hue): what glows;
//   `down`:      each level half the last, a 4x4 box (four bilinear taps);
//   `up`:        from the smallest level back up, each level plus `spread`
//                times the tent-filtered level below: wide, soft halos from
//                the small levels, tight ones from the large;
//   `composite`: source + intensity * bloom (normalized by the chain's
//                total weight), red and blue pushed radially apart by
//                `aberration` (a fraction of the distance to the centre).
// Every level is clamped below half-float overflow, so 1e6 in is 65000 at
// worst, never infinity, however many levels add up.
// The chain's own levels (Rgba16Float, filterable) are read through the
// bilinear sampler, one fetch a tap; the source, whose format is the
// input's, too when it is filterable (FILTERED_SOURCE), else by four loads
// (`bilinear`).
#import spreadlight::post::{sanitize, load_clamped, bilinear, luminance, HALF_MAX}

struct Params {
    // x: threshold, y: intensity, z: spread, w: aberration
    settings: vec4<f32>,
    // x: 1 / the sum of the levels' weights
    norm: vec4<f32>,
}

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var source: texture_2d<f32>;
@group(0) @binding(2) var lower: texture_2d<f32>;
@group(0) @binding(3) var output: texture_storage_2d<rgba16float, write>;
@group(0) @binding(4) var linear: sampler;

// A chain level at `uv`, bilinear, held at the edges.
fn level_at(t: texture_2d<f32>, uv: vec2<f32>) -> vec4<f32> {
    return textureSampleLevel(t, linear, uv, 0.0);
}

fn clamp_half(c: vec3<f32>) -> vec4<f32> {
    return vec4<f32>(clamp(c, vec3<f32>(0.0), vec3<f32>(HALF_MAX)), 1.0);
}

@compute @workgroup_size(8, 8)
fn bright(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(output);
    if (id.x >= size.x || id.y >= size.y) {
        return;
    }
    let p = vec2<i32>(id.xy) * 2;
    var c = vec3<f32>(0.0);
    for (var y = 0; y < 2; y++) {
        for (var x = 0; x < 2; x++) {
            c += max(sanitize(load_clamped(source, p + vec2<i32>(x, y))).rgb, vec3<f32>(0.0));
        }
    }
    c *= 0.25;
    let l = luminance(c);
    let keep = max(l - params.settings.x, 0.0) / max(l, 1e-6);
    textureStore(output, id.xy, clamp_half(c * min(keep, 1.0)));
}

@compute @workgroup_size(8, 8)
fn down(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(output);
    if (id.x >= size.x || id.y >= size.y) {
        return;
    }
    let texel = 1.0 / vec2<f32>(textureDimensions(source));
    let uv = (vec2<f32>(id.xy) + 0.5) / vec2<f32>(size);
    var c = vec3<f32>(0.0);
    c += level_at(source, uv + vec2<f32>(-1.0, -1.0) * texel).rgb;
    c += level_at(source, uv + vec2<f32>(1.0, -1.0) * texel).rgb;
    c += level_at(source, uv + vec2<f32>(-1.0, 1.0) * texel).rgb;
    c += level_at(source, uv + vec2<f32>(1.0, 1.0) * texel).rgb;
    textureStore(output, id.xy, clamp_half(c * 0.25));
}

@compute @workgroup_size(8, 8)
fn up(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(output);
    if (id.x >= size.x || id.y >= size.y) {
        return;
    }
    let texel = 1.0 / vec2<f32>(textureDimensions(lower));
    let uv = (vec2<f32>(id.xy) + 0.5) / vec2<f32>(size);
    // A 3x3 tent over the smaller level.
    var c = level_at(lower, uv).rgb * 4.0;
    c += (level_at(lower, uv + vec2<f32>(-texel.x, 0.0)).rgb + level_at(lower, uv + vec2<f32>(texel.x, 0.0)).rgb
        + level_at(lower, uv + vec2<f32>(0.0, -texel.y)).rgb + level_at(lower, uv + vec2<f32>(0.0, texel.y)).rgb) * 2.0;
    c += level_at(lower, uv - texel).rgb + level_at(lower, uv + texel).rgb
        + level_at(lower, uv + vec2<f32>(texel.x, -texel.y)).rgb + level_at(lower, uv + vec2<f32>(-texel.x, texel.y)).rgb;
    let here = textureLoad(source, vec2<i32>(id.xy), 0).rgb;
    textureStore(output, id.xy, clamp_half(here + params.settings.z * c / 16.0));
}

// Where red and blue are read for `uv`: moved radially by the aberration.
fn aberration_uvs(uv: vec2<f32>) -> array<vec2<f32>, 2> {
    let a = params.settings.w;
    let from_center = uv - 0.5;
    return array<vec2<f32>, 2>(0.5 + from_center * (1.0 + a), 0.5 + from_center * (1.0 - a));
}

// The source with red and blue moved by the aberration. Apart from
// `aberrated_glow` on purpose: without FILTERED_SOURCE the source must not
// meet the sampler anywhere in the shader, or the derived bind group layout
// asks for a filterable texture and an Rgba32Float source fails to bind.
fn aberrated_source(uv: vec2<f32>) -> vec3<f32> {
    let at = aberration_uvs(uv);
#ifdef FILTERED_SOURCE
    return vec3<f32>(level_at(source, at[0]).r, level_at(source, uv).g, level_at(source, at[1]).b);
#else
    return vec3<f32>(bilinear(source, at[0]).r, bilinear(source, uv).g, bilinear(source, at[1]).b);
#endif
}

// The glow (the chain's top level) with red and blue moved by the aberration.
fn aberrated_glow(uv: vec2<f32>) -> vec3<f32> {
    if (params.settings.w == 0.0) {
        return level_at(lower, uv).rgb;
    }
    let at = aberration_uvs(uv);
    return vec3<f32>(level_at(lower, at[0]).r, level_at(lower, uv).g, level_at(lower, at[1]).b);
}

@compute @workgroup_size(8, 8)
fn composite(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(output);
    if (id.x >= size.x || id.y >= size.y) {
        return;
    }
    let uv = (vec2<f32>(id.xy) + 0.5) / vec2<f32>(size);
    let center = sanitize(load_clamped(source, vec2<i32>(id.xy)));
    var base = center.rgb;
    if (params.settings.w != 0.0) {
        base = sanitize(vec4<f32>(aberrated_source(uv), 0.0)).rgb;
    }
    let glow = aberrated_glow(uv) * params.norm.x;
    let c = base + params.settings.y * glow;
    textureStore(output, id.xy, vec4<f32>(clamp(c, vec3<f32>(0.0), vec3<f32>(HALF_MAX)), center.a));
}
