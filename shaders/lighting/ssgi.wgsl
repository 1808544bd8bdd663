// SSGI: one bounce of diffuse light from what the screen sees. Default
// (raw): `samples` rays per pixel in a cosine-weighted hemisphere about the
// normal, marched `steps` times like stochastic AO; where a ray passes
// behind a surface within `radius`, that surface's lit colour (the source
// image) is light arriving from it. With cosine-weighted rays, the mean of
// what they bring is the irradiance over pi: the outgoing radiance per unit
// albedo, which CompositeLight multiplies by albedo. Alpha carries the share
// of rays that escaped: the environment's diffuse light (the `Ambient`
// input) reaches the surface only through those, so the resolve adds
// ambient x escaped share — AO for the environment light, with the bounce
// filling in what it blocks (no double counting of occlusion).
// TEMPORAL: last frame's result (RGBA: bounce, escaped share) reprojected
// with the G-buffer velocity and blended in where the stored view distance
// (a second history, `distance`) matches within 5%; non-finite history is
// never used. Alone it blends `source` (an upsampled half-resolution
// gather); with GATHER it gathers this pixel first, in the same pass, so a
// full-resolution gather writes no raw target and costs no second pass.
// BLUR: a depth-aware separable blur of all four channels along `axis`;
// with AMBIENT (the last pass) the ambient is added. With PACKED the taps
// read the G-buffer's packed surface (view distance and normal in one
// RG32Uint texel, crates/render/src/packed_surface) instead of depth and
// normals (PACKED comes with BLUR alone). PACKED_Z (a gather): the rays
// read the packed surface's view z, four steps' reads at a time
// (screen.wgsl's march_packed): the same pixels as `march`.
// HALF: one thread per half texel, which stands for full pixel 2h (its
// depth, normal and velocity: crates/render/src/resolution.rs). Alone, the
// gather at half resolution; with TEMPORAL (never GATHER), the blend into a
// half-size history; with BLUR (never AMBIENT or PACKED), a blur pass of the
// half-size image whose taps read the full G-buffer two pixels apart
// (screen.wgsl's separable_blur_half, half_blur_tap). The half chain's last
// step, resolution/upsample.wgsl, adds the ambient at full size.
#import spreadlight::camera::Camera
#import spreadlight::packing::safe_normalize
#import spreadlight::screen::{RayParams, view_position}
#ifdef BLUR
#ifdef HALF
#import spreadlight::screen::{separable_blur_half, half_blur_tap}
#else
#import spreadlight::screen::{separable_blur, blur_tap}
#endif
#ifdef PACKED
#import spreadlight::screen::{packed_blur_tap, surface_normal, NO_SURFACE}
#endif
#endif
#ifndef BLUR
#import spreadlight::screen::{tangent_frame, interleaved_gradient_noise, cosine_direction, march}
#ifdef PACKED_Z
#import spreadlight::screen::march_packed
#endif
#endif

// Per pass: which way the blur runs.
struct Axis {
    axis: vec2<i32>,
    spare: vec2<i32>,
}

@group(0) @binding(0) var<uniform> camera: Camera;
@group(0) @binding(1) var<uniform> params: RayParams;
#ifdef PACKED
@group(0) @binding(2) var surface: texture_2d<u32>;
#else
@group(0) @binding(2) var depth: texture_2d<f32>;
@group(0) @binding(3) var normals: texture_2d<f32>;
#endif
@group(0) @binding(4) var source: texture_2d<f32>;
@group(0) @binding(5) var output: texture_storage_2d<rgba16float, write>;
#ifdef PACKED_Z
@group(0) @binding(11) var view_z: texture_2d<f32>;
#endif
#ifdef TEMPORAL
@group(0) @binding(6) var velocity_uv: texture_2d<f32>;
@group(0) @binding(7) var previous: texture_2d<f32>;
@group(0) @binding(9) var previous_distance: texture_2d<f32>;
@group(0) @binding(10) var distance: texture_storage_2d<r32float, write>;
// x: 1 when the history was created this frame and holds nothing.
@group(0) @binding(8) var<uniform> fresh: vec4<u32>;
#endif
#ifdef BLUR
@group(0) @binding(6) var<uniform> axis: Axis;
#ifdef AMBIENT
@group(0) @binding(7) var ambient: texture_2d<f32>;
#endif
#endif

