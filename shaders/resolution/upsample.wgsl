// Depth-aware upsampling of a half-resolution result into the full-size
// target (crates/render/src/resolution). A pass run at half resolution
// (its shader's HALF feature) computes half texel h exactly as the full
// pass computes full pixel 2h: the same camera, the same full-size inputs,
// only a quarter of the pixels. So every half texel stands at a known full
// pixel whose depth and normal this pass can read.
//
// A full pixel p reads the (up to) four half texels around it. Each weighs
// bilinearly by where it stands (p on an even row and column IS a half
// texel and copies it exactly) times how alike its surface is to p's: view
// distance within about 2% (relative, so the test holds near and far) and
// normals alike. A texel across a silhouette weighs about nothing, so the
// foreground's value does not bleed onto the background or back. Where no
// texel is alike (a feature thinner than two pixels that no sample landed
// on) the texel of the nearest view distance is taken: nearest-depth
// upsampling. Depth-empty pixels (the sky) match only depth-empty texels.
//
// R32: the target is R32Float (AO's raw visibility), else RGBA16F.
// AO / AO_COMBINE (AO's half chain, whose temporal blend and blurs ran at
// half size): the source is the blurred R32 visibility and the target the
// RGBA16F output, grey with alpha 1, times another AO with AO_COMBINE: what
// ssao/blur.wgsl's VERTICAL (and COMBINE) pass writes at full resolution.
// AMBIENT (SSGI's half chain): the ambient light times the escaped share
// (alpha) is added to the bounce, alpha 1: what ssgi.wgsl's AMBIENT blur
// pass writes at full resolution.
// DETAIL (depth of field): the half result is a blur; where p is in focus
// (its circle of confusion under a pixel) the detail the half grid cannot
// hold comes back from the full image: image(p) minus the same weighted
// mix of the image at the texels' pixels, faded out as p's circle grows
// (gone at DETAIL_FADE pixels).
#import spreadlight::camera::Camera
#import spreadlight::packing::safe_normalize
#import spreadlight::screen::{view_position, surface_similarity}

@group(0) @binding(0) var<uniform> camera: Camera;
@group(0) @binding(1) var depth: texture_2d<f32>;
@group(0) @binding(2) var normals: texture_2d<f32>;
@group(0) @binding(3) var source: texture_2d<f32>;
#ifdef R32
@group(0) @binding(4) var output: texture_storage_2d<r32float, write>;
#else
@group(0) @binding(4) var output: texture_storage_2d<rgba16float, write>;
#endif
#ifdef AO_COMBINE
@group(0) @binding(5) var combine: texture_2d<f32>;
#endif
#ifdef AMBIENT
@group(0) @binding(5) var ambient: texture_2d<f32>;
#endif
#ifdef DETAIL
@group(0) @binding(5) var image: texture_2d<f32>;
// x: the signed circle-of-confusion radius in pixels (DOF's `coc` pass).
@group(0) @binding(6) var coc: texture_2d<f32>;
#endif

const HALF_MAX: f32 = 65000.0;
// Relative view-distance difference that lowers a texel's weight by e.
const DEPTH_FALLOFF: f32 = 0.02;
// DETAIL: the circle-of-confusion radius (pixels) where no detail comes back.
const DETAIL_FADE: f32 = 3.0;
// The gap of a depth-empty pixel against a surface: never alike.
const NO_MATCH: f32 = 1e30;

fn clean(v: vec4<f32>) -> vec4<f32> {
    let ok = (v == v) & (abs(v) < vec4<f32>(3.0e38));
    return clamp(select(vec4<f32>(0.0), v, ok), vec4<f32>(-HALF_MAX), vec4<f32>(HALF_MAX));
}

// View distance under a full pixel; 0 where depth is empty.
fn distance_at(pixel: vec2<u32>) -> f32 {
    let d = textureLoad(depth, pixel, 0).r;
    if (!(d > 0.0)) {
        return 0.0;
    }
    let z = -view_position(camera, pixel, d).z;
    return select(0.0, z, z > 0.0 && z < 3.0e38);
}

// A workgroup's 8x8 pixels read the same 5x5 half texels (each pixel the
// 2x2 around it), so the group loads them once: each texel's view distance,
// normal and source (and DETAIL's image at its pixel) go to workgroup memory
// in one read and one inverse projection each, where every pixel reading its
// four texels from the textures made 12 reads and 4 projections a pixel.
// The arithmetic on them is the per-pixel code's, in the same order.
const GROUP: u32 = 8u;
const SPAN: u32 = GROUP / 2u + 1u;
const TEXELS: u32 = SPAN * SPAN;

var<workgroup> texel_distance: array<f32, TEXELS>;
var<workgroup> texel_normal: array<vec3<f32>, TEXELS>;
var<workgroup> texel_source: array<vec4<f32>, TEXELS>;
#ifdef DETAIL
var<workgroup> texel_image: array<vec4<f32>, TEXELS>;
#endif

