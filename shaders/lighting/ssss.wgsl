// SSSS: screen-space subsurface scattering in the manner of Jimenez et al.
// 2015 ("Separable Subsurface Scattering"): CookTorrance's subsurface term
// blurred by a separable kernel, one pass along x, one along y (VERTICAL),
// the kernel one Gaussian per channel (not their fitted sum of Gaussians
// for a measured skin profile: FakeSSS gives a colour, not a profile),
// as wide on screen as `width` world units at the pixel's depth. Per
// material (the FakeSSS feature): each channel's reach is `width` times
// that channel of the FakeSSS colour over its largest channel, so a skin
// tone scatters red farthest. Taps on other materials or the sky take no
// weight (Jimenez's stencil), and taps across a depth step are pulled back
// toward the centre ("follow surface"), so light does not bleed between
// objects. Pixels without FakeSSS, or whose FakeSSS has strength or colour
// 0, pass through.
// SOURCES_2 / SOURCES_3 (with SOURCES_2): two or three sources blurred
// alike in one pass (CookTorrance gives a subsurface term per light type):
// the taps' depths, materials and weights are found once for all of them.
#import spreadlight::camera::Camera
#import spreadlight::packing::channel_to_id
#import spreadlight::material::{feature_param, FEATURE_FAKE_SSS}
#import spreadlight::screen::view_position

struct Params {
    // World units of the widest channel's reach (3 standard deviations).
    width: f32,
    // Taps on each side of the centre.
    taps: u32,
    _pad0: u32,
    _pad1: u32,
}

@group(0) @binding(0) var<uniform> camera: Camera;
@group(0) @binding(1) var<uniform> params: Params;
@group(0) @binding(2) var source: texture_2d<f32>;
@group(0) @binding(3) var depth: texture_2d<f32>;
@group(0) @binding(4) var color: texture_2d<f32>;
@group(0) @binding(5) var output: texture_storage_2d<rgba16float, write>;
#ifdef SOURCES_2
@group(0) @binding(6) var source_b: texture_2d<f32>;
@group(0) @binding(7) var output_b: texture_storage_2d<rgba16float, write>;
#ifdef SOURCES_3
@group(0) @binding(8) var source_c: texture_2d<f32>;
@group(0) @binding(9) var output_c: texture_storage_2d<rgba16float, write>;
const SOURCES: u32 = 3u;
#else
const SOURCES: u32 = 2u;
#endif
#else
const SOURCES: u32 = 1u;
#endif

// Source `k`'s texel, cleaned.
fn load_source(k: u32, q: vec2<u32>) -> vec3<f32> {
#ifdef SOURCES_2
    if (k == 1u) {
        return clean(textureLoad(source_b, q, 0).rgb);
    }
#ifdef SOURCES_3
    if (k == 2u) {
        return clean(textureLoad(source_c, q, 0).rgb);
    }
#endif
#endif
    return clean(textureLoad(source, q, 0).rgb);
}

fn store(k: u32, pixel: vec2<u32>, value: vec3<f32>) {
    let v = vec4<f32>(value, 1.0);
#ifdef SOURCES_2
    if (k == 1u) {
        textureStore(output_b, pixel, v);
        return;
    }
#ifdef SOURCES_3
    if (k == 2u) {
        textureStore(output_c, pixel, v);
        return;
    }
#endif
#endif
    textureStore(output, pixel, v);
}

fn clean(v: vec3<f32>) -> vec3<f32> {
    return select(vec3<f32>(0.0), min(v, vec3<f32>(65000.0)), v >= vec3<f32>(0.0) & v <= vec3<f32>(3e38));
}

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = vec2<u32>(camera.size.xy);
    if (id.x >= size.x || id.y >= size.y) {
        return;
    }
    let pixel = id.xy;
    var center: array<vec3<f32>, SOURCES>;
    for (var k = 0u; k < SOURCES; k++) {
        center[k] = load_source(k, pixel);
    }
    let d = textureLoad(depth, pixel, 0).r;
    let material = channel_to_id(textureLoad(color, pixel, 0).a);
    // FakeSSS's colour and strength; zero without the feature. A material
    // that scatters nothing (strength or colour 0: its subsurface term is
    // zero) passes through, as one without the feature does: on a frame
    // whose floor carries FakeSSS at strength 0 that skips most taps.
    let scatter = feature_param(material, FEATURE_FAKE_SSS, 0u, vec4<f32>(0.0));
    let tint = max(scatter.rgb, vec3<f32>(0.0));
    let widest = max(tint.r, max(tint.g, tint.b));
    if (d <= 0.0 || scatter.a <= 0.0 || widest <= 0.0 || params.width <= 0.0 || params.taps == 0u) {
        for (var k = 0u; k < SOURCES; k++) {
            store(k, pixel, center[k]);
        }
        return;
    }
    let z = max(-view_position(camera, pixel, d).z, 1e-6);
    let reach = tint / widest;
    // Standard deviation per channel in pixels; the taps cover 3 of the widest.
    let pixels_per_unit = camera.projection[1][1] * camera.size.y * 0.5 / z;
    let sigma = max(reach * params.width / 3.0 * pixels_per_unit, vec3<f32>(1e-3));
    let extent = min(params.width * pixels_per_unit, 256.0);
#ifdef VERTICAL
    let axis = vec2<f32>(0.0, 1.0);
#else
    let axis = vec2<f32>(1.0, 0.0);
#endif
    var sum = center;
    var weights = vec3<f32>(1.0);
    let n = f32(params.taps);
    for (var i = 1u; i <= params.taps; i++) {
        // Taps denser near the centre (Jimenez's quadratic spacing).
        let t = f32(i) / n;
        let offset = t * t * extent;
        let g = exp(-0.5 * (offset * offset) / (sigma * sigma));
        for (var side = -1.0; side <= 1.0; side += 2.0) {
            let q = vec2<i32>(floor(vec2<f32>(pixel) + 0.5 + axis * offset * side));
            if (any(q < vec2<i32>(0)) || any(q >= vec2<i32>(size))) {
                continue;
            }
            let qu = vec2<u32>(q);
            let dq = textureLoad(depth, qu, 0).r;
            if (dq <= 0.0 || channel_to_id(textureLoad(color, qu, 0).a) != material) {
                continue;
            }
            // Follow the surface: across a depth step of the reach, fall back to the centre.
            let zq = -view_position(camera, qu, dq).z;
            let step = clamp(abs(zq - z) / max(params.width, 1e-6), 0.0, 1.0);
            // Each tap stands for the band of offsets around it (spacing grows as t).
            let w = g * (2.0 * t / n) * extent;
            for (var k = 0u; k < SOURCES; k++) {
                sum[k] += mix(load_source(k, qu), center[k], step) * w;
            }
            weights += w;
        }
    }
    for (var k = 0u; k < SOURCES; k++) {
        store(k, pixel, min(sum[k] / weights, vec3<f32>(65000.0)));
    }
}
