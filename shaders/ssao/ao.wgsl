// Raw ambient occlusion: visibility 0..1 per pixel (1 where depth is empty).
// Default: Emeshe's stochastic wide-range AO — `samples` rays in a
// cosine-weighted hemisphere about the normal, each marched `steps` times;
// a ray is blocked where it passes behind the depth buffer's surface by
// less than `radius` (a surface farther in front is a separate object, not
// an occluder). The unblocked share is ray-cast AO's estimate.
// SAO: McGuire et al. 2012 — a spiral of taps over a view-depth mip chain,
// obscurance sum(max(0, v.n - bias) / (v.v + eps) * falloff).
// HBAO: Bavoil 2008 — `samples` screen directions, `steps` taps each; with
// the highest horizon at elevation e above the tangent plane, sin^2(e) is
// the cosine-weighted occluded share of that slice.
// The rotation (interleaved gradient noise) changes every frame, so the
// temporal pass converges to many more samples than one frame takes.
// HALF: one pixel per 2x2 block (see main), for the depth-aware upsample.
// TEMPORAL: the estimate is blended with last frame's here
// (shaders/lib/ao_history.wgsl) and the history texel written, so
// accumulation costs no pass of its own; with HALF into the half-size
// history at the half texel, blended at the full pixel it stands for.
// PACKED_Z (the plain estimator): the rays read the packed surface's view z
// (crates/render/src/packed_surface), four steps' reads at a time
// (screen.wgsl's march_packed): the same pixels as `march`.
#import spreadlight::camera::Camera
#import spreadlight::packing::safe_normalize
#import spreadlight::screen::{RayParams, view_position, interleaved_gradient_noise}
#ifdef TEMPORAL
#import spreadlight::ao_history::{accumulate, SKY}
#endif
#ifdef SAO
#import spreadlight::screen::view_position_at_distance
#else
#ifndef HBAO
#import spreadlight::screen::{tangent_frame, cosine_direction, march}
#ifdef PACKED_Z
#import spreadlight::screen::march_packed
#endif
#endif
#endif

@group(0) @binding(0) var<uniform> camera: Camera;
@group(0) @binding(1) var<uniform> params: RayParams;
@group(0) @binding(2) var depth: texture_2d<f32>;
@group(0) @binding(3) var normals: texture_2d<f32>;
#ifdef PACKED_Z
@group(0) @binding(13) var view_z: texture_2d<f32>;
#endif
#ifdef TEMPORAL
// The estimate blended with last frame's in this pass (at the output's
// size, full or half): the history texel (shaders/lib/ao_history.wgsl), not the raw visibility.
@group(0) @binding(4) var history: texture_storage_2d<rgba16float, write>;
@group(0) @binding(10) var velocity_uv: texture_2d<f32>;
@group(0) @binding(11) var previous: texture_2d<f32>;
// x: 1 when the history was created this frame and holds nothing.
@group(0) @binding(12) var<uniform> fresh: vec4<u32>;
#else
@group(0) @binding(4) var output: texture_storage_2d<r32float, write>;
#endif
#ifdef SAO
@group(0) @binding(5) var z0: texture_2d<f32>;
@group(0) @binding(6) var z1: texture_2d<f32>;
@group(0) @binding(7) var z2: texture_2d<f32>;
@group(0) @binding(8) var z3: texture_2d<f32>;
@group(0) @binding(9) var z4: texture_2d<f32>;
#endif

const TAU: f32 = 6.283185307;

// Pixels per world unit at view distance 1 (vertical).
fn projection_scale() -> f32 {
    return camera.projection[1][1] * camera.size.y * 0.5;
}

#ifdef SAO
fn view_distance(level: i32, tap: vec2<i32>) -> f32 {
    let p = vec2<u32>(tap >> vec2<u32>(u32(level)));
    switch level {
        case 0: { return textureLoad(z0, min(p, textureDimensions(z0) - 1u), 0).r; }
        case 1: { return textureLoad(z1, min(p, textureDimensions(z1) - 1u), 0).r; }
        case 2: { return textureLoad(z2, min(p, textureDimensions(z2) - 1u), 0).r; }
        case 3: { return textureLoad(z3, min(p, textureDimensions(z3) - 1u), 0).r; }
        default: { return textureLoad(z4, min(p, textureDimensions(z4) - 1u), 0).r; }
    }
}

