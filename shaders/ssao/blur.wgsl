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
// brings to the full-size output. Never with PACKED or COMBINE. An 8x8
// workgroup's taps along the axis overlap: each half texel's surface (its
// view distance, its normal as read) and value are read once into
// workgroup memory, for the workgroup's 8 texels along the axis and
// HALF_APRON on each side, and every tap weighs them from there with the
// same arithmetic as half_blur_tap. A half-width beyond HALF_APRON (none
// the node pins allow) taps the textures as before.
#import spreadlight::camera::Camera
#ifdef PACKED
#import spreadlight::screen::{RayParams, separable_blur, packed_blur_tap, surface_normal, NO_SURFACE}
#else
#import spreadlight::packing::safe_normalize
#ifdef HALF
#import spreadlight::screen::{RayParams, view_position, separable_blur_half, half_blur_tap, tap_weight, BlurTap}
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

#ifdef HALF
// The largest half-width in half texels: Blur Radius 16 (its pins' limit,
// crates/render/src/ssao/mod.rs) is 8.
const HALF_APRON: i32 = 8;
// Along the axis the workgroup's 8 and HALF_APRON each side; across it 8.
const HALF_ROW: i32 = 24;
const HALF_ENTRIES: u32 = 192u;
// A half texel's surface as half_blur_tap reads it: the normal as read and
// the view distance (xyz, w), and its value and what it is (x; y: 0 off
// the image, 1 on the background, 2 a surface).
var<workgroup> half_surface: array<vec4<f32>, 192>;
var<workgroup> half_value: array<vec2<f32>, 192>;

// Entry `e`'s half texel: row e / HALF_ROW across the axis, column along
// it from HALF_APRON before the workgroup's first texel.
fn half_entry_texel(origin: vec2<i32>, axis: vec2<i32>, e: i32) -> vec2<i32> {
    let along = e % HALF_ROW - HALF_APRON;
    let across = e / HALF_ROW;
    return origin + axis * along + (vec2<i32>(1) - axis) * across;
}

// Reads the workgroup's entries: what half_blur_tap reads of each.
fn load_half_entries(origin: vec2<i32>, axis: vec2<i32>, lane: u32, size: vec2<u32>) {
    for (var e = lane; e < HALF_ENTRIES; e += 64u) {
        let t = half_entry_texel(origin, axis, i32(e));
        let q = t * 2;
        var surface = vec4<f32>(0.0);
        var value = vec2<f32>(0.0, 0.0);
        if (all(t >= vec2<i32>(0)) && all(q < vec2<i32>(size))) {
            let qu = vec2<u32>(q);
            let dq = textureLoad(depth, qu, 0).r;
            value = vec2<f32>(textureLoad(source, vec2<u32>(t), 0).r, 1.0);
            if (dq > 0.0) {
                surface = vec4<f32>(textureLoad(normals, qu, 0).xyz, -view_position(camera, qu, dq).z);
                value.y = 2.0;
            }
        }
        half_surface[e] = surface;
        half_value[e] = value;
    }
}
#endif

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>,
#ifdef HALF
        @builtin(local_invocation_id) local: vec3<u32>,
        @builtin(local_invocation_index) lane: u32,
        @builtin(workgroup_id) group: vec3<u32>,
#endif
        ) {
    let size = vec2<u32>(camera.size.xy);
#ifdef HALF
#ifdef VERTICAL
    let axis = vec2<i32>(0, 1);
#else
    let axis = vec2<i32>(1, 0);
#endif
    // Every thread reads its share before any leaves: the barrier is the
    // whole workgroup's.
    let cached = i32((params.blur_radius + 1u) / 2u) <= HALF_APRON;
    let origin = vec2<i32>(group.xy * 8u);
    if (cached) {
        load_half_entries(origin, axis, lane, size);
    }
    workgroupBarrier();
    if (id.x >= (size.x + 1u) / 2u || id.y >= (size.y + 1u) / 2u) {
        return;
    }
    // The half texel, and the full pixel it stands for; its entry's place.
    let texel = id.xy;
    let pixel = id.xy * 2u;
    let own = dot(vec2<i32>(local.xy), axis) + HALF_APRON + dot(vec2<i32>(local.xy), vec2<i32>(1) - axis) * HALF_ROW;
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
#ifndef HALF
#ifdef VERTICAL
        let axis = vec2<i32>(0, 1);
#else
        let axis = vec2<i32>(1, 0);
#endif
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
            var tap: BlurTap;
            var s: f32;
            if (cached) {
                // half_blur_tap's weight from the entry's surface.
                let entry = own + o;
                let value = half_value[entry];
                tap.valid = value.y > 1.5;
                if (tap.valid) {
                    let surface = half_surface[entry];
                    let nq = safe_normalize(surface.xyz, n0);
                    tap.weight = tap_weight(o, blur.spread, surface.w - blur.centre_distance, blur.reach, dot(n0, nq));
                }
                s = value.x;
            } else {
                tap = half_blur_tap(camera, depth, normals, blur, texel, axis, o, size);
                if (tap.valid) {
                    s = textureLoad(source, tap.pixel, 0).r;
                }
            }
#else
            let tap = blur_tap(camera, depth, normals, blur, pixel, axis, o, size);
#endif
#endif
            if (!tap.valid) {
                continue;
            }
#ifndef HALF
            let s = textureLoad(source, tap.pixel, 0).r;
#endif
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
