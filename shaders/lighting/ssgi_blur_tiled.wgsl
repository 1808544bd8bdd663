// SSGI's depth-aware blur, x and y in one dispatch: the same weights and
// the same order of sums as ssgi.wgsl's two BLUR passes, whose image this
// matches (crates/render/tests/depth_aware_blur.rs), so the x pass's
// full-screen write, the y pass's read of it and the barrier between them
// go away. As ssao/blur_tiled.wgsl: a 16x16 workgroup loads its tile and
// an apron of `blur_radius` texels into workgroup memory once (view
// distance, unit normal, the cleaned source), blurs x over the tile's
// columns in every row of tile and apron, then y over the tile; with
// AMBIENT the ambient is added as the last BLUR pass adds it.
//
// The two passes keep the x result in an RGBA16F target: the x result here
// is rounded to half float the same way before y reads it, so y sees the
// numbers it saw. How a store rounds is the implementation's (Vulkan's
// "Floating-Point Format Conversions"): to nearest, ties to even, on GPUs;
// toward zero on lavapipe (HALF_TOWARD_ZERO, chosen per adapter class by
// render::lighting::ssgi; depth_aware_blur.rs tells). Values are held as
// half-float bits, two to a u32 (exact: every one is a half float, or
// clean()'s 65000, which takes infinity's pattern, never held otherwise),
// so the tile and an apron of MAX_RADIUS fit in 16 KiB.
#import spreadlight::camera::Camera
#import spreadlight::packing::safe_normalize
#import spreadlight::screen::{RayParams, view_position, tap_weight}

@group(0) @binding(0) var<uniform> camera: Camera;
@group(0) @binding(1) var<uniform> params: RayParams;
@group(0) @binding(2) var depth: texture_2d<f32>;
@group(0) @binding(3) var normals: texture_2d<f32>;
@group(0) @binding(4) var source: texture_2d<f32>;
@group(0) @binding(5) var output: texture_storage_2d<rgba16float, write>;
#ifdef AMBIENT
@group(0) @binding(7) var ambient: texture_2d<f32>;
#endif

const TILE: u32 = 16u;
// Must equal render::lighting::SSGI_TILED_MAX_RADIUS (depth_aware_blur.rs
// blurs at that radius both ways: a smaller MAX_RADIUS here would differ).
const MAX_RADIUS: u32 = 5u;
// (TILE + 2 MAX_RADIUS)^2 texels of 24 bytes: 16,224 of 16,384.
const SPAN: u32 = TILE + 2u * MAX_RADIUS;
const TEXELS: u32 = SPAN * SPAN;
// Marks a texel a tap leaves out (off the image, or no depth).
const NO_DEPTH: f32 = -3e38;
// Half float's infinity: stands for clean()'s 65000.
const CLAMPED_BITS: u32 = 0x7c00u;

var<workgroup> distances: array<f32, TEXELS>;
// safe_normalize's unit normal, or 0 where it falls back.
var<workgroup> normal_x: array<f32, TEXELS>;
var<workgroup> normal_y: array<f32, TEXELS>;
var<workgroup> normal_z: array<f32, TEXELS>;
// clean_gi of the source as half-float bits (rg, ba); after the x blur,
// clean_gi of the x result in the tile's columns.
var<workgroup> gi_rg: array<u32, TEXELS>;
var<workgroup> gi_ba: array<u32, TEXELS>;

// Finite, non-negative, below half-float overflow; anything else is black (ssgi.wgsl's).
fn clean(v: vec3<f32>) -> vec3<f32> {
    return select(vec3<f32>(0.0), min(v, vec3<f32>(65000.0)), v >= vec3<f32>(0.0) & v <= vec3<f32>(3e38));
}

// A (bounce, escaped share) texel made safe: share in 0..1, 1 when unknown (ssgi.wgsl's).
fn clean_gi(v: vec4<f32>) -> vec4<f32> {
    return vec4<f32>(clean(v.rgb), select(1.0, clamp(v.a, 0.0, 1.0), abs(v.a) <= 1.0));
}

