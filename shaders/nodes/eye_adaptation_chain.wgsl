// breezEngine's eye adaptation written as a shader node: the log-luminance
// of the image at half size, halved again and again (a repeated pass) until
// 1x1, then blended over time into a persistent 1x1 target. The same maths
// as the built-in EyeAdaptation (shaders/post/eye_adaptation.wgsl), so the
// two agree; a test checks it.
// @category Filter
// @help Adapted scene luminance (1x1, linear) by repeated log-luminance halving and a persistent blend over time: Speed Up / Speed Down per second, held in Minimum..Maximum.
// @input source "Texture"
// @target lum temporary rg32float scale=0.5
// @target adapted persistent r32float size=1x1
// @pass log_luminance -> lum
// @pass downsample -> lum repeat=until:1x1 step=0.5
// @pass adapt -> adapted

struct Params {
    speed_up: f32, // @pin "Speed Up" default=3 min=0
    speed_down: f32, // @pin "Speed Down" default=1 min=0
    min_luminance: f32, // @pin "Minimum" default=0.01 min=0.000001 max=1000000000
    max_luminance: f32, // @pin "Maximum" default=1000 min=0.000001 max=1000000000
    delta: f32,
    fresh: u32,
}

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var source: texture_2d<f32>;
@group(0) @binding(2) var lum: texture_2d<f32>;
@group(0) @binding(3) var lum_out: texture_storage_2d<rg32float, write>;
@group(0) @binding(4) var adapted: texture_2d<f32>;
@group(0) @binding(5) var adapted_out: texture_storage_2d<r32float, write>;

const FLOAT_MAX: f32 = 3.0e38;
const MIN_LUMINANCE: f32 = 1e-6;

fn luminance(c: vec3<f32>) -> f32 {
    return dot(c, vec3<f32>(0.2126, 0.7152, 0.0722));
}

fn weighted(sum: f32, count: f32) -> vec4<f32> {
    return vec4<f32>(select(0.0, sum / count, count > 0.0), count, 0.0, 1.0);
}

@compute @workgroup_size(8, 8)
fn log_luminance(@builtin(global_invocation_id) id: vec3<u32>) {
    let dst = textureDimensions(lum_out);
    if (id.x >= dst.x || id.y >= dst.y) {
        return;
    }
    let src = textureDimensions(source);
    let begin = id.xy * src / dst;
    let end = (id.xy + vec2<u32>(1u)) * src / dst;
    var sum = 0.0;
    var count = 0.0;
    for (var y = begin.y; y < end.y; y++) {
        for (var x = begin.x; x < end.x; x++) {
            let c = textureLoad(source, vec2<u32>(x, y), 0).rgb;
            if (all(c >= vec3<f32>(-FLOAT_MAX) & c <= vec3<f32>(FLOAT_MAX))) {
                let l = luminance(max(c, vec3<f32>(0.0)));
                sum += log(clamp(l, max(params.min_luminance, MIN_LUMINANCE), FLOAT_MAX));
                count += 1.0;
            }
        }
    }
    textureStore(lum_out, id.xy, weighted(sum, count));
}

@compute @workgroup_size(8, 8)
fn downsample(@builtin(global_invocation_id) id: vec3<u32>) {
    let dst = textureDimensions(lum_out);
    if (id.x >= dst.x || id.y >= dst.y) {
        return;
    }
    let src = textureDimensions(lum);
    var sum = 0.0;
    var count = 0.0;
    for (var dy = 0u; dy < 2u; dy++) {
        for (var dx = 0u; dx < 2u; dx++) {
            let p = id.xy * 2u + vec2<u32>(dx, dy);
            if (p.x < src.x && p.y < src.y) {
                let v = textureLoad(lum, p, 0).rg;
                sum += v.r * v.g;
                count += v.g;
            }
        }
    }
    textureStore(lum_out, id.xy, weighted(sum, count));
}

@compute @workgroup_size(1)
fn adapt() {
    let lo = log(params.min_luminance);
    let hi = log(max(params.max_luminance, params.min_luminance));
    let m = textureLoad(lum, vec2<u32>(0u), 0).rg;
    let valid = m.g > 0.0 && m.r >= -FLOAT_MAX && m.r <= FLOAT_MAX;
    let target_log = clamp(select(lo, m.r, valid), lo, hi);
    var result = target_log;
    let last = textureLoad(adapted, vec2<u32>(0u), 0).r;
    if (params.fresh == 0u && last > 0.0 && last <= FLOAT_MAX) {
        let last_log = clamp(log(last), lo, hi);
        let speed = select(params.speed_down, params.speed_up, target_log > last_log);
        let rate = clamp(1.0 - exp(-params.delta * speed), 0.0, 1.0);
        result = last_log + (target_log - last_log) * rate;
    }
    let l = clamp(exp(result), params.min_luminance, max(params.max_luminance, params.min_luminance));
    textureStore(adapted_out, vec2<u32>(0u), vec4<f32>(l, 0.0, 0.0, 1.0));
}