fn occlusion(pixel: vec2<u32>, p: vec3<f32>, n: vec3<f32>) -> f32 {
    let r = params.radius;
    let r2 = r * r;
    let screen_radius = min(r * projection_scale() / max(-p.z, 1e-6), 4096.0);
    let rotation = interleaved_gradient_noise(vec2<f32>(pixel), params.frame) * TAU;
    let size = vec2<i32>(camera.size.xy);
    var sum = 0.0;
    for (var i = 0u; i < params.samples; i++) {
        let alpha = (f32(i) + 0.5) / f32(params.samples);
        // 7 turns of the spiral over the taps (McGuire's choice for few taps).
        let angle = alpha * 7.0 * TAU + rotation;
        let h = screen_radius * alpha;
        let tap = vec2<i32>(floor(vec2<f32>(pixel) + 0.5 + vec2<f32>(cos(angle), sin(angle)) * h));
        if (any(tap < vec2<i32>(0)) || any(tap >= size)) {
            continue;
        }
        // Far taps read coarse levels: 2^3 pixels is the finest spacing that
        // still touches neighbouring texels of one cache line.
        let level = clamp(i32(floor(log2(max(h, 1.0)))) - 3, 0, 4);
        let z = view_distance(level, tap);
        if (z <= 0.0) {
            continue;
        }
        let q = view_position_at_distance(camera, vec2<f32>(tap) + 0.5, z);
        let v = q - p;
        let vv = dot(v, v);
        let vn = dot(v, n);
        let f = max(r2 - vv, 0.0);
        sum += f * f * f * max((vn - params.bias) / (vv + 0.01 * r2), 0.0);
    }
    // 5 / r^6: McGuire's normalization of the falloff f^3 (f <= r^2).
    let r6 = max(r2 * r2 * r2, 1e-30);
    return max(0.0, 1.0 - sum * 5.0 / (r6 * f32(params.samples)));
}
#else
#ifdef HBAO
fn occlusion(pixel: vec2<u32>, p: vec3<f32>, n: vec3<f32>) -> f32 {
    let r2 = params.radius * params.radius;
    let screen_radius = min(params.radius * projection_scale() / max(-p.z, 1e-6), 1024.0);
    if (screen_radius < 1.0) {
        return 1.0;
    }
    let noise = interleaved_gradient_noise(vec2<f32>(pixel), params.frame);
    let jitter = interleaved_gradient_noise(vec2<f32>(pixel.yx) + 13.0, params.frame);
    let size = vec2<i32>(camera.size.xy);
    let step = screen_radius / f32(params.steps);
    var occluded = 0.0;
    for (var i = 0u; i < params.samples; i++) {
        let angle = TAU * (f32(i) + noise) / f32(params.samples);
        let dir = vec2<f32>(cos(angle), sin(angle));
        var highest = 0.0;
        for (var k = 0u; k < params.steps; k++) {
            let offset = dir * max(step * (f32(k) + jitter), 1.0);
            let tap = vec2<i32>(floor(vec2<f32>(pixel) + 0.5 + offset));
            if (any(tap < vec2<i32>(0)) || any(tap >= size)) {
                break;
            }
            let d = textureLoad(depth, vec2<u32>(tap), 0).r;
            if (d <= 0.0) {
                continue;
            }
            let v = view_position(camera, vec2<u32>(tap), d) - p;
            let l2 = dot(v, v);
            if (l2 >= r2 || l2 < 1e-12) {
                continue;
            }
            // Sine of the elevation above the tangent plane, fading out over
            // the outer half of the radius (no hard edge where occluders leave it).
            let elevation = dot(v, n) * inverseSqrt(l2) - params.bias / params.radius;
            // sqrt: the falloff weighs the squared share below, not the sine twice.
            highest = max(highest, elevation * sqrt(clamp(2.0 - 2.0 * l2 / r2, 0.0, 1.0)));
        }
        // Cosine-weighted, a slice whose horizon stands at elevation e above the
        // tangent plane is occluded by sin^2(e) (the integral of cos x sin x).
        let e = clamp(highest, 0.0, 1.0);
        occluded += e * e;
    }
    return 1.0 - occluded / f32(params.samples);
}
#else
fn occlusion(pixel: vec2<u32>, p: vec3<f32>, n: vec3<f32>) -> f32 {
    let frame = tangent_frame(n);
    let noise = interleaved_gradient_noise(vec2<f32>(pixel), params.frame);
    let jitter = interleaved_gradient_noise(vec2<f32>(pixel.yx) + 29.0, params.frame);
    let origin = p + n * params.bias;
    var blocked = 0u;
    for (var i = 0u; i < params.samples; i++) {
        let dir = cosine_direction(frame, i, params.samples, noise);
#ifdef PACKED_Z
        let hit = march_packed(camera, view_z, origin, dir, params.radius, params.steps, jitter, params.bias);
#else
        let hit = march(camera, depth, origin, dir, params.radius, params.steps, jitter, params.bias);
#endif
        if (hit.x >= 0) {
            blocked++;
        }
    }
    return 1.0 - f32(blocked) / f32(params.samples);
}
#endif
#endif

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = vec2<u32>(camera.size.xy);
#ifdef HALF
    // Half resolution: this thread is the 2x2 block's top-left pixel, computed
    // as at full resolution and stored in the half-size output
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
    let d = textureLoad(depth, pixel, 0).r;
    var visibility = 1.0;
    let p = view_position(camera, pixel, d);
    let n_view = safe_normalize(textureLoad(normals, pixel, 0).xyz, vec3<f32>(0.0, 0.0, 1.0));
    if (d > 0.0 && params.radius > 0.0) {
        var n = n_view;
        // A normal facing away from the eye (a back face, or a bad normal):
        // its hemisphere would lie behind the surface seen; turn it round.
        if (dot(n, -p) < 0.0) {
            n = -n;
        }
        visibility = occlusion(pixel, p, n);
    }
    visibility = pow(clamp(visibility, 0.0, 1.0), params.intensity);
    if (!(visibility >= 0.0 && visibility <= 1.0)) {
        visibility = 1.0;
    }
#ifdef TEMPORAL
    if (d <= 0.0) {
        textureStore(history, id.xy, SKY);
        return;
    }
    let reuse = params.reset == 0u && fresh.x == 0u;
    textureStore(history, id.xy, accumulate(camera, visibility, pixel, p, n_view, velocity_uv, previous, reuse, params.blend));
#else
    textureStore(output, id.xy, vec4<f32>(visibility, 0.0, 0.0, 0.0));
#endif
}