// `x` (finite, at most 65504 in size) rounded to half float as an RGBA16F
// store rounds it; kept in f32.
fn round_to_half(x: f32) -> f32 {
    let b = bitcast<u32>(x);
#ifdef HALF_TOWARD_ZERO
    if (abs(x) < 6.103515625e-5) {
        // Below half float's smallest normal its step is 2^-24 (exact scalings).
        return trunc(x * 16777216.0) / 16777216.0;
    }
    return bitcast<f32>(b & 0xffffe000u);
#else
    if (abs(x) < 6.103515625e-5) {
        // round() takes ties to even.
        return round(x * 16777216.0) / 16777216.0;
    }
    return bitcast<f32>((b + 0xfffu + ((b >> 13u) & 1u)) & 0xffffe000u);
#endif
}

// The bits of `x`, a half float or 65000 (an output of clean_gi).
fn half_bits(x: f32) -> u32 {
    if (x == 65000.0) {
        return CLAMPED_BITS;
    }
    let b = bitcast<u32>(x);
    let sign = (b >> 16u) & 0x8000u;
    let a = b & 0x7fffffffu;
    if (a < 0x38800000u) {
        return sign | u32(round(abs(x) * 16777216.0));
    }
    return sign | (((a >> 23u) - 112u) << 10u) | ((a >> 13u) & 0x3ffu);
}

fn half_value(h: u32) -> f32 {
    if (h == CLAMPED_BITS) {
        return 65000.0;
    }
    let e = (h >> 10u) & 0x1fu;
    let m = h & 0x3ffu;
    var v = bitcast<f32>(((e + 112u) << 23u) | (m << 13u));
    if (e == 0u) {
        v = f32(m) / 16777216.0;
    }
    return select(v, -v, (h & 0x8000u) != 0u);
}

fn pack(v: vec4<f32>) -> vec2<u32> {
    return vec2<u32>(half_bits(v.x) | (half_bits(v.y) << 16u), half_bits(v.z) | (half_bits(v.w) << 16u));
}

fn gi_at(i: u32) -> vec4<f32> {
    let rg = gi_rg[i];
    let ba = gi_ba[i];
    return vec4<f32>(half_value(rg & 0xffffu), half_value(rg >> 16u), half_value(ba & 0xffffu), half_value(ba >> 16u));
}

// safe_normalize(the normal at `i`, fallback), from the unit normal stored.
fn normal_at(i: u32, fallback: vec3<f32>) -> vec3<f32> {
    let n = vec3<f32>(normal_x[i], normal_y[i], normal_z[i]);
    return select(n, fallback, all(n == vec3<f32>(0.0)));
}

// The depth-aware blur at region texel `i` along `stride` (1: x, SPAN: y),
// as ssgi.wgsl's BLUR `resolve` computes it; the centre has depth.
fn blur(i: u32, stride: i32, r: i32, spread: f32) -> vec4<f32> {
    let z0 = distances[i];
    let n0 = normal_at(i, vec3<f32>(0.0, 0.0, 1.0));
    let reach = 1.0 / (0.03 * z0 + 1e-6);
    var sum = vec4<f32>(0.0);
    var weights = 0.0;
    for (var o = -r; o <= r; o++) {
        let j = u32(i32(i) + o * stride);
        let zq = distances[j];
        if (zq == NO_DEPTH) {
            continue;
        }
        let nq = normal_at(j, n0);
        let w = tap_weight(o, spread, zq - z0, reach, dot(n0, nq));
        sum += w * gi_at(j);
        weights += w;
    }
    var gi = gi_at(i);
    if (weights > 1e-6) {
        gi = sum / weights;
    }
    return gi;
}