// Finite, non-negative, below half-float overflow; anything else is black.
fn clean(v: vec3<f32>) -> vec3<f32> {
    return select(vec3<f32>(0.0), min(v, vec3<f32>(65000.0)), v >= vec3<f32>(0.0) & v <= vec3<f32>(3e38));
}

// A (bounce, escaped share) texel made safe: share in 0..1, 1 when unknown.
fn clean_gi(v: vec4<f32>) -> vec4<f32> {
    return vec4<f32>(clean(v.rgb), select(1.0, clamp(v.a, 0.0, 1.0), abs(v.a) <= 1.0));
}

#ifdef TEMPORAL
// `raw` blended with last frame's result where that saw the same surface;
// `pixel` is the full pixel, `texel` where the history stores it (the same
// but at half resolution, where the history is half size).
fn accumulate(raw: vec4<f32>, pixel: vec2<u32>, texel: vec2<u32>, p: vec3<f32>) -> vec4<f32> {
    var gi = raw;
    let uv = (vec2<f32>(pixel) + 0.5) * camera.size.zw;
    let before = uv - textureLoad(velocity_uv, pixel, 0).xy;
    if (params.reset == 0u && fresh.x == 0u && all(before >= vec2<f32>(0.0)) && all(before < vec2<f32>(1.0))) {
        let history_size = textureDimensions(previous);
        let at = min(vec2<u32>(before * vec2<f32>(history_size)), history_size - 1u);
        let h = textureLoad(previous, at, 0);
        let last = textureLoad(previous_distance, at, 0).r;
        let world = camera.view_inverse * vec4<f32>(p, 1.0);
        let expected = (camera.previous_view_projection * world).w;
        if (all(abs(h) <= vec4<f32>(65000.0)) && last > 0.0 && last < 1e30 && abs(last - expected) <= 0.05 * expected + 1e-3) {
            gi = mix(gi, clean_gi(h), params.blend);
        }
    }
    textureStore(distance, texel, vec4<f32>(min(-p.z, 1e30), 0.0, 0.0, 0.0));
    return gi;
}

fn resolve(pixel: vec2<u32>, texel: vec2<u32>, size: vec2<u32>, p: vec3<f32>) -> vec4<f32> {
#ifdef GATHER
    return accumulate(gather(pixel, p), pixel, texel, p);
#else
    return accumulate(clean_gi(textureLoad(source, texel, 0)), pixel, texel, p);
#endif
}
#else
#ifdef BLUR
// The blur about a pixel at view distance `z0` with unit normal `n0`
// (`texel`: where the source holds it, the pixel itself but at HALF).
fn blur_at(pixel: vec2<u32>, texel: vec2<u32>, size: vec2<u32>, z0: f32, n0: vec3<f32>) -> vec4<f32> {
#ifdef HALF
    let blur = separable_blur_half(params.blur_radius, z0, n0);
#else
    let blur = separable_blur(params.blur_radius, z0, n0);
#endif
    var sum = vec4<f32>(0.0);
    var weights = 0.0;
    for (var o = -blur.radius; o <= blur.radius; o++) {
#ifdef PACKED
        let tap = packed_blur_tap(surface, blur, pixel, axis.axis, o, size);
#else
#ifdef HALF
        let tap = half_blur_tap(camera, depth, normals, blur, texel, axis.axis, o, size);
#else
        let tap = blur_tap(camera, depth, normals, blur, pixel, axis.axis, o, size);
#endif
#endif
        if (!tap.valid) {
            continue;
        }
        sum += tap.weight * clean_gi(textureLoad(source, tap.pixel, 0));
        weights += tap.weight;
    }
    var gi = clean_gi(textureLoad(source, texel, 0));
    if (weights > 1e-6) {
        gi = sum / weights;
    }
#ifdef AMBIENT
    // The environment's light arrives only along the rays that escaped.
    return vec4<f32>(min(gi.rgb + clean(textureLoad(ambient, pixel, 0).rgb) * gi.a, vec3<f32>(65000.0)), 1.0);
#else
    return gi;
#endif
}

