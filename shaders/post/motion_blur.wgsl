// Motion blur along the G-buffer's velocity, after McGuire, Hennessy,
// Bukowski and Osman, "A Reconstruction Filter for Plausible Motion Blur"
// (I3D 2012). Velocities (UV per frame) become pixels over the exposure
// (shutter angle / 360 of a frame), halved (the blur reaches half the
// motion each way) and held within the tile size K:
//   `tile_max`:     per KxK tile, the longest velocity in it;
//   `neighbor_max`: per tile, the longest of its 3x3 tiles': a pixel can be
//                   covered by anything moving within K of it, so moving
//                   silhouettes extend over still background;
//   `main`:         per pixel, `samples` taps along the neighbourhood's
//                   longest velocity, each weighted by whether it is in
//                   front (soft depth test) and whether its own blur, or
//                   this pixel's, reaches across the gap (cone and cylinder
//                   terms). A tile whose neighbourhood moves less than half
//                   a pixel copies its pixels.
#import spreadlight::camera::Camera
#import spreadlight::post::{sanitize, load_clamped, inverse_view_depth, hash2}

struct Params {
    // x: exposure (shutter angle / 360), y: tile size K in pixels, z: samples
    settings: vec4<f32>,
}

@group(0) @binding(0) var<uniform> camera: Camera;
@group(0) @binding(1) var<uniform> params: Params;
@group(0) @binding(2) var source: texture_2d<f32>;
@group(0) @binding(3) var depth: texture_2d<f32>;
@group(0) @binding(4) var velocity_uv: texture_2d<f32>;
@group(0) @binding(5) var tiles_in: texture_2d<f32>;
@group(0) @binding(6) var tiles_out: texture_storage_2d<rg32float, write>;
@group(0) @binding(7) var output: texture_storage_2d<rgba16float, write>;

// A pixel's half-velocity in pixels over the exposure, within K; NaN is still.
fn velocity_at(p: vec2<i32>) -> vec2<f32> {
    let size = vec2<f32>(textureDimensions(velocity_uv));
    let raw = sanitize(load_clamped(velocity_uv, p)).xy;
    let v = raw * size * params.settings.x * 0.5;
    let k = params.settings.y;
    let l = length(v);
    if (l > k) {
        return v * (k / l);
    }
    return v;
}

fn longest(a: vec2<f32>, b: vec2<f32>) -> vec2<f32> {
    return select(a, b, dot(b, b) > dot(a, a));
}

// Per lane: the longest velocity it saw (xy) and the first pixel (row-major
// index, z) where it saw it, so ties go to the first pixel as a serial walk would.
var<workgroup> partial_longest: array<vec3<f32>, 64>;

fn longest_first(a: vec3<f32>, b: vec3<f32>) -> vec3<f32> {
    let la = dot(a.xy, a.xy);
    let lb = dot(b.xy, b.xy);
    return select(a, b, lb > la || (lb == la && b.z < a.z));
}

// One 8x8 workgroup per tile (dispatched per tile, not per pixel): its 64
// lanes stride over the tile, then reduce in workgroup memory (a thread per
// tile walking K x K pixels alone left the GPU nearly idle).
@compute @workgroup_size(8, 8)
fn tile_max(@builtin(workgroup_id) tile: vec3<u32>, @builtin(local_invocation_index) lane: u32) {
    let k = i32(params.settings.y);
    let full = vec2<i32>(textureDimensions(velocity_uv));
    let origin = vec2<i32>(tile.xy) * k;
    let hi = min(origin + k, full);
    let local = vec2<i32>(i32(lane % 8u), i32(lane / 8u));
    // Row-major index within the tile; pixels past the edge are never read.
    var m = vec3<f32>(0.0, 0.0, f32(k * k));
    for (var y = origin.y + local.y; y < hi.y; y += 8) {
        for (var x = origin.x + local.x; x < hi.x; x += 8) {
            let at = f32((y - origin.y) * k + (x - origin.x));
            let v = velocity_at(vec2<i32>(x, y));
            // Within a lane, pixels come in row-major order: keep the first of ties.
            if (dot(v, v) > dot(m.xy, m.xy) || (at < m.z && dot(v, v) == dot(m.xy, m.xy))) {
                m = vec3<f32>(v, at);
            }
        }
    }
    partial_longest[lane] = m;
    workgroupBarrier();
    for (var step = 32u; step > 0u; step = step / 2u) {
        if (lane < step) {
            partial_longest[lane] = longest_first(partial_longest[lane], partial_longest[lane + step]);
        }
        workgroupBarrier();
    }
    let size = textureDimensions(tiles_out);
    if (lane == 0u && tile.x < size.x && tile.y < size.y) {
        textureStore(tiles_out, tile.xy, vec4<f32>(partial_longest[0].xy, 0.0, 0.0));
    }
}

