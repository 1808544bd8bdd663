// AO's depth- and normal-aware blur, x and y in one dispatch: the same
// weights and the same order of sums as the two passes of ssao/blur.wgsl,
// whose result this matches (crates/render/tests/depth_aware_blur.rs), so
// the x pass's full-screen write, the y pass's read of it and the barrier
// between them go away.
//
// A 16x16 workgroup owns a 16x16 tile. It loads the tile and an apron of
// `blur_radius` texels on every side into workgroup memory once: view
// distance (one inverse projection per texel, where the two passes made one
// per tap), the unit normal (one normalize per texel) and the source value. Then it blurs along x for
// the tile's columns over every row of tile and apron (the rows the y taps
// need), writes those results over the source values of the same texels,
// and blurs along y for the tile. Half-widths above MAX_RADIUS do not fit
// in 16 KiB of workgroup memory (WebGPU's default limit): the recipe keeps
// the two passes for them.
#import spreadlight::camera::Camera
#import spreadlight::packing::safe_normalize
#import spreadlight::screen::{RayParams, view_position, tap_weight}

@group(0) @binding(0) var<uniform> camera: Camera;
@group(0) @binding(1) var<uniform> params: RayParams;
@group(0) @binding(2) var source: texture_2d<f32>;
@group(0) @binding(3) var depth: texture_2d<f32>;
@group(0) @binding(4) var normals: texture_2d<f32>;
@group(0) @binding(5) var output: texture_storage_2d<rgba16float, write>;
#ifdef COMBINE
@group(0) @binding(6) var combine: texture_2d<f32>;
#endif

const TILE: u32 = 16u;
// Must equal render::ssao::TILED_MAX_RADIUS (depth_aware_blur.rs blurs at
// that radius both ways: a smaller MAX_RADIUS here would differ).
const MAX_RADIUS: u32 = 6u;
// (TILE + 2 MAX_RADIUS)^2 texels of 20 bytes: 15,680 of 16,384.
const SPAN: u32 = TILE + 2u * MAX_RADIUS;
const TEXELS: u32 = SPAN * SPAN;
// Marks a source value a tap leaves out (as the passes leave out a value
// that is not finite): above the 1e30 the finiteness test allows.
const LEFT_OUT: f32 = 2e30;

// Marks a texel a tap leaves out for its depth (off the image, or empty):
// no view distance is this.
const NO_DEPTH: f32 = -3e38;

// View distance, or NO_DEPTH.
var<workgroup> distances: array<f32, TEXELS>;
// safe_normalize's unit normal, or 0 where it falls back (to the centre's
// normal for a tap, to +Z for a centre). Three arrays of f32, not one of
// vec3 (whose 16-byte stride would not fit).
var<workgroup> normal_x: array<f32, TEXELS>;
var<workgroup> normal_y: array<f32, TEXELS>;
var<workgroup> normal_z: array<f32, TEXELS>;
// The source value clamped to 0..1, or LEFT_OUT; after the x blur, the x
// result in the tile's columns.
var<workgroup> values: array<f32, TEXELS>;

// safe_normalize(the normal at `i`, fallback), from the unit normal stored.
fn normal_at(i: u32, fallback: vec3<f32>) -> vec3<f32> {
    let n = vec3<f32>(normal_x[i], normal_y[i], normal_z[i]);
    return select(n, fallback, all(n == vec3<f32>(0.0)));
}

// The x blur of region texel (column `c`, row `row`), as blur.wgsl's first
// pass computes it for the pixel there.
fn blur_x(c: u32, row: u32, r: i32, spread: f32) -> f32 {
    let i = row * SPAN + c;
    let z0 = distances[i];
    if (z0 == NO_DEPTH) {
        return 1.0;
    }
    let n0 = normal_at(i, vec3<f32>(0.0, 0.0, 1.0));
    let reach = 1.0 / (0.03 * z0 + 1e-6);
    var sum = 0.0;
    var weights = 0.0;
    for (var o = -r; o <= r; o++) {
        let j = u32(i32(i) + o);
        let zq = distances[j];
        let s = values[j];
        if (zq == NO_DEPTH || !(abs(s) <= 1e30)) {
            continue;
        }
        let nq = normal_at(j, n0);
        let w = tap_weight(o, spread, zq - z0, reach, dot(n0, nq));
        sum += w * s;
        weights += w;
    }
    var v = 1.0;
    if (weights > 1e-6) {
        v = sum / weights;
    } else {
        v = select(1.0, values[i], abs(values[i]) <= 1e30);
    }
    return clamp(v, 0.0, 1.0);
}

