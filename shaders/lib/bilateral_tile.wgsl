// The depth- and normal-aware separable blur of AO (occlusion/blur.wgsl)
// and SSGI (lighting/ssgi.wgsl), both directions in one dispatch.
//
// Two dispatches (x, then y through a full-screen target) cost a pass's
// floor, a boundary and the target's round trip each; here a 16x16
// workgroup loads its tile with a 4-texel apron once (each texel's view
// distance and unit normal made once, not once per tap), blurs the
// apron's rows along x into workgroup memory, then its own pixels along y.
// The arithmetic per tap is the two-pass blur's, and the x result is kept
// at the precision the two-pass target held (f32 for AO's R32Float, half
// floats for SSGI's Rgba16Float), so the image is the two passes' image.
// Blurs wider than the apron (`BILATERAL_APRON`) keep the two passes.
//
// Values: with BILATERAL_SCALAR one channel of occlusion in 0..1 (a tap
// that is not finite is left out; the x result lands in R32Float);
// without, four channels of light cleaned as SSGI's `clean_gi` does.
#define_import_path spreadlight::bilateral_tile
#import spreadlight::camera::Camera
#import spreadlight::packing::safe_normalize
#import spreadlight::screen::view_position

const TILE: u32 = 16u;
// The widest blur (half-width) one dispatch holds; crates/render mirrors it.
const BILATERAL_APRON: u32 = 4u;
const SPAN: u32 = 24u; // TILE + 2 * BILATERAL_APRON
const TEXELS: u32 = 576u; // SPAN * SPAN
const ROWS_OF_X: u32 = 384u; // TILE * SPAN: the x blur of the tile's columns, every row

// Per texel of tile and apron: view distance (-1 where no surface or off
// screen: such a tap is skipped) and unit normal (0 where it had none: the
// centre's stands in, as `safe_normalize`'s fallback does).
var<workgroup> surfaces: array<vec4<f32>, TEXELS>;
// The source per texel, then (from the x blur on) the x blur per column and row.
var<workgroup> values: array<vec2<u32>, TEXELS>;

fn pack_value(v: vec4<f32>) -> vec2<u32> {
#ifdef BILATERAL_SCALAR
    return vec2<u32>(bitcast<u32>(v.x), 0u);
#else
    return vec2<u32>(pack2x16float(v.xy), pack2x16float(v.zw));
#endif
}

fn unpack_value(p: vec2<u32>) -> vec4<f32> {
#ifdef BILATERAL_SCALAR
    return vec4<f32>(bitcast<f32>(p.x), 0.0, 0.0, 0.0);
#else
    return vec4<f32>(unpack2x16float(p.x), unpack2x16float(p.y));
#endif
}

// Finite, non-negative, below half-float overflow; anything else is black.
fn clean_light(v: vec3<f32>) -> vec3<f32> {
    return select(vec3<f32>(0.0), min(v, vec3<f32>(65000.0)), v >= vec3<f32>(0.0) & v <= vec3<f32>(3e38));
}

// A (bounce, escaped share) texel made safe: share in 0..1, 1 when unknown.
fn clean_gi(v: vec4<f32>) -> vec4<f32> {
    return vec4<f32>(clean_light(v.rgb), select(1.0, clamp(v.a, 0.0, 1.0), abs(v.a) <= 1.0));
}

// A tap's value, or a negative x where the tap is left out (occlusion only).
fn tap_value(raw: vec4<f32>) -> vec4<f32> {
#ifdef BILATERAL_SCALAR
    return vec4<f32>(select(-1.0, clamp(raw.x, 0.0, 1.0), abs(raw.x) <= 1e30), 0.0, 0.0, 0.0);
#else
    return clean_gi(raw);
#endif
}

// The centre's own value where no tap carries weight.
fn lone_value(raw: vec4<f32>) -> vec4<f32> {
#ifdef BILATERAL_SCALAR
    return vec4<f32>(select(1.0, clamp(raw.x, 0.0, 1.0), abs(raw.x) <= 1e30), 0.0, 0.0, 0.0);
#else
    return clean_gi(raw);
#endif
}

// The texel `k` of the tile whose first pixel is `origin`, apron included.
fn span_pixel(origin: vec2<i32>, k: u32) -> vec2<i32> {
    return origin - vec2<i32>(i32(BILATERAL_APRON)) + vec2<i32>(i32(k % SPAN), i32(k / SPAN));
}