@compute @workgroup_size(8, 8)
fn neighbor_max(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(tiles_out);
    if (id.x >= size.x || id.y >= size.y) {
        return;
    }
    var m = vec2<f32>(0.0);
    for (var y = -1; y <= 1; y++) {
        for (var x = -1; x <= 1; x++) {
            m = longest(m, load_clamped(tiles_in, vec2<i32>(id.xy) + vec2<i32>(x, y)).xy);
        }
    }
    textureStore(tiles_out, id.xy, vec4<f32>(m, 0.0, 0.0));
}

fn view_depth(p: vec2<i32>) -> f32 {
    let inv = inverse_view_depth(camera.projection_inverse, load_clamped(depth, p).r);
    return 1.0 / max(inv, 1e-6);
}

// 1 when `a` is in front of `b` (nearer), fading over 2% of the depth.
fn soft_depth_compare(a: f32, b: f32) -> f32 {
    let extent = 0.02 * min(a, b) + 1e-4;
    return clamp(1.0 - (a - b) / extent, 0.0, 1.0);
}

fn cone(distance: f32, v: f32) -> f32 {
    return clamp(1.0 - distance / v, 0.0, 1.0);
}

fn cylinder(distance: f32, v: f32) -> f32 {
    return 1.0 - smoothstep(0.95 * v, 1.05 * v, distance);
}

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(output);
    if (id.x >= size.x || id.y >= size.y) {
        return;
    }
    let x = vec2<i32>(id.xy);
    let center = sanitize(load_clamped(source, x));
    let k = i32(params.settings.y);
    let vn = load_clamped(tiles_in, x / k).xy;
    if (length(vn) < 0.5) {
        textureStore(output, id.xy, center);
        return;
    }
    let vx = velocity_at(x);
    let lx = max(length(vx), 0.5);
    let zx = view_depth(x);
    let n = max(u32(params.settings.z), 2u);
    var weight = 1.0 / lx;
    var sum = center.rgb * weight;
    let jitter = hash2(id.xy) - 0.5;
    for (var i = 0u; i < n; i++) {
        let t = mix(-1.0, 1.0, (f32(i) + jitter + 1.0) / f32(n + 1u));
        let y = x + vec2<i32>(round(vn * t));
        if (all(y == x)) {
            continue;
        }
        let vy = velocity_at(y);
        let ly = max(length(vy), 0.5);
        let zy = view_depth(y);
        let d = length(vn * t);
        let front = soft_depth_compare(zy, zx);
        let back = soft_depth_compare(zx, zy);
        // The paper's weights, scaled by 15 / samples: the centre's weight (1 / |V|)
        // does not grow with the sample count, so without this more samples would
        // blur more; at 15 (the default) they are the paper's.
        let alpha = (front * cone(d, ly) + back * cone(d, lx) + cylinder(d, ly) * cylinder(d, lx) * 2.0) * (15.0 / f32(n));
        weight += alpha;
        sum += sanitize(load_clamped(source, y)).rgb * alpha;
    }
    let color = sum / max(weight, 1e-6);
    textureStore(output, id.xy, vec4<f32>(clamp(color, vec3<f32>(0.0), vec3<f32>(65000.0)), center.a));
}
