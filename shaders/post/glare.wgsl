// Glare: bloom through a mip-like chain, with chromatic aberration.
//   `bright`:    the source at half size (2x2 box), less the threshold (by
//                luminance, keeping hue): what glows;
//   `down`:      each level half the last, a 4x4 box (four bilinear taps);
//                `bright_down` and `down2` make two levels a dispatch (the
//                small levels barely fill the GPU; each dispatch costs a
//                barrier), rounding the middle level as storing it would;
//   `up`:        from the smallest level back up, each level plus `spread`
//                times the tent-filtered level below: wide, soft halos from
//                the small levels, tight ones from the large;
//   `composite`: source + intensity * bloom (normalized by the chain's
//                total weight), red and blue pushed radially apart by
//                `aberration` (a fraction of the distance to the centre).
// Every level is clamped below half-float overflow, so 1e6 in is 65000 at
// worst, never infinity, however many levels add up.
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
// bright_down and down2: the level between `source` and `output`, written too.
@group(0) @binding(4) var middle: texture_storage_2d<rgba16float, write>;

fn clamp_half(c: vec3<f32>) -> vec4<f32> {
    return vec4<f32>(clamp(c, vec3<f32>(0.0), vec3<f32>(HALF_MAX)), 1.0);
}

// What an rgba16float texel holds of `c`: a level made and read in one
// dispatch is rounded as if it had been stored and loaded, so the fused
// chain gives the image of the chain a pass a level.
fn stored(c: vec4<f32>) -> vec4<f32> {
    return vec4<f32>(to_half(c.x), to_half(c.y), to_half(c.z), to_half(c.w));
}

// `x` rounded to the nearest half float (ties to even), kept in an f32: the
// levels hold 0..65000 (clamp_half), so neither overflow nor NaN arrives.
// (pack2x16float would say it in one call, but needs a capability the
// shader cache does not grant.)
fn to_half(x: f32) -> f32 {
    if (abs(x) < 6.103515625e-5) {
        // Subnormal halves: steps of 2^-24.
        return round(x * 16777216.0) / 16777216.0;
    }
    let b = bitcast<u32>(x);
    return bitcast<f32>((b + 0xfffu + ((b >> 13u) & 1u)) & 0xffffe000u);
}

// Texel `p` of the bright level (half size): the source's 2x2 box less the
// threshold.
fn bright_at(p: vec2<i32>) -> vec4<f32> {
    var c = vec3<f32>(0.0);
    for (var y = 0; y < 2; y++) {
        for (var x = 0; x < 2; x++) {
            c += max(sanitize(load_clamped(source, p * 2 + vec2<i32>(x, y))).rgb, vec3<f32>(0.0));
        }
    }
    c *= 0.25;
    let l = luminance(c);
    let keep = max(l - params.settings.x, 0.0) / max(l, 1e-6);
    return clamp_half(c * min(keep, 1.0));
}

// Texel `p` of a level `size` texels big, down from `source` (`below` big).
fn down_at(p: vec2<i32>, size: vec2<u32>, below: vec2<u32>) -> vec4<f32> {
    let texel = 1.0 / vec2<f32>(below);
    let uv = (vec2<f32>(p) + 0.5) / vec2<f32>(size);
    var c = vec3<f32>(0.0);
    c += bilinear(source, uv + vec2<f32>(-1.0, -1.0) * texel).rgb;
    c += bilinear(source, uv + vec2<f32>(1.0, -1.0) * texel).rgb;
    c += bilinear(source, uv + vec2<f32>(-1.0, 1.0) * texel).rgb;
    c += bilinear(source, uv + vec2<f32>(1.0, 1.0) * texel).rgb;
    return clamp_half(c * 0.25);
}

@compute @workgroup_size(8, 8)
fn bright(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(output);
    if (id.x >= size.x || id.y >= size.y) {
        return;
    }
    textureStore(output, id.xy, bright_at(vec2<i32>(id.xy)));
}

@compute @workgroup_size(8, 8)
fn down(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(output);
    if (id.x >= size.x || id.y >= size.y) {
        return;
    }
    textureStore(output, id.xy, down_at(vec2<i32>(id.xy), size, textureDimensions(source)));
}

// The texels of a level `big` wide that texel `k` of the next (`small`
// wide) writes in a two-level pass: its two, and at the last texel the rest.
fn owned(k: u32, small: u32, big: u32) -> vec2<u32> {
    var hi = min(k * 2u + 1u, big - 1u);
    if (k + 1u == small) {
        hi = big - 1u;
    }
    return vec2<u32>(min(k * 2u, big - 1u), hi);
}