@compute @workgroup_size(16, 16)
fn main(
    @builtin(workgroup_id) group: vec3<u32>,
    @builtin(local_invocation_id) local: vec3<u32>,
    @builtin(local_invocation_index) index: u32,
) {
    let size = vec2<i32>(camera.size.xy);
    let r = i32(min(params.blur_radius, MAX_RADIUS));
    let span = TILE + 2u * u32(r);
    let origin = vec2<i32>(group.xy * TILE) - vec2<i32>(r);
    // 1. Tile and apron into workgroup memory, laid out SPAN wide.
    for (var k = index; k < span * span; k += TILE * TILE) {
        let c = k % span;
        let row = k / span;
        let i = row * SPAN + c;
        let q = origin + vec2<i32>(i32(c), i32(row));
        var d = 0.0;
        var raw = vec3<f32>(0.0);
        var s = LEFT_OUT;
        if (all(q >= vec2<i32>(0)) && all(q < size)) {
            let qu = vec2<u32>(q);
            d = textureLoad(depth, qu, 0).r;
            raw = textureLoad(normals, qu, 0).xyz;
            let v = textureLoad(source, qu, 0).r;
            s = select(LEFT_OUT, clamp(v, 0.0, 1.0), abs(v) <= 1e30);
        }
        var z = NO_DEPTH;
        if (d > 0.0) {
            z = -view_position(camera, vec2<u32>(q), d).z;
        }
        distances[i] = z;
        // Zero marks safe_normalize's fallback (a unit normal is never zero).
        let n = safe_normalize(raw, vec3<f32>(0.0));
        normal_x[i] = n.x;
        normal_y[i] = n.y;
        normal_z[i] = n.z;
        values[i] = s;
    }
    workgroupBarrier();
    // 2. x over the tile's columns, every row of tile and apron: at most
    //    SPAN x TILE = 448 results, two per thread, held until every thread
    //    has read the source values they replace.
    let sigma = max(f32(r), 1.0) * 0.5;
    let spread = 1.0 / (2.0 * sigma * sigma);
    let rows = span * TILE;
    let k0 = index;
    let k1 = index + TILE * TILE;
    var x0 = 0.0;
    var x1 = 0.0;
    if (k0 < rows) {
        x0 = blur_x(k0 % TILE + u32(r), k0 / TILE, r, spread);
    }
    if (k1 < rows) {
        x1 = blur_x(k1 % TILE + u32(r), k1 / TILE, r, spread);
    }
    workgroupBarrier();
    if (k0 < rows) {
        values[(k0 / TILE) * SPAN + k0 % TILE + u32(r)] = x0;
    }
    if (k1 < rows) {
        values[(k1 / TILE) * SPAN + k1 % TILE + u32(r)] = x1;
    }
    workgroupBarrier();
    // 3. y over the tile, as blur.wgsl's VERTICAL pass over the x result.
    let pixel = vec2<i32>(group.xy * TILE + local.xy);
    if (any(pixel >= size)) {
        return;
    }
    let c = local.x + u32(r);
    let centre = (local.y + u32(r)) * SPAN + c;
    let z0 = distances[centre];
    var v = 1.0;
    if (z0 != NO_DEPTH) {
        let n0 = normal_at(centre, vec3<f32>(0.0, 0.0, 1.0));
        let reach = 1.0 / (0.03 * z0 + 1e-6);
        var sum = 0.0;
        var weights = 0.0;
        for (var o = -r; o <= r; o++) {
            let j = u32(i32(centre) + o * i32(SPAN));
            let zq = distances[j];
            if (zq == NO_DEPTH) {
                continue;
            }
            let s = values[j];
            if (!(abs(s) <= 1e30)) {
                continue;
            }
            let nq = normal_at(j, n0);
            let w = tap_weight(o, spread, zq - z0, reach, dot(n0, nq));
            sum += w * clamp(s, 0.0, 1.0);
            weights += w;
        }
        if (weights > 1e-6) {
            v = sum / weights;
        } else {
            let s = values[centre];
            v = select(1.0, clamp(s, 0.0, 1.0), abs(s) <= 1e30);
        }
    }
#ifdef COMBINE
    let other = textureLoad(combine, vec2<u32>(pixel), 0).r;
    v *= select(1.0, clamp(other, 0.0, 1.0), abs(other) <= 1e30);
#endif
    v = clamp(v, 0.0, 1.0);
    textureStore(output, vec2<u32>(pixel), vec4<f32>(v, v, v, 1.0));
}
