// Temporal anti-aliasing: each frame is rendered with a sub-pixel jittered
// projection; this pass blends it into a history reprojected along the
// G-buffer's velocity (of the nearest of the 3x3 pixels, so moving edges
// carry their own motion). The velocity holds this and last frame's jitter
// difference too (both projections were jittered): it is taken out, so a
// still scene reads its history at the same place and converges to the
// average over the jitter pattern, the supersampled image.
//
// The history is trusted only as far as the current 3x3 neighbourhood
// allows, in YCoCg: clamped to its min/max box, or with VARIANCE_CLIP
// clipped towards the mean into mean +- 1.5 standard deviations (Salvi 2016),
// which rejects stale colours (disocclusion, lighting change) with less
// flicker. With CATMULL_ROM the history is read bicubically, which keeps it
// sharp under motion. History is sanitized on read: NaN or infinity there
// (or a pixel reprojected from off screen, or a fresh target) is replaced by
// the current colour, so it never spreads.
#import spreadlight::post::{sanitize, load_clamped}

struct Params {
    // xy: jitter difference in UV (this frame's minus last frame's), z: history weight, w: sharpen
    jitter_feedback: vec4<f32>,
    // x: 1 when the history is fresh (first frame, cut, resize)
    flags: vec4<f32>,
}

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var source: texture_2d<f32>;
@group(0) @binding(2) var velocity_uv: texture_2d<f32>;
@group(0) @binding(3) var depth: texture_2d<f32>;
@group(0) @binding(4) var history: texture_2d<f32>;
@group(0) @binding(5) var output: texture_storage_2d<rgba16float, write>;
// The history is this pass's own Rgba16Float: filterable, so read through
// the bilinear sampler, one fetch a tap.
@group(0) @binding(6) var linear: sampler;

fn to_ycocg(c: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(
        0.25 * c.r + 0.5 * c.g + 0.25 * c.b,
        0.5 * c.r - 0.5 * c.b,
        -0.25 * c.r + 0.5 * c.g - 0.25 * c.b,
    );
}

fn from_ycocg(c: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(c.x + c.y - c.z, c.x + c.z, c.x - c.y - c.z);
}

// Bright pixels weigh less in the blend (Karis 2014), so one firefly does not ghost.
fn tonemap_weight(c: vec3<f32>) -> f32 {
    return 1.0 / (1.0 + max(c.x, 0.0));
}

fn history_at(uv: vec2<f32>) -> vec4<f32> {
#ifdef CATMULL_ROM
    // The 4x4 Catmull-Rom filter in 9 bilinear fetches (Jimenez 2016, as
    // MJP's "Bicubic Catmull-Rom in 9 taps"): per axis, the middle two taps
    // have weights of one sign, so one bilinear fetch between them at
    // w2 / (w1 + w2) weighs both; the outer two are fetched on their texels.
    let size = vec2<f32>(textureDimensions(history));
    let p = uv * size - 0.5;
    let base = floor(p);
    let f = p - base;
    // Catmull-Rom weights per axis for taps at -1, 0, 1, 2.
    let w0 = f * (-0.5 + f * (1.0 - 0.5 * f));
    let w1 = 1.0 + f * f * (-2.5 + 1.5 * f);
    let w2 = f * (0.5 + f * (2.0 - 1.5 * f));
    let w3 = f * f * (-0.5 + 0.5 * f);
    let w12 = w1 + w2;
    // Texel centres in UV: the first tap, the middle pair's blend, the last.
    let t0 = (base - 0.5) / size;
    let t12 = (base + 0.5 + w2 / w12) / size;
    let t3 = (base + 2.5) / size;
    var wx = array<f32, 3>(w0.x, w12.x, w3.x);
    var wy = array<f32, 3>(w0.y, w12.y, w3.y);
    var ux = array<f32, 3>(t0.x, t12.x, t3.x);
    var uy = array<f32, 3>(t0.y, t12.y, t3.y);
    var sum = vec4<f32>(0.0);
    for (var y = 0; y < 3; y++) {
        for (var x = 0; x < 3; x++) {
            let tap = textureSampleLevel(history, linear, vec2<f32>(ux[x], uy[y]), 0.0);
            sum += tap * wx[x] * wy[y];
        }
    }
    return sum;
#else
    return textureSampleLevel(history, linear, uv, 0.0);
#endif
}

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(output);
    if (id.x >= size.x || id.y >= size.y) {
        return;
    }
    let p = vec2<i32>(id.xy);
    let current = sanitize(load_clamped(source, p));
    let c = to_ycocg(max(current.rgb, vec3<f32>(0.0)));
    var lo = c;
    var hi = c;
    var m1 = vec3<f32>(0.0);
    var m2 = vec3<f32>(0.0);
    var cross = vec3<f32>(0.0);
    var nearest = -1.0;
    var nearest_pixel = p;
    for (var y = -1; y <= 1; y++) {
        for (var x = -1; x <= 1; x++) {
            let q = p + vec2<i32>(x, y);
            let n = to_ycocg(max(sanitize(load_clamped(source, q)).rgb, vec3<f32>(0.0)));
            lo = min(lo, n);
            hi = max(hi, n);
            m1 += n;
            m2 += n * n;
            if (abs(x) + abs(y) == 1) {
                cross += n;
            }
            // Reversed-Z: the largest depth is the nearest surface.
            let d = load_clamped(depth, q).r;
            if (d > nearest) {
                nearest = d;
                nearest_pixel = q;
            }
        }
    }
    let velocity = sanitize(load_clamped(velocity_uv, nearest_pixel)).xy - params.jitter_feedback.xy;
    let uv = (vec2<f32>(p) + 0.5) / vec2<f32>(size);
    let previous_uv = uv - velocity;
    var result = c;
    let on_screen = all(previous_uv >= vec2<f32>(0.0)) && all(previous_uv <= vec2<f32>(1.0));
    if (params.flags.x < 0.5 && on_screen) {
        let raw = history_at(previous_uv);
        // Sanitize on read: a NaN or infinity in history is the current colour instead.
        let finite = all(raw == raw) && all(abs(raw) < vec4<f32>(65504.0));
        var h = c;
        if (finite) {
            h = to_ycocg(max(raw.rgb, vec3<f32>(0.0)));
        }
#ifdef VARIANCE_CLIP
        let mean = m1 / 9.0;
        let sigma = sqrt(max(m2 / 9.0 - mean * mean, vec3<f32>(0.0)));
        let box_lo = max(mean - 1.5 * sigma, lo);
        let box_hi = min(mean + 1.5 * sigma, hi);
        // Clip along the line to the mean (not per channel), keeping hue.
        let center = 0.5 * (box_hi + box_lo);
        let extent = 0.5 * (box_hi - box_lo) + 1e-5;
        let offset = h - center;
        let units = abs(offset / extent);
        let reach = max(units.x, max(units.y, units.z));
        if (reach > 1.0) {
            h = center + offset / reach;
        }
#else
        h = clamp(h, lo, hi);
#endif
        let feedback = clamp(params.jitter_feedback.z, 0.0, 1.0);
        let wc = (1.0 - feedback) * tonemap_weight(c);
        let wh = feedback * tonemap_weight(h);
        result = (c * wc + h * wh) / max(wc + wh, 1e-6);
    }
    // Sharpen: the current frame's detail (centre less its cross) added back.
    result += params.jitter_feedback.w * (c - cross * 0.25);
    let rgb = clamp(from_ycocg(result), vec3<f32>(0.0), vec3<f32>(65000.0));
    textureStore(output, id.xy, vec4<f32>(rgb, current.a));
}