// `bilinear` over the middle level as the next pass would read it, with
// each middle texel made here by `make_middle` (0: bright_at, 1: down_at).
fn middle_bilinear(uv: vec2<f32>, mid: vec2<u32>, below: vec2<u32>, make_middle: u32) -> vec4<f32> {
    let p = uv * vec2<f32>(mid) - 0.5;
    let base = floor(p);
    let f = p - base;
    let i = vec2<i32>(base);
    let hi = vec2<i32>(mid) - 1;
    var t: array<vec4<f32>, 4>;
    for (var k = 0; k < 4; k++) {
        let q = clamp(i + vec2<i32>(k % 2, k / 2), vec2<i32>(0), hi);
        if (make_middle == 0u) {
            t[k] = stored(bright_at(q));
        } else {
            t[k] = stored(down_at(q, mid, below));
        }
    }
    return mix(mix(t[0], t[1], f.x), mix(t[2], t[3], f.x), f.y);
}

// Two levels in one dispatch: the middle one (bright from the source with
// `make_middle` 0, a down of `source` with 1) and the next down of it, a
// thread per texel of the second. Each writes the middle texels it owns
// and makes again the few more its taps read (the levels are small).
fn two_levels(id: vec2<u32>, make_middle: u32) {
    let size = textureDimensions(output);
    if (id.x >= size.x || id.y >= size.y) {
        return;
    }
    let mid = textureDimensions(middle);
    let below = textureDimensions(source);
    let ox = owned(id.x, size.x, mid.x);
    let oy = owned(id.y, size.y, mid.y);
    for (var y = oy.x; y <= oy.y; y++) {
        for (var x = ox.x; x <= ox.y; x++) {
            let q = vec2<i32>(vec2<u32>(x, y));
            if (make_middle == 0u) {
                textureStore(middle, q, bright_at(q));
            } else {
                textureStore(middle, q, down_at(q, mid, below));
            }
        }
    }
    let texel = 1.0 / vec2<f32>(mid);
    let uv = (vec2<f32>(id) + 0.5) / vec2<f32>(size);
    var c = vec3<f32>(0.0);
    c += middle_bilinear(uv + vec2<f32>(-1.0, -1.0) * texel, mid, below, make_middle).rgb;
    c += middle_bilinear(uv + vec2<f32>(1.0, -1.0) * texel, mid, below, make_middle).rgb;
    c += middle_bilinear(uv + vec2<f32>(-1.0, 1.0) * texel, mid, below, make_middle).rgb;
    c += middle_bilinear(uv + vec2<f32>(1.0, 1.0) * texel, mid, below, make_middle).rgb;
    textureStore(output, id, clamp_half(c * 0.25));
}

// The bright level and the first down of it.
@compute @workgroup_size(8, 8)
fn bright_down(@builtin(global_invocation_id) id: vec3<u32>) {
    two_levels(id.xy, 0u);
}

// Two downs.
@compute @workgroup_size(8, 8)
fn down2(@builtin(global_invocation_id) id: vec3<u32>) {
    two_levels(id.xy, 1u);
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
    var c = bilinear(lower, uv).rgb * 4.0;
    c += (bilinear(lower, uv + vec2<f32>(-texel.x, 0.0)).rgb + bilinear(lower, uv + vec2<f32>(texel.x, 0.0)).rgb
        + bilinear(lower, uv + vec2<f32>(0.0, -texel.y)).rgb + bilinear(lower, uv + vec2<f32>(0.0, texel.y)).rgb) * 2.0;
    c += bilinear(lower, uv - texel).rgb + bilinear(lower, uv + texel).rgb
        + bilinear(lower, uv + vec2<f32>(texel.x, -texel.y)).rgb + bilinear(lower, uv + vec2<f32>(-texel.x, texel.y)).rgb;
    let here = textureLoad(source, vec2<i32>(id.xy), 0).rgb;
    textureStore(output, id.xy, clamp_half(here + params.settings.z * c / 16.0));
}

// `t` sampled with red and blue moved radially by the aberration.
fn aberrated(t: texture_2d<f32>, uv: vec2<f32>) -> vec3<f32> {
    let a = params.settings.w;
    if (a == 0.0) {
        return bilinear(t, uv).rgb;
    }
    let from_center = uv - 0.5;
    let r = bilinear(t, 0.5 + from_center * (1.0 + a)).r;
    let g = bilinear(t, uv).g;
    let b = bilinear(t, 0.5 + from_center * (1.0 - a)).b;
    return vec3<f32>(r, g, b);
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
        base = sanitize(vec4<f32>(aberrated(source, uv), 0.0)).rgb;
    }
    let glow = aberrated(lower, uv) * params.norm.x;
    let c = base + params.settings.y * glow;
    textureStore(output, id.xy, vec4<f32>(clamp(c, vec3<f32>(0.0), vec3<f32>(HALF_MAX)), center.a));
}
