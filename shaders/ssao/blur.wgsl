// AO's depth- and normal-aware separable blur: a Gaussian of half-width
// `blur_radius` whose taps lose weight with view-distance difference (3%
// of the distance falls off by e) and normal difference, so occlusion does
// not bleed across silhouettes. Horizontal by default, VERTICAL the second
// pass; the vertical pass writes the RGBA result and, with COMBINE,
// multiplies another AO in. Half-width 0 is a copy.
// PACKED: each tap's view distance and normal come from the G-buffer's
// packed surface (one RG32Uint read, crates/render/src/packed_surface)
// instead of depth, normals and an inverse projection.
// HALF (AO's half-resolution chain, crates/render/src/resolution.rs): one
// thread per half texel, which stands for full pixel 2h; the centre and
// every tap read the full G-buffer at their own full pixel, the taps two
// full pixels apart (screen.wgsl's separable_blur_half, half_blur_tap), and
// both passes write R32 at half size, which resolution/upsample.wgsl's AO
// brings to the full-size output. Never with PACKED or COMBINE.
#import spreadlight::camera::Camera
#ifdef PACKED
#import spreadlight::screen::{RayParams, separable_blur, packed_blur_tap, surface_normal, NO_SURFACE}
#else
#import spreadlight::packing::safe_normalize
#ifdef HALF
#import spreadlight::screen::{RayParams, view_position, separable_blur_half, half_blur_tap}
#else
#import spreadlight::screen::{RayParams, view_position, separable_blur, blur_tap}
#endif
#endif

@group(0) @binding(0) var<uniform> camera: Camera;
@group(0) @binding(1) var<uniform> params: RayParams;
@group(0) @binding(2) var source: texture_2d<f32>;
#ifdef PACKED
@group(0) @binding(3) var surface: texture_2d<u32>;
#else
@group(0) @binding(3) var depth: texture_2d<f32>;
@group(0) @binding(4) var normals: texture_2d<f32>;
#endif
#ifdef HALF
@group(0) @binding(5) var output: texture_storage_2d<r32float, write>;
#else
#ifdef VERTICAL
@group(0) @binding(5) var output: texture_storage_2d<rgba16float, write>;
#else
@group(0) @binding(5) var output: texture_storage_2d<r32float, write>;
#endif
#endif
#ifdef COMBINE
@group(0) @binding(6) var combine: texture_2d<f32>;
#endif

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = vec2<u32>(camera.size.xy);
#ifdef HALF
    if (id.x >= (size.x + 1u) / 2u || id.y >= (size.y + 1u) / 2u) {
        return;
    }
    // The half texel, and the full pixel it stands for.
    let texel = id.xy;
    let pixel = id.xy * 2u;
#else
    if (id.x >= size.x || id.y >= size.y) {
        return;
    }
    let pixel = id.xy;
    let texel = pixel;
#endif
    var v = 1.0;
#ifdef PACKED
    let centre = textureLoad(surface, pixel, 0).xy;
    if (centre.x != NO_SURFACE) {
        let z0 = bitcast<f32>(centre.x);
        let n0 = surface_normal(centre.y, vec3<f32>(0.0, 0.0, 1.0));
#else
    let d0 = textureLoad(depth, pixel, 0).r;
    if (d0 > 0.0) {
        let z0 = -view_position(camera, pixel, d0).z;
        let n0 = safe_normalize(textureLoad(normals, pixel, 0).xyz, vec3<f32>(0.0, 0.0, 1.0));
#endif
#ifdef VERTICAL
        let axis = vec2<i32>(0, 1);
#else
        let axis = vec2<i32>(1, 0);
#endif
#ifdef HALF
        let blur = separable_blur_half(params.blur_radius, z0, n0);
#else
        let blur = separable_blur(params.blur_radius, z0, n0);
#endif
        var sum = 0.0;
        var weights = 0.0;
        for (var o = -blur.radius; o <= blur.radius; o++) {
#ifdef PACKED
            let tap = packed_blur_tap(surface, blur, pixel, axis, o, size);
#else
#ifdef HALF
            let tap = half_blur_tap(camera, depth, normals, blur, texel, axis, o, size);
#else
            let tap = blur_tap(camera, depth, normals, blur, pixel, axis, o, size);
#endif
#endif
            if (!tap.valid) {
                continue;
            }
            let s = textureLoad(source, tap.pixel, 0).r;
            if (!(abs(s) <= 1e30)) {
                continue;
            }
            sum += tap.weight * clamp(s, 0.0, 1.0);
            weights += tap.weight;
        }
        if (weights > 1e-6) {
            v = sum / weights;
        } else {
            let s = textureLoad(source, texel, 0).r;
            v = select(1.0, clamp(s, 0.0, 1.0), abs(s) <= 1e30);
        }
    }
#ifdef COMBINE
    let other = textureLoad(combine, pixel, 0).r;
    v *= select(1.0, clamp(other, 0.0, 1.0), abs(other) <= 1e30);
#endif
    v = clamp(v, 0.0, 1.0);
#ifdef HALF
    textureStore(output, texel, vec4<f32>(v, 0.0, 0.0, 0.0));
#else
#ifdef VERTICAL
    textureStore(output, pixel, vec4<f32>(v, v, v, 1.0));
#else
    textureStore(output, pixel, vec4<f32>(v, 0.0, 0.0, 0.0));
#endif
#endif
}
