// AO's depth- and normal-aware separable blur: a Gaussian of half-width
// `blur_radius` whose taps lose weight with view-distance difference (3%
// of the distance falls off by e) and normal difference, so occlusion does
// not bleed across silhouettes. Horizontal by default, VERTICAL the second
// pass; the vertical pass writes the RGBA result and, with COMBINE,
// multiplies another AO in. Half-width 0 is a copy.
#import spreadlight::camera::Camera
#import spreadlight::packing::safe_normalize
#import spreadlight::screen::{RayParams, view_position, surface_similarity}

@group(0) @binding(0) var<uniform> camera: Camera;
@group(0) @binding(1) var<uniform> params: RayParams;
@group(0) @binding(2) var source: texture_2d<f32>;
@group(0) @binding(3) var depth: texture_2d<f32>;
@group(0) @binding(4) var normals: texture_2d<f32>;
#ifdef VERTICAL
@group(0) @binding(5) var output: texture_storage_2d<rgba16float, write>;
#else
@group(0) @binding(5) var output: texture_storage_2d<r32float, write>;
#endif
#ifdef COMBINE
@group(0) @binding(6) var combine: texture_2d<f32>;
#endif

// A workgroup blurs a run of LINE pixels along the axis, LINES of them
// across it. Each pixel's depth, view distance, normal and value are loaded
// once into workgroup memory, with the run's apron of up to MAX_RADIUS
// pixels each side, and every tap reads them there: a tap used to fetch
// three texels and project a depth, and the pass was bound by texture
// fetches (27 a pixel at half-width 4). The sums are the same as tapping
// the textures (same values, same order).
const LINE: u32 = 64u;
const LINES: u32 = 4u;
// BlurSettings clamps the half-width to this (occlusion/mod.rs).
const MAX_RADIUS: u32 = 16u;
const SPAN: u32 = LINE + 2u * MAX_RADIUS;
// Normal (xyz, as stored) and view distance (w).
var<workgroup> tile_normal_z: array<vec4<f32>, SPAN * LINES>;
// Reversed-Z depth (x; 0: background or outside the image) and the value (y).
var<workgroup> tile_depth_value: array<vec2<f32>, SPAN * LINES>;

// Along the axis, across it: the pixel of tile coordinate (along, across).
fn tile_pixel(origin: vec2<i32>, along: i32, across: i32) -> vec2<i32> {
#ifdef VERTICAL
    return origin + vec2<i32>(across, along);
#else
    return origin + vec2<i32>(along, across);
#endif
}

#ifdef VERTICAL
@compute @workgroup_size(4, 64)
#else
@compute @workgroup_size(64, 4)
#endif
fn main(@builtin(workgroup_id) wid: vec3<u32>, @builtin(local_invocation_index) lane: u32) {
    let size = vec2<u32>(camera.size.xy);
    let r = i32(min(params.blur_radius, MAX_RADIUS));
#ifdef VERTICAL
    let origin = vec2<i32>(i32(wid.x * LINES), i32(wid.y * LINE)) - vec2<i32>(0, i32(MAX_RADIUS));
    let axis = vec2<i32>(0, 1);
#else
    let origin = vec2<i32>(i32(wid.x * LINE), i32(wid.y * LINES)) - vec2<i32>(i32(MAX_RADIUS), 0);
    let axis = vec2<i32>(1, 0);
#endif
    // Fill the tile (SPAN x LINES), the apron included.
    for (var k = lane; k < SPAN * LINES; k += LINE * LINES) {
        let along = i32(k % SPAN);
        let across = i32(k / SPAN);
        let q = tile_pixel(origin, along, across);
        var normal_z = vec4<f32>(0.0);
        var depth_value = vec2<f32>(0.0);
        if (all(q >= vec2<i32>(0)) && all(q < vec2<i32>(size))) {
            let qu = vec2<u32>(q);
            let dq = textureLoad(depth, qu, 0).r;
            depth_value = vec2<f32>(dq, textureLoad(source, qu, 0).r);
            if (dq > 0.0) {
                normal_z = vec4<f32>(textureLoad(normals, qu, 0).xyz, -view_position(camera, qu, dq).z);
            }
        }
        tile_normal_z[k] = normal_z;
        tile_depth_value[k] = depth_value;
    }
    workgroupBarrier();
    // This lane's pixel: lanes run along the axis first.
    let along0 = i32(lane % LINE) + i32(MAX_RADIUS);
    let across = i32(lane / LINE);
    let q0 = tile_pixel(origin, along0, across);
    if (any(q0 >= vec2<i32>(size))) {
        return;
    }
    let pixel = vec2<u32>(q0);
    let center = u32(across) * SPAN + u32(along0);
    let d0 = tile_depth_value[center].x;
    var v = 1.0;
    if (d0 > 0.0) {
        let z0 = tile_normal_z[center].w;
        let n0 = safe_normalize(tile_normal_z[center].xyz, vec3<f32>(0.0, 0.0, 1.0));
        let sigma = max(f32(r), 1.0) * 0.5;
        var sum = 0.0;
        var weights = 0.0;
        for (var o = -r; o <= r; o++) {
            let q = vec2<i32>(pixel) + axis * o;
            if (any(q < vec2<i32>(0)) || any(q >= vec2<i32>(size))) {
                continue;
            }
            let t = u32(i32(center) + o);
            let dq = tile_depth_value[t].x;
            if (dq <= 0.0) {
                continue;
            }
            let zq = tile_normal_z[t].w;
            let nq = safe_normalize(tile_normal_z[t].xyz, n0);
            let s = tile_depth_value[t].y;
            if (!(abs(s) <= 1e30)) {
                continue;
            }
            let w = exp(-f32(o * o) / (2.0 * sigma * sigma))
                * surface_similarity(zq, z0, nq, n0, 0.03);
            sum += w * clamp(s, 0.0, 1.0);
            weights += w;
        }
        if (weights > 1e-6) {
            v = sum / weights;
        } else {
            let s = tile_depth_value[center].y;
            v = select(1.0, clamp(s, 0.0, 1.0), abs(s) <= 1e30);
        }
    }
#ifdef COMBINE
    let other = textureLoad(combine, pixel, 0).r;
    v *= select(1.0, clamp(other, 0.0, 1.0), abs(other) <= 1e30);
#endif
    v = clamp(v, 0.0, 1.0);
#ifdef VERTICAL
    textureStore(output, pixel, vec4<f32>(v, v, v, 1.0));
#else
    textureStore(output, pixel, vec4<f32>(v, 0.0, 0.0, 0.0));
#endif
}