@compute @workgroup_size(8, 8)
fn main(
    @builtin(global_invocation_id) id: vec3<u32>,
    @builtin(workgroup_id) group: vec3<u32>,
    @builtin(local_invocation_index) lane: u32,
) {
    let size = vec2<u32>(camera.size.xy);
    let half_size = textureDimensions(source);
    // The group's first half texel: its pixels' texels are first..first+4.
    let first = group.xy * (GROUP / 2u);
    if (lane < TEXELS) {
        let h = min(first + vec2<u32>(lane % SPAN, lane / SPAN), half_size - 1u);
        let at = min(h * 2u, size - 1u);
        texel_distance[lane] = distance_at(at);
        texel_normal[lane] = textureLoad(normals, at, 0).xyz;
        texel_source[lane] = clean(textureLoad(source, h, 0));
#ifdef DETAIL
        texel_image[lane] = clean(textureLoad(image, at, 0));
#endif
    }
    workgroupBarrier();
    if (id.x >= size.x || id.y >= size.y) {
        return;
    }
    let pixel = id.xy;
    let z0 = distance_at(pixel);
    let n0 = safe_normalize(textureLoad(normals, pixel, 0).xyz, vec3<f32>(0.0, 0.0, 1.0));
    let base = pixel / 2u;
    // 0 on an even row or column (the texel itself), 0.5 between two texels.
    let f = vec2<f32>(pixel - base * 2u) * 0.5;
    let local = base - first;
    var sum = vec4<f32>(0.0);
    var weights = 0.0;
#ifdef DETAIL
    var image_sum = vec4<f32>(0.0);
#endif
    var nearest = local.y * SPAN + local.x;
    var nearest_gap = 3.0e38;
    for (var k = 0u; k < 4u; k++) {
        let o = vec2<u32>(k & 1u, k >> 1u);
        let t = (local.y + o.y) * SPAN + local.x + o.x;
        let bilinear = select(1.0 - f.x, f.x, o.x == 1u) * select(1.0 - f.y, f.y, o.y == 1u);
        let z = texel_distance[t];
        var gap = NO_MATCH;
        var alike = 0.0;
        if (z0 <= 0.0 || z <= 0.0) {
            if (z0 <= 0.0 && z <= 0.0) {
                gap = 0.0;
                alike = 1.0;
            }
        } else {
            gap = abs(z - z0) / z0;
            let n = safe_normalize(texel_normal[t], n0);
            alike = surface_similarity(z, z0, n, n0, DEPTH_FALLOFF);
        }
        if (gap < nearest_gap) {
            nearest_gap = gap;
            nearest = t;
        }
        let w = bilinear * alike;
        if (w > 0.0) {
            sum += w * texel_source[t];
#ifdef DETAIL
            image_sum += w * texel_image[t];
#endif
            weights += w;
        }
    }
    var v: vec4<f32>;
#ifdef DETAIL
    var mixed: vec4<f32>;
#endif
    if (weights > 1e-4) {
        v = sum / weights;
#ifdef DETAIL
        mixed = image_sum / weights;
#endif
    } else {
        v = texel_source[nearest];
#ifdef DETAIL
        mixed = texel_image[nearest];
#endif
    }
#ifdef DETAIL
    let radius = abs(textureLoad(coc, pixel, 0).x);
    // All the detail at a circle under half a pixel, none from DETAIL_FADE
    // pixels on: a small blur still keeps much of the detail, which the half
    // grid cannot hold.
    let sharp = clamp((DETAIL_FADE - select(0.0, radius, radius == radius)) / (DETAIL_FADE - 0.5), 0.0, 1.0);
    v += sharp * (clean(textureLoad(image, pixel, 0)) - mixed);
#endif
    v = clean(v);
#ifdef AO
    let ao = clamp(v.x, 0.0, 1.0);
    textureStore(output, pixel, vec4<f32>(ao, ao, ao, 1.0));
#else
#ifdef AO_COMBINE
    let other = textureLoad(combine, pixel, 0).r;
    let ao = clamp(v.x, 0.0, 1.0) * select(1.0, clamp(other, 0.0, 1.0), abs(other) <= 1e30);
    textureStore(output, pixel, vec4<f32>(ao, ao, ao, 1.0));
#else
#ifdef AMBIENT
    // The environment's light arrives only along the rays that escaped.
    let light = clean(textureLoad(ambient, pixel, 0)).rgb;
    let rgb = max(v.rgb, vec3<f32>(0.0)) + max(light, vec3<f32>(0.0)) * clamp(v.a, 0.0, 1.0);
    textureStore(output, pixel, vec4<f32>(min(rgb, vec3<f32>(HALF_MAX)), 1.0));
#else
#ifdef R32
    textureStore(output, pixel, vec4<f32>(v.x, 0.0, 0.0, 0.0));
#else
    textureStore(output, pixel, vec4<f32>(max(v.rgb, vec3<f32>(0.0)), v.a));
#endif
#endif
#endif
#endif
}