@compute @workgroup_size(16, 16)
fn main(
    @builtin(workgroup_id) group: vec3<u32>,
    @builtin(local_invocation_id) local: vec3<u32>,
    @builtin(local_invocation_index) index: u32,
) {
    let size = vec2<i32>(camera.size.xy);
    let r = i32(min(params.blur_radius, MAX_RADIUS));
    let ru = u32(r);
    let span = TILE + 2u * ru;
    let origin = vec2<i32>(group.xy * TILE) - vec2<i32>(r);
    // 1. Tile and apron into workgroup memory, laid out SPAN wide.
    for (var k = index; k < span * span; k += TILE * TILE) {
        let c = k % span;
        let row = k / span;
        let i = row * SPAN + c;
        let q = origin + vec2<i32>(i32(c), i32(row));
        var d = 0.0;
        var raw = vec3<f32>(0.0);
        var s = vec4<f32>(0.0, 0.0, 0.0, 1.0);
        if (all(q >= vec2<i32>(0)) && all(q < size)) {
            let qu = vec2<u32>(q);
            d = textureLoad(depth, qu, 0).r;
            raw = textureLoad(normals, qu, 0).xyz;
            s = clean_gi(textureLoad(source, qu, 0));
        }
        var z = NO_DEPTH;
        if (d > 0.0) {
            z = -view_position(camera, vec2<u32>(q), d).z;
        }
        distances[i] = z;
        let n = safe_normalize(raw, vec3<f32>(0.0));
        normal_x[i] = n.x;
        normal_y[i] = n.y;
        normal_z[i] = n.z;
        let bits = pack(s);
        gi_rg[i] = bits.x;
        gi_ba[i] = bits.y;
    }
    workgroupBarrier();
    // 2. x over the tile's columns in every row of tile and apron: at most
    //    SPAN x TILE = 416 results, two per thread, held until every thread
    //    has read the values they replace. A centre with no depth writes
    //    (0, 0, 0, 1), as the x pass does.
    let sigma = max(f32(r), 1.0) * 0.5;
    let spread = 1.0 / (2.0 * sigma * sigma);
    let rows = span * TILE;
    var x = array<vec2<u32>, 2>();
    for (var t = 0u; t < 2u; t++) {
        let k = index + t * TILE * TILE;
        if (k < rows) {
            let i = (k / TILE) * SPAN + k % TILE + ru;
            var gi = vec4<f32>(0.0, 0.0, 0.0, 1.0);
            if (distances[i] != NO_DEPTH) {
                gi = blur(i, 1, r, spread);
            }
            // Through the RGBA16F target, read back cleaned.
            x[t] = pack(clean_gi(vec4<f32>(round_to_half(gi.x), round_to_half(gi.y), round_to_half(gi.z), round_to_half(gi.w))));
        }
    }
    workgroupBarrier();
    for (var t = 0u; t < 2u; t++) {
        let k = index + t * TILE * TILE;
        if (k < rows) {
            let i = (k / TILE) * SPAN + k % TILE + ru;
            gi_rg[i] = x[t].x;
            gi_ba[i] = x[t].y;
        }
    }
    workgroupBarrier();
    // 3. y over the tile, as the last BLUR pass.
    let pixel = vec2<i32>(group.xy * TILE + local.xy);
    if (any(pixel >= size)) {
        return;
    }
    let p = vec2<u32>(pixel);
    let centre = (local.y + ru) * SPAN + local.x + ru;
    if (distances[centre] == NO_DEPTH || params.radius <= 0.0) {
#ifdef AMBIENT
        textureStore(output, p, vec4<f32>(clean(textureLoad(ambient, p, 0).rgb), 1.0));
#else
        textureStore(output, p, vec4<f32>(0.0, 0.0, 0.0, 1.0));
#endif
        return;
    }
    let gi = blur(centre, i32(SPAN), r, spread);
#ifdef AMBIENT
    // The environment's light arrives only along the rays that escaped.
    textureStore(output, p, vec4<f32>(min(gi.rgb + clean(textureLoad(ambient, p, 0).rgb) * gi.a, vec3<f32>(65000.0)), 1.0));
#else
    textureStore(output, p, gi);
#endif
}
