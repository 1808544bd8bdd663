// Eye adaptation, as breezEngine's tonemapping effect does it: the average
// log-luminance of the HDR image, reduced to 1x1 by repeated halving, then
// blended over time into a persistent 1x1 target of the adapted luminance.
//
// The reduction targets are RG32Float: R holds the mean log-luminance of the
// pixels a texel covers, G how many valid pixels that is. Each step takes the
// weighted mean, so odd sizes and left-out pixels do not bias the result.
// Non-finite pixels (NaN, infinity) are left out; negative channels count as
// 0; pixels darker than the Minimum pin count as the minimum (so a black
// background does not over-expose the rest, and log of 0 never happens). A
// frame with no valid pixel measures the minimum.
#import spreadlight::tonemap::{luminance, MIN_LUMINANCE}

struct Params {
    // 1 - exp(-dt * speed) for a rising and a falling luminance, in 0..1
    rate_up: f32,
    rate_down: f32,
    // the pins: the adapted luminance stays in min..max (both > 0, finite)
    min_luminance: f32,
    max_luminance: f32,
    // 1 when the persistent target holds no history (first frame, cut): take the measurement
    fresh: u32,
    _pad0: u32,
    _pad1: u32,
    _pad2: u32,
}

@group(0) @binding(0) var<uniform> params: Params;
// log_luminance: the HDR image; downsample: the previous level
@group(0) @binding(1) var input: texture_2d<f32>;
@group(0) @binding(2) var reduced: texture_storage_2d<rg32float, write>;
// adapt: the 1x1 measurement, last frame's adapted luminance (a copy), the persistent target
@group(0) @binding(3) var measured: texture_2d<f32>;
@group(0) @binding(4) var previous: texture_2d<f32>;
@group(0) @binding(5) var adapted: texture_storage_2d<r32float, write>;

const FLOAT_MAX: f32 = 3.0e38;

fn weighted(sum: f32, count: f32) -> vec4<f32> {
    return vec4<f32>(select(0.0, sum / count, count > 0.0), count, 0.0, 1.0);
}

// Level 0: each texel covers a block of the image (the blocks partition it,
// whatever the two sizes are) and stores the block's mean log-luminance.
@compute @workgroup_size(8, 8)
fn log_luminance(@builtin(global_invocation_id) id: vec3<u32>) {
    let dst = textureDimensions(reduced);
    if (id.x >= dst.x || id.y >= dst.y) {
        return;
    }
    let src = textureDimensions(input);
    let begin = id.xy * src / dst;
    let end = (id.xy + vec2<u32>(1u)) * src / dst;
    var sum = 0.0;
    var count = 0.0;
    for (var y = begin.y; y < end.y; y++) {
        for (var x = begin.x; x < end.x; x++) {
            let c = textureLoad(input, vec2<u32>(x, y), 0).rgb;
            // NaN compares false everywhere: only finite pixels pass.
            if (all(c >= vec3<f32>(-FLOAT_MAX) & c <= vec3<f32>(FLOAT_MAX))) {
                let l = luminance(max(c, vec3<f32>(0.0)));
                // Darker than the eye adapts to counts as the minimum: a black
                // background must not drag the average into over-exposure.
                sum += log(clamp(l, max(params.min_luminance, MIN_LUMINANCE), FLOAT_MAX));
                count += 1.0;
            }
        }
    }
    textureStore(reduced, id.xy, weighted(sum, count));
}

// Level n + 1 (half the size, rounded up): the weighted mean of a 2x2 block of level n.
@compute @workgroup_size(8, 8)
fn downsample(@builtin(global_invocation_id) id: vec3<u32>) {
    let dst = textureDimensions(reduced);
    if (id.x >= dst.x || id.y >= dst.y) {
        return;
    }
    let src = textureDimensions(input);
    var sum = 0.0;
    var count = 0.0;
    for (var dy = 0u; dy < 2u; dy++) {
        for (var dx = 0u; dx < 2u; dx++) {
            let p = id.xy * 2u + vec2<u32>(dx, dy);
            if (p.x < src.x && p.y < src.y) {
                let v = textureLoad(input, p, 0).rg;
                sum += v.r * v.g;
                count += v.g;
            }
        }
    }
    textureStore(reduced, id.xy, weighted(sum, count));
}

// The 1x1 measurement blended into last frame's value, in log space (so a
// speed is the same in stops whichever the level), separately up and down.
@compute @workgroup_size(1)
fn adapt() {
    let lo = log(params.min_luminance);
    let hi = log(params.max_luminance);
    let m = textureLoad(measured, vec2<u32>(0u), 0).rg;
    // No valid pixel (or a broken measurement): the minimum.
    let valid = m.g > 0.0 && m.r >= -FLOAT_MAX && m.r <= FLOAT_MAX;
    let target_log = clamp(select(lo, m.r, valid), lo, hi);
    var result = target_log;
    let last = textureLoad(previous, vec2<u32>(0u), 0).r;
    // History is only what this pass wrote (in min..max); anything else restarts.
    if (params.fresh == 0u && last > 0.0 && last <= FLOAT_MAX) {
        let last_log = clamp(log(last), lo, hi);
        let rate = select(params.rate_down, params.rate_up, target_log > last_log);
        result = last_log + (target_log - last_log) * clamp(rate, 0.0, 1.0);
    }
    let l = clamp(exp(result), params.min_luminance, params.max_luminance);
    textureStore(adapted, vec2<u32>(0u), vec4<f32>(l, 0.0, 0.0, 1.0));
}
