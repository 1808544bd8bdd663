// Depth of field from a thin lens, in two passes.
//
// `coc`: per pixel (a pass of its own at half resolution; at full
// resolution, INLINE_COC, made where `tiles` and `main` read it), the
// signed circle of confusion in pixels (negative in
// front of the focus plane, the near field; positive behind, the far field)
// and the inverse view depth. For a lens of aperture A = f / N focused at s,
// with the field of view held (the sensor where the focus plane's image
// forms), a point at depth z blurs to a circle of A |1/s - 1/z| times the
// image distance: in pixels, `scale` |1/s - 1/z|, where `scale` folds A, the
// field of view and the image height in pixels, computed on the CPU. Written
// with inverse depths it stays finite for a focus at infinity and the sky.
//
// `tiles`: per tile (at least as wide as the largest radius), the largest
// radius in it and its eight neighbours: how far any pixel of the tile must
// look for circles that may cover it.
//
// `main`: a scatter-as-gather lens blur. Each of `samples` points of a
// golden-angle spiral over a disk of the tile's radius (turned
// by a per-pixel random angle: the stochastic part, noise at low sample
// counts) is a pixel whose own blur circle may cover this one; it counts by
// its circle's coverage of this pixel over the circle's area, so the image's
// energy is kept. A sample behind this pixel can spread over it no further
// than this pixel's own circle: a sharp foreground keeps its edges against a
// blurred background (no halo), while a blurred foreground still spreads over
// whatever lies behind it (the near field). With BOKEH the coverage is the
// bokeh texture's value at the offset, so highlights take its shape.
#import spreadlight::camera::Camera
#import spreadlight::post::{sanitize, sanitize_scalar, load_clamped, inverse_view_depth, hash2, luminance}

struct Params {
    // x: CoC scale (pixels per unit of |1/s - 1/z|), y: 1/s (fixed focus),
    // z: largest radius in pixels, w: samples
    lens: vec4<f32>,
    // x: focal length in scene units (unused), y: largest 1/s allowed, z: tile size in pixels
    limits: vec4<f32>,
}

@group(0) @binding(0) var<uniform> camera: Camera;
@group(0) @binding(1) var<uniform> params: Params;
@group(0) @binding(2) var source: texture_2d<f32>;
@group(0) @binding(3) var depth: texture_2d<f32>;
@group(0) @binding(4) var coc_out: texture_storage_2d<rg32float, write>;
@group(0) @binding(5) var coc_in: texture_2d<f32>;
@group(0) @binding(6) var output: texture_storage_2d<rgba16float, write>;
@group(0) @binding(9) var tiles_out: texture_storage_2d<r32float, write>;
@group(0) @binding(10) var tiles_in: texture_2d<f32>;
#ifdef AUTOFOCUS
// 1x1: the inverse focus distance the Autofocus pass keeps.
@group(0) @binding(7) var focus: texture_2d<f32>;
#endif
#ifdef BOKEH
@group(0) @binding(8) var bokeh: texture_2d<f32>;
#endif

fn inverse_focus() -> f32 {
#ifdef AUTOFOCUS
    let inv = sanitize_scalar(textureLoad(focus, vec2<i32>(0), 0).r);
#else
    let inv = params.lens.y;
#endif
    return clamp(inv, 0.0, params.limits.y);
}

// Pixel `p`'s signed blur radius and inverse view depth, from the depth.
fn coc_at(p: vec2<i32>) -> vec2<f32> {
    let inv_z = inverse_view_depth(camera.projection_inverse, load_clamped(depth, p).r);
    let inv_s = inverse_focus();
    let c = params.lens.x * (inv_s - inv_z);
    let radius = params.lens.z;
    // Half the diameter: the blur radius, within the largest the pass gathers.
    return vec2<f32>(clamp(0.5 * c, -radius, radius), inv_z);
}

// What `tiles` and `main` read of pixel `p`: with INLINE_COC (full
// resolution) made from the depth where it is read, a few operations, so
// no pass writes and reads back a full-size CoC target; otherwise the
// `coc` pass's target (the half-resolution upsample reads it too).
fn coc_value(p: vec2<i32>) -> vec2<f32> {
#ifdef INLINE_COC
    return coc_at(p);
#else
    return load_clamped(coc_in, p).rg;
#endif
}

fn coc_size() -> vec2<i32> {
#ifdef INLINE_COC
    return vec2<i32>(textureDimensions(depth));
#else
    return vec2<i32>(textureDimensions(coc_in));
#endif
}

@compute @workgroup_size(8, 8)
fn coc(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(coc_out);
    if (id.x >= size.x || id.y >= size.y) {
        return;
    }
    textureStore(coc_out, id.xy, vec4<f32>(coc_at(vec2<i32>(id.xy)), 0.0, 0.0));
}

var<workgroup> partial_max: array<f32, 64>;