// Every thread of the workgroup calls this (it holds barriers): fills the
// tile's surfaces and values from the G-buffer and `source`.
fn load_tile(
    camera: Camera,
    depth: texture_2d<f32>,
    normals: texture_2d<f32>,
    source: texture_2d<f32>,
    origin: vec2<i32>,
    thread: u32,
) {
    let size = vec2<i32>(camera.size.xy);
    for (var k = thread; k < TEXELS; k += TILE * TILE) {
        let q = span_pixel(origin, k);
        var surface = vec4<f32>(-1.0, 0.0, 0.0, 0.0);
        var value = vec2<u32>(0u);
        if (all(q >= vec2<i32>(0)) && all(q < size)) {
            let qu = vec2<u32>(q);
            let d = textureLoad(depth, qu, 0).r;
            if (d > 0.0) {
                let z = -view_position(camera, qu, d).z;
                surface = vec4<f32>(z, safe_normalize(textureLoad(normals, qu, 0).xyz, vec3<f32>(0.0)));
            }
            value = pack_value(textureLoad(source, qu, 0));
        }
        surfaces[k] = surface;
        values[k] = value;
    }
    workgroupBarrier();
}

// The blur of texel `centre` along `step` (1: x, SPAN: y) over `r` taps each
// side, from `values`; a centre with no surface keeps its own value.
fn blur_along(centre: u32, step: i32, r: i32) -> vec4<f32> {
    let s0 = surfaces[centre];
    let raw = unpack_value(values[centre]);
    let z0 = s0.x;
    if (z0 < 0.0) {
        return lone_value(raw);
    }
    let n0 = select(s0.yzw, vec3<f32>(0.0, 0.0, 1.0), all(s0.yzw == vec3<f32>(0.0)));
    let sigma = max(f32(r), 1.0) * 0.5;
    var sum = vec4<f32>(0.0);
    var weights = 0.0;
    for (var o = -r; o <= r; o++) {
        let k = u32(i32(centre) + step * o);
        let sq = surfaces[k];
        if (sq.x < 0.0) {
            continue;
        }
        let v = tap_value(unpack_value(values[k]));
        if (v.x < 0.0) {
            continue;
        }
        let nq = select(sq.yzw, n0, all(sq.yzw == vec3<f32>(0.0)));
        let w = exp(-f32(o * o) / (2.0 * sigma * sigma))
            * exp(-abs(sq.x - z0) / (0.03 * z0 + 1e-6))
            * pow(max(dot(n0, nq), 0.0), 8.0);
        sum += w * v;
        weights += w;
    }
    if (weights > 1e-6) {
        return sum / weights;
    }
    return lone_value(raw);
}

// Every thread calls this after `load_tile`: the blur, x then y, at the
// thread's pixel `local` of the tile (r <= BILATERAL_APRON).
fn blur_tile(local: vec2<u32>, thread: u32, r: i32) -> vec4<f32> {
    // The x blur of each tile column in every row of the apron, held until
    // all threads have read the source, then stored over it.
    var across: array<vec4<f32>, 2>;
    for (var j = 0u; j < 2u; j++) {
        let k = thread + j * TILE * TILE;
        if (k < ROWS_OF_X) {
            let centre = (k / TILE) * SPAN + BILATERAL_APRON + k % TILE;
            var v = blur_along(centre, 1, r);
#ifdef BILATERAL_SCALAR
            // The two-pass blur clamps and stores this in R32Float.
            v = vec4<f32>(clamp(v.x, 0.0, 1.0), 0.0, 0.0, 0.0);
#endif
            across[j] = v;
        }
    }
    workgroupBarrier();
    for (var j = 0u; j < 2u; j++) {
        let k = thread + j * TILE * TILE;
        if (k < ROWS_OF_X) {
            // Back at the column's own texel, so the y taps step by SPAN.
            values[(k / TILE) * SPAN + BILATERAL_APRON + k % TILE] = pack_value(across[j]);
        }
    }
    workgroupBarrier();
    return blur_along((local.y + BILATERAL_APRON) * SPAN + local.x + BILATERAL_APRON, i32(SPAN), r);
}