#ifndef PACKED
fn resolve(pixel: vec2<u32>, texel: vec2<u32>, size: vec2<u32>, p: vec3<f32>) -> vec4<f32> {
    let n0 = safe_normalize(textureLoad(normals, pixel, 0).xyz, vec3<f32>(0.0, 0.0, 1.0));
    return blur_at(pixel, texel, size, -p.z, n0);
}
#endif
#else
fn resolve(pixel: vec2<u32>, texel: vec2<u32>, size: vec2<u32>, p: vec3<f32>) -> vec4<f32> {
    return gather(pixel, p);
}
#endif
#endif

#ifndef BLUR
// The bounce at this pixel: `samples` cosine-weighted rays marched over the
// depth, with the share of rays that escaped.
fn gather(pixel: vec2<u32>, p: vec3<f32>) -> vec4<f32> {
    var n = safe_normalize(textureLoad(normals, pixel, 0).xyz, vec3<f32>(0.0, 0.0, 1.0));
    if (dot(n, -p) < 0.0) {
        n = -n;
    }
    let frame = tangent_frame(n);
    let noise = interleaved_gradient_noise(vec2<f32>(pixel), params.frame);
    let jitter = interleaved_gradient_noise(vec2<f32>(pixel.yx) + 29.0, params.frame);
    let origin = p + n * params.bias;
    var gathered = vec3<f32>(0.0);
    var escaped = 0u;
    for (var i = 0u; i < params.samples; i++) {
        let dir = cosine_direction(frame, i, params.samples, noise);
#ifdef PACKED_Z
        let hit = march_packed(camera, view_z, origin, dir, params.radius, params.steps, jitter, params.bias);
#else
        let hit = march(camera, depth, origin, dir, params.radius, params.steps, jitter, params.bias);
#endif
        if (hit.x >= 0) {
            gathered += clean(textureLoad(source, vec2<u32>(hit), 0).rgb);
        } else {
            escaped++;
        }
    }
    let n_samples = f32(params.samples);
    return vec4<f32>(min(gathered * params.intensity / n_samples, vec3<f32>(65000.0)), f32(escaped) / n_samples);
}
#endif

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = vec2<u32>(camera.size.xy);
#ifdef HALF
    // The gather at half resolution: this thread is the 2x2 block's top-left
    // pixel, computed as at full resolution and stored in the half-size output
    // (crates/render/src/resolution.rs upsamples it).
    if (id.x >= (size.x + 1u) / 2u || id.y >= (size.y + 1u) / 2u) {
        return;
    }
    let pixel = id.xy * 2u;
#else
    if (id.x >= size.x || id.y >= size.y) {
        return;
    }
    let pixel = id.xy;
#endif
#ifdef PACKED
    let centre = textureLoad(surface, pixel, 0).xy;
    let empty = centre.x == NO_SURFACE;
#else
    let d = textureLoad(depth, pixel, 0).r;
    let empty = d <= 0.0;
#endif
    if (empty || params.radius <= 0.0) {
#ifdef AMBIENT
        textureStore(output, id.xy, vec4<f32>(clean(textureLoad(ambient, id.xy, 0).rgb), 1.0));
#else
        // No bounce; every ray escapes.
        textureStore(output, id.xy, vec4<f32>(0.0, 0.0, 0.0, 1.0));
#endif
#ifdef TEMPORAL
        // No distance: never reused.
        textureStore(distance, id.xy, vec4<f32>(0.0));
#endif
        return;
    }
#ifdef PACKED
    textureStore(output, id.xy, blur_at(pixel, id.xy, size, bitcast<f32>(centre.x), surface_normal(centre.y, vec3<f32>(0.0, 0.0, 1.0))));
#else
    textureStore(output, id.xy, resolve(pixel, id.xy, size, view_position(camera, pixel, d)));
#endif
}