// Each tile's largest circle: one 8x8 workgroup per tile (dispatched per
// tile, not per pixel), its 64 lanes striding over the tile's pixels, then
// a reduction in workgroup memory. A thread per tile walking up to 3k x 3k
// pixels alone left the GPU nearly idle (0.29 ms at 1080p on the H100);
// reading the 3x3 tiles around it here read every pixel nine times (0.035
// ms at 1080p on the H200), so `neighbour_max` takes the 3x3 after.
@compute @workgroup_size(8, 8)
fn tiles(@builtin(workgroup_id) tile: vec3<u32>, @builtin(local_invocation_index) lane: u32) {
    let k = i32(params.limits.z);
    let full = coc_size();
    let lo = vec2<i32>(tile.xy) * k;
    let hi = min(lo + k, full);
    let local = vec2<i32>(i32(lane % 8u), i32(lane / 8u));
    var m = 0.0;
    for (var y = lo.y + local.y; y < hi.y; y += 8) {
        for (var x = lo.x + local.x; x < hi.x; x += 8) {
            m = max(m, abs(coc_value(vec2<i32>(x, y)).x));
        }
    }
    partial_max[lane] = m;
    workgroupBarrier();
    for (var step = 32u; step > 0u; step = step / 2u) {
        if (lane < step) {
            partial_max[lane] = max(partial_max[lane], partial_max[lane + step]);
        }
        workgroupBarrier();
    }
    let size = textureDimensions(tiles_out);
    if (lane == 0u && tile.x < size.x && tile.y < size.y) {
        textureStore(tiles_out, tile.xy, vec4<f32>(partial_max[0], 0.0, 0.0, 0.0));
    }
}

// Per tile, the largest circle of it and its eight neighbours: a circle
// reaches no further than the next tile, so nothing wider can cover a pixel.
@compute @workgroup_size(8, 8)
fn neighbour_max(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(tiles_out);
    if (id.x >= size.x || id.y >= size.y) {
        return;
    }
    var m = 0.0;
    for (var y = -1; y <= 1; y++) {
        for (var x = -1; x <= 1; x++) {
            m = max(m, load_clamped(tiles_in, vec2<i32>(id.xy) + vec2<i32>(x, y)).r);
        }
    }
    textureStore(tiles_out, id.xy, vec4<f32>(m, 0.0, 0.0, 0.0));
}

fn shape(offset: vec2<f32>) -> f32 {
#ifdef BOKEH
    let size = vec2<f32>(textureDimensions(bokeh));
    let p = vec2<i32>((offset * 0.5 + 0.5) * size);
    return max(sanitize_scalar(luminance(load_clamped(bokeh, p).rgb)), 0.0);
#else
    return 1.0;
#endif
}

// How much a blur circle of radius `c` (pixels) centred `distance` away covers this pixel, per pixel of area.
fn coverage(c: f32, offset: vec2<f32>, distance: f32) -> f32 {
    let r = max(c, 0.5);
    let edge = clamp(r - distance + 0.5, 0.0, 1.0);
    var s = 1.0;
    if (distance > 0.0) {
        s = shape(-offset * distance / r);
    }
    return edge * s / (3.14159265 * r * r);
}

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(output);
    if (id.x >= size.x || id.y >= size.y) {
        return;
    }
#ifdef HALF
    // Half resolution: the output is half size; this thread blurs its 2x2
    // block's top-left pixel exactly as at full resolution
    // (crates/render/src/resolution.rs upsamples it, keeping in-focus detail).
    let p = vec2<i32>(id.xy * 2u);
#else
    let p = vec2<i32>(id.xy);
#endif
    let here = coc_value(p);
    let c0 = abs(here.x);
    let center = sanitize(load_clamped(source, p));
    let tile_radius = load_clamped(tiles_in, p / i32(params.limits.z)).r;
    // In focus across the tile and its neighbours: no circle that could
    // cover this pixel reaches past it (every sample would round to this
    // pixel), so the gather would give the centre back. Skip it.
    if (!(tile_radius > 0.5)) {
        textureStore(output, id.xy, vec4<f32>(clamp(center.rgb, vec3<f32>(0.0), vec3<f32>(65000.0)), center.a));
        return;
    }
    let radius = tile_radius;
    let n = u32(params.lens.w);
    var sum = center.rgb * coverage(c0, vec2<f32>(0.0), 0.0);
    var weight = coverage(c0, vec2<f32>(0.0), 0.0);
    // Each sample stands for radius^2 * pi / n pixels of the disk.
    let area = 3.14159265 * radius * radius / f32(max(n, 1u));
    let turn = hash2(vec2<u32>(p)) * 6.2831853;
    for (var i = 0u; i < n; i++) {
        // Golden-angle spiral, areas equal: r ~ sqrt((i + 0.5) / n).
        let t = (f32(i) + 0.5) / f32(n);
        let angle = f32(i) * 2.39996323 + turn;
        let offset = vec2<f32>(cos(angle), sin(angle));
        let distance = sqrt(t) * radius;
        let q = p + vec2<i32>(round(offset * distance));
        // Coverage by where the sample really is (a whole pixel); this pixel itself is counted above.
        let actual = vec2<f32>(q - p);
        let reach = length(actual);
        if (reach < 0.5) {
            continue;
        }
        let there = coc_value(q);
        var c = abs(there.x);
        // Behind this pixel (smaller inverse depth): spreads no further than this pixel's own circle.
        if (there.y < here.y) {
            c = min(c, c0);
        }
        let w = coverage(c, actual / reach, reach) * area;
        sum += sanitize(load_clamped(source, q)).rgb * w;
        weight += w;
    }
    let color = sum / max(weight, 1e-6);
    textureStore(output, id.xy, vec4<f32>(clamp(color, vec3<f32>(0.0), vec3<f32>(65000.0)), center.a));
}
