// SSR: screen-space reflection with roughness (crates/render/src/environment/ssr/).
//
// hiz_first / hiz_down2 / hiz_down build a hierarchical depth: mip 0 the
// G-buffer's reversed-Z depth, each further mip the MAX of the texels under
// it (its 2x2, and at the last row or column what an odd level leaves).
// Two levels a dispatch (hiz_first: the copy and mip 1; hiz_down2: the next
// two from the one before), and from the first level after mip 1 of at most
// 32 texels a side down to 1x1 in one workgroup (hiz_tail, through workgroup
// memory; crates/render/src/mip_chain.rs says when a chain has a tail), so
// the 11 levels of 1080p take 4 dispatches: most levels are too small to
// fill the GPU, and each dispatch costs a barrier. A texel's footprint is
// read with independent loads (its 2x2, then an odd level's third row or
// column), so a thread waits for one load's latency, not one per texel: at
// the small levels there are too few threads to hide it. hiz_copy alone
// serves a 1x1 image; hiz_down one level where two would run past the chain's
// end or into the tail's first. In
// reversed-Z the max is the NEAREST surface of the cell (the farthest is
// the min): a ray nearer than a cell's max is in front of everything in it
// and may skip the whole cell; with the min it could skip past a near
// occluder.
//
// trace: per pixel whose material has the Reflection feature, `rays` rays
// (mirror at roughness < 0.02, else GGX half vectors jittered per pixel and
// frame) marched in screen space, where reversed-Z depth is affine along the
// projected ray: a step of 2^level pixels, up a level while the ray is in
// front of the cell's nearest surface, down a level when not, a hit at level
// 0 when the ray is behind the surface by less than a thickness. A hit reads
// the lit image, with a confidence that fades at the screen's edges and for
// surfaces facing away; misses (off screen, no hit within `max_steps`)
// have confidence 0. Radiance is averaged with N.L weights (as the
// prefilter does) and
//   output = conf * L_hit * (F0 A + B) + (1 - conf) * fallback
// where fallback is Reflection's specular: the same quantity from the
// environment, so the two are interchangeable.
//
// CLEARCOAT (trace only; some material has a clear coat): a coated pixel
// also traces the coat's lobe (its normal, its roughness, f0 0.04: one
// mirror ray for a smooth coat, else `rays` GGX rays) and mixes the two as
// Reflection does: base x (1 - factor F(N_c.V)) + factor x coat, each
// lobe's hits times its split sum; the fallback fills in by the lobes'
// confidences weighted by their split sums.
//
// HALF (trace only): one pixel per 2x2 block, into a half-size output that
// crates/render/src/resolution.rs upsamples with depth awareness.
//
// resolve: blend with last frame's output reprojected by the G-buffer
// velocity; history that is off screen, not finite, or fresh (camera cut,
// resize) is not used. Its own pass after a half-resolution trace's
// upsample; at full resolution TEMPORAL blends in the trace's own pass
// (`store`), so no raw target is written and read back.
#import spreadlight::camera::{Camera, pixel_to_ndc}
#import spreadlight::packing::{channel_to_id, safe_normalize}
#import spreadlight::ibl::{split_sum, facing_normal, importance_sample_ggx, hammersley}
#import spreadlight::material::{feature_param_at, has_feature, FEATURE_COOK_TORRANCE, FEATURE_REFLECTION}
#ifdef CLEARCOAT
#import spreadlight::material::{clearcoat_at, clearcoat_normal_at}
#import spreadlight::brdf::{schlick_weight, DIELECTRIC_F0}
#endif

struct Params {
    max_steps: u32,
    rays: u32,
    frame: u32,
    // Bit 0: the history holds a previous frame.
    flags: u32,
    near: f32,
    // View-space thickness assumed behind each surface.
    thickness: f32,
    // Weight of the new frame in the temporal blend.
    blend: f32,
    max_level: u32,
}

@group(0) @binding(0) var<uniform> camera: Camera;
@group(0) @binding(1) var<uniform> params: Params;
@group(0) @binding(2) var color: texture_2d<f32>;
@group(0) @binding(3) var normals: texture_2d<f32>;
@group(0) @binding(4) var depth: texture_2d<f32>;
@group(0) @binding(5) var hiz: texture_2d<f32>;
@group(0) @binding(6) var lit: texture_2d<f32>;
@group(0) @binding(7) var fallback: texture_2d<f32>;
@group(0) @binding(8) var lut: texture_2d<f32>;
@group(0) @binding(9) var lut_sampler: sampler;
@group(0) @binding(10) var output: texture_storage_2d<rgba16float, write>;
@group(0) @binding(11) var out_hiz: texture_storage_2d<r32float, write>;
@group(0) @binding(12) var hiz_source: texture_2d<f32>;
// The level after out_hiz's (hiz_first, hiz_down2).
@group(0) @binding(16) var out_hiz_next: texture_storage_2d<r32float, write>;
// hiz_tail's levels: slot 0 the level after hiz_source, each next slot the
// level after; where the chain ends first, the rest are bound to levels the
// tail neither reads nor writes (crates/render/src/mip_chain.rs, tail_slots).
@group(0) @binding(17) var out_tail_0: texture_storage_2d<r32float, write>;
@group(0) @binding(18) var out_tail_1: texture_storage_2d<r32float, write>;
@group(0) @binding(19) var out_tail_2: texture_storage_2d<r32float, write>;
@group(0) @binding(20) var out_tail_3: texture_storage_2d<r32float, write>;
@group(0) @binding(21) var out_tail_4: texture_storage_2d<r32float, write>;
@group(0) @binding(22) var out_tail_5: texture_storage_2d<r32float, write>;
@group(0) @binding(13) var current: texture_2d<f32>;
@group(0) @binding(14) var history: texture_2d<f32>;
@group(0) @binding(15) var velocity_uv: texture_2d<f32>;

const HALF_MAX: f32 = 65000.0;

fn clean(c: vec3<f32>) -> vec3<f32> {
    let finite = (c == c) & (abs(c) <= vec3<f32>(3.0e38));
    return select(vec3<f32>(0.0), min(max(c, vec3<f32>(0.0)), vec3<f32>(HALF_MAX)), finite);
}

@compute @workgroup_size(8, 8)
fn hiz_copy(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(depth);
    if (id.x >= size.x || id.y >= size.y) {
        return;
    }
    let d = textureLoad(depth, id.xy, 0).r;
    textureStore(out_hiz, id.xy, vec4<f32>(select(0.0, d, d == d), 0.0, 0.0, 0.0));
}

// Along each axis, the texels of a level `src` big under texel `k` of the
// level `out` big after it: its two (`lo`, `hi`; one where `src` is 1), and
// at the last row or column of an odd level also `last`, the third
// (`extra`). `src` is at most 2 out + 1, so that is all an odd level leaves.
struct Footprint {
    lo: vec2<u32>,
    hi: vec2<u32>,
    last: vec2<u32>,
    extra: vec2<bool>,
}

fn footprint(k: vec2<u32>, out: vec2<u32>, src: vec2<u32>) -> Footprint {
    let lo = k * 2u;
    let last = src - 1u;
    let hi = min(lo + 1u, last);
    return Footprint(lo, hi, last, (k + 1u == out) & (hi < last));
}

// Texel `i` (0..4) of a footprint's 2x2: (lo, lo), (hi, lo), (lo, hi), (hi, hi).
// A caller reads all four without a loop, so the loads do not wait on
// each other.
fn corner(f: Footprint, i: u32) -> vec2<u32> {
    return vec2<u32>(select(f.lo.x, f.hi.x, (i & 1u) != 0u), select(f.lo.y, f.hi.y, i >= 2u));
}

// How many texels an odd level leaves beyond the 2x2: its third column's
// two, its third row's two, and where both, their corner.
fn extra_count(f: Footprint) -> u32 {
    return select(0u, 2u, f.extra.x) + select(0u, 2u, f.extra.y) + select(0u, 1u, all(f.extra));
}

// Extra texel `i` (0..extra_count): the third column's, then the third
// row's, then the corner.
fn extra_texel(f: Footprint, i: u32) -> vec2<u32> {
    var j = i;
    if (f.extra.x) {
        if (j < 2u) {
            return vec2<u32>(f.last.x, select(f.lo.y, f.hi.y, j == 1u));
        }
        j -= 2u;
    }
    if (f.extra.y && j < 2u) {
        return vec2<u32>(select(f.lo.x, f.hi.x, j == 1u), f.last.y);
    }
    return f.last;
}

fn hiz_at(p: vec2<u32>) -> f32 {
    return textureLoad(hiz_source, p, 0).r;
}

// The nearest depth of `hiz_source` under texel `k` of a level `out` big.
fn nearest_under(k: vec2<u32>, out: vec2<u32>) -> f32 {
    let f = footprint(k, out, textureDimensions(hiz_source));
    var nearest = max(max(hiz_at(corner(f, 0u)), hiz_at(corner(f, 1u))), max(hiz_at(corner(f, 2u)), hiz_at(corner(f, 3u))));
    for (var i = 0u; i < extra_count(f); i++) {
        nearest = max(nearest, hiz_at(extra_texel(f, i)));
    }
    return nearest;
}

// A depth texel as mip 0 keeps it (NaN as 0), written there.
fn depth_copied(p: vec2<u32>) -> f32 {
    let d = textureLoad(depth, p, 0).r;
    let clean = select(0.0, d, d == d);
    textureStore(out_hiz, p, vec4<f32>(clean, 0.0, 0.0, 0.0));
    return clean;
}

// Mip 0 (the depth, NaN as 0) and mip 1: a thread per mip 1 texel copies
// the depth texels under it. The footprints tile mip 0, so each is
// written once (twice with the same value where a side is 1 texel).
@compute @workgroup_size(8, 8)
fn hiz_first(@builtin(global_invocation_id) id: vec3<u32>) {
    let out_size = textureDimensions(out_hiz_next);
    if (id.x >= out_size.x || id.y >= out_size.y) {
        return;
    }
    let f = footprint(id.xy, out_size, textureDimensions(depth));
    var nearest = max(max(depth_copied(corner(f, 0u)), depth_copied(corner(f, 1u))), max(depth_copied(corner(f, 2u)), depth_copied(corner(f, 3u))));
    for (var i = 0u; i < extra_count(f); i++) {
        nearest = max(nearest, depth_copied(extra_texel(f, i)));
    }
    textureStore(out_hiz_next, id.xy, vec4<f32>(nearest, 0.0, 0.0, 0.0));
}

// A texel of out_hiz (a level `size` big) made from hiz_source, written there.
fn mid_texel(p: vec2<u32>, size: vec2<u32>) -> f32 {
    let nearest = nearest_under(p, size);
    textureStore(out_hiz, p, vec4<f32>(nearest, 0.0, 0.0, 0.0));
    return nearest;
}

// Two levels from `hiz_source`: a thread per texel of the second
// (out_hiz_next) makes the texels of the first (out_hiz) under it.
@compute @workgroup_size(8, 8)
fn hiz_down2(@builtin(global_invocation_id) id: vec3<u32>) {
    let out_size = textureDimensions(out_hiz_next);
    if (id.x >= out_size.x || id.y >= out_size.y) {
        return;
    }
    let mid = textureDimensions(out_hiz);
    let f = footprint(id.xy, out_size, mid);
    var nearest = max(max(mid_texel(corner(f, 0u), mid), mid_texel(corner(f, 1u), mid)), max(mid_texel(corner(f, 2u), mid), mid_texel(corner(f, 3u), mid)));
    for (var i = 0u; i < extra_count(f); i++) {
        nearest = max(nearest, mid_texel(extra_texel(f, i), mid));
    }
    textureStore(out_hiz_next, id.xy, vec4<f32>(nearest, 0.0, 0.0, 0.0));
}

@compute @workgroup_size(8, 8)
fn hiz_down(@builtin(global_invocation_id) id: vec3<u32>) {
    let out_size = textureDimensions(out_hiz);
    if (id.x >= out_size.x || id.y >= out_size.y) {
        return;
    }
    textureStore(out_hiz, id.xy, vec4<f32>(nearest_under(id.xy, out_size), 0.0, 0.0, 0.0));
}

// hiz_tail's levels in workgroup memory: the first (at most 32 x 32) from
// offset 0, the next from TAIL_SECOND, and on alternating between the two.
const TAIL_SECOND: u32 = 1024u;
var<workgroup> tail_levels: array<f32, 1280>;

fn tail_store(slot: u32, p: vec2<u32>, nearest: f32) {
    let v = vec4<f32>(nearest, 0.0, 0.0, 0.0);
    switch slot {
        case 0u: { textureStore(out_tail_0, p, v); }
        case 1u: { textureStore(out_tail_1, p, v); }
        case 2u: { textureStore(out_tail_2, p, v); }
        case 3u: { textureStore(out_tail_3, p, v); }
        case 4u: { textureStore(out_tail_4, p, v); }
        default: { textureStore(out_tail_5, p, v); }
    }
}

fn tail_at(base: u32, width: u32, p: vec2<u32>) -> f32 {
    return tail_levels[base + p.y * width + p.x];
}

// The nearest of the workgroup's level at `base` (`src` big) under texel
// `k` of a level `out` big: nearest_under's rule.
fn tail_nearest(base: u32, src: vec2<u32>, k: vec2<u32>, out: vec2<u32>) -> f32 {
    let f = footprint(k, out, src);
    let w = src.x;
    var nearest = max(max(tail_at(base, w, corner(f, 0u)), tail_at(base, w, corner(f, 1u))), max(tail_at(base, w, corner(f, 2u)), tail_at(base, w, corner(f, 3u))));
    for (var i = 0u; i < extra_count(f); i++) {
        nearest = max(nearest, tail_at(base, w, extra_texel(f, i)));
    }
    return nearest;
}

// Every level after hiz_source's down to 1 x 1, in one workgroup: the
// first (at most 32 a side: mip_chain.rs's TAIL_SIDE) from hiz_source, each next from the one
// before it in workgroup memory, a barrier between levels. One dispatch
// instead of one for every level or two, each of which would wait for the
// one before it with a handful of busy threads.
@compute @workgroup_size(16, 16)
fn hiz_tail(@builtin(local_invocation_index) thread: u32) {
    var size = max(textureDimensions(hiz_source) >> vec2<u32>(1u), vec2<u32>(1u));
    for (var i = thread; i < size.x * size.y; i += 256u) {
        let p = vec2<u32>(i % size.x, i / size.x);
        let nearest = nearest_under(p, size);
        tail_levels[i] = nearest;
        tail_store(0u, p, nearest);
    }
    var base = 0u;
    var slot = 1u;
    while (size.x > 1u || size.y > 1u) {
        workgroupBarrier();
        let next = max(size >> vec2<u32>(1u), vec2<u32>(1u));
        let next_base = select(0u, TAIL_SECOND, base == 0u);
        for (var i = thread; i < next.x * next.y; i += 256u) {
            let p = vec2<u32>(i % next.x, i / next.x);
            let nearest = tail_nearest(base, size, p, next);
            tail_levels[next_base + i] = nearest;
            tail_store(slot, p, nearest);
        }
        size = next;
        base = next_base;
        slot += 1u;
    }
}

fn view_position(uv: vec2<f32>, d: f32) -> vec3<f32> {
    let h = camera.projection_inverse * vec4<f32>(uv.x * 2.0 - 1.0, 1.0 - uv.y * 2.0, d, 1.0);
    return h.xyz / h.w;
}

// Screen position in pixels (xy) and reversed-Z depth (z) of view-space `p`.
fn project(p: vec3<f32>) -> vec3<f32> {
    let clip = camera.projection * vec4<f32>(p, 1.0);
    let ndc = clip.xyz / clip.w;
    return vec3<f32>((ndc.x * 0.5 + 0.5) * camera.size.x, (0.5 - ndc.y * 0.5) * camera.size.y, ndc.z);
}

// A per-pixel, per-frame, per-ray rotation of the sample pattern.
fn jitter(pixel: vec2<u32>, frame: u32, ray: u32) -> f32 {
    var h = pixel.x * 1973u + pixel.y * 9277u + frame * 26699u + ray * 7919u;
    h = (h ^ (h >> 16u)) * 0x45d9f3bu;
    h = (h ^ (h >> 16u)) * 0x45d9f3bu;
    h = h ^ (h >> 16u);
    return f32(h & 0xffffu) / 65536.0;
}

struct Trace {
    radiance: vec3<f32>,
    confidence: f32,
}

// March from view-space `origin` along unit view-space `dir`.
fn trace(origin: vec3<f32>, dir: vec3<f32>) -> Trace {
    var miss = Trace(vec3<f32>(0.0), 0.0);
    // Keep the end in front of the near plane, so it projects.
    var length = 1000.0;
    if (dir.z > 1e-5) {
        length = min(length, (-params.near * 1.01 - origin.z) / dir.z);
    }
    if (length <= 1e-4) {
        return miss;
    }
    let start = project(origin);
    let end = project(origin + dir * length);
    let delta = end.xy - start.xy;
    let pixels = max(abs(delta.x), abs(delta.y));
    if (pixels < 1.0) {
        return miss;
    }
    // Per pixel of the major axis: screen step and depth step.
    let step_xy = delta / pixels;
    let step_z = (end.z - start.z) / pixels;
    let size = camera.size.xy;
    var s = 1.5;
    var level = 0u;
    // Level sizes from level 0's (a mip is max(1, size >> level)), not a
    // size query per step: the same numbers without a texture instruction.
    let hiz_size = textureDimensions(hiz);
    for (var i = 0u; i < params.max_steps; i++) {
        let cell = f32(1u << level);
        let next = s + cell;
        if (next > pixels) {
            return miss;
        }
        let p = start.xy + step_xy * next;
        if (any(p < vec2<f32>(0.0)) || any(p >= size)) {
            return miss;
        }
        let ray_depth = start.z + step_z * next;
        // Clamped: a level's size rounds down, and the chain folds odd edges into its last texel.
        let level_size = max(hiz_size >> vec2<u32>(level), vec2<u32>(1u));
        let cell_texel = min(vec2<u32>(p) >> vec2<u32>(level), level_size - 1u);
        let nearest = textureLoad(hiz, cell_texel, i32(level)).r;
        if (ray_depth > nearest) {
            // In front of everything in the cell: skip it, try a coarser level.
            s = next;
            level = min(level + 1u, params.max_level);
            continue;
        }
        if (level > 0u) {
            level -= 1u;
            continue;
        }
        // Level 0: the ray is at or behind this pixel's surface.
        let pixel = vec2<u32>(p);
        let surface = textureLoad(depth, pixel, 0).r;
        let uv = p / size;
        let surface_z = view_position(uv, surface).z;
        let ray_z = view_position(uv, ray_depth).z;
        if (surface > 0.0 && surface_z - ray_z < params.thickness) {
            let n_hit = safe_normalize(textureLoad(normals, pixel, 0).xyz, -dir);
            // A surface seen from behind is not what the ray would see.
            let facing = clamp(-dot(n_hit, dir) * 4.0, 0.0, 1.0);
            let edge = min(min(uv.x, 1.0 - uv.x), min(uv.y, 1.0 - uv.y));
            let fade = clamp(edge / 0.08, 0.0, 1.0);
            return Trace(clean(textureLoad(lit, pixel, 0).rgb), facing * fade);
        }
        // Behind a thin surface: pass it.
        s = next;
    }
    return miss;
}

// Where a full pixel's result goes: itself, or under HALF its 2x2 block's texel.
fn store(pixel: vec2<u32>, c: vec3<f32>) {
#ifdef HALF
    textureStore(output, pixel / 2u, vec4<f32>(clean(c), 1.0));
#else
#ifdef TEMPORAL
    textureStore(output, pixel, blended(pixel, c));
#else
    textureStore(output, pixel, vec4<f32>(clean(c), 1.0));
#endif
#endif
}

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = vec2<u32>(camera.size.xy);
#ifdef HALF
    // The trace at half resolution: this thread is the 2x2 block's top-left
    // pixel, traced as at full resolution into the half-size output
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
    let texel = textureLoad(color, pixel, 0);
    let material = channel_to_id(texel.a);
    if (d <= 0.0 || !has_feature(material, FEATURE_REFLECTION)) {
        store(pixel, vec3<f32>(0.0));
        return;
    }
    let uv = (vec2<f32>(pixel) + 0.5) * camera.size.zw;
    let p = view_position(uv, d);
    let v = safe_normalize(-p, vec3<f32>(0.0, 0.0, 1.0));
    let n = facing_normal(safe_normalize(textureLoad(normals, pixel, 0).xyz, v), v);
    let ct = clamp(feature_param_at(material, FEATURE_COOK_TORRANCE, 0u, vec4<f32>(0.5, 0.0, 0.04, 0.0), pixel), vec4<f32>(0.0), vec4<f32>(1.0));
    let roughness = ct.x;
    let f0 = mix(vec3<f32>(ct.z), max(texel.rgb, vec3<f32>(0.0)), ct.y);
    let n_dot_v = clamp(dot(n, v), 1e-4, 1.0);
    let factor = split_sum(lut, lut_sampler, f0, n_dot_v, roughness);
    // Start a little off the surface, more for far surfaces (depth precision).
    let origin = p + n * (0.01 + 0.002 * -p.z);
    let rays = max(params.rays, 1u);
    let base = trace_lobe(pixel, origin, v, n, roughness, rays, 0u);
    let fall = clean(textureLoad(fallback, pixel, 0).rgb);
    var reflected = base.radiance * factor;
    var c = base.confidence;
#ifdef CLEARCOAT
    let coat = clamp(clearcoat_at(material, pixel), vec2<f32>(0.0), vec2<f32>(1.0));
    if (coat.x > 0.0) {
        let coat_n = facing_normal(safe_normalize(clearcoat_normal_at(pixel, n), n), v);
        let coat_n_dot_v = clamp(dot(coat_n, v), 1e-4, 1.0);
        // What the coat reflects does not reach the base, nor leave it.
        let dim = 1.0 - coat.x * (DIELECTRIC_F0 + (1.0 - DIELECTRIC_F0) * schlick_weight(coat_n_dot_v));
        let coat_factor = coat.x * split_sum(lut, lut_sampler, vec3<f32>(DIELECTRIC_F0), coat_n_dot_v, coat.y);
        // A smooth coat (car paint) is one mirror ray, whatever `rays`.
        let coat_rays = select(rays, 1u, coat.y < 0.02);
        let lobe = trace_lobe(pixel, origin, v, coat_n, coat.y, coat_rays, 1u);
        // The fallback holds both lobes' environment: each lobe's misses
        // take their share of it, by the lobes' split-sum weights.
        let base_share = dim * max(max(factor.x, factor.y), factor.z);
        let coat_share = max(max(coat_factor.x, coat_factor.y), coat_factor.z);
        c = (base_share * c + coat_share * lobe.confidence) / max(base_share + coat_share, 1e-6);
        reflected = reflected * dim + lobe.radiance * coat_factor;
    }
#endif
    store(pixel, reflected + (1.0 - clamp(c, 0.0, 1.0)) * fall);
}

// One lobe's rays: the N.L-weighted mean of hit radiance times confidence,
// and the mean confidence (both 0 when no ray leaves above the surface).
struct Lobe {
    radiance: vec3<f32>,
    confidence: f32,
}

// `rays` rays of the GGX lobe of `roughness` about `n` (the mirror ray
// below roughness 0.02) from view-space `origin`; `salt` decorrelates the
// jitter of a second lobe at the same pixel.
fn trace_lobe(pixel: vec2<u32>, origin: vec3<f32>, v: vec3<f32>, n: vec3<f32>, roughness: f32, rays: u32, salt: u32) -> Lobe {
    var sum = vec3<f32>(0.0);
    var confidence = 0.0;
    var weight = 0.0;
    for (var k = 0u; k < rays; k++) {
        var l = reflect(-v, n);
        if (roughness >= 0.02) {
            let ray = k + salt * 7717u;
            var xi = hammersley(k, rays);
            xi.x = fract(xi.x + jitter(pixel, params.frame, ray));
            xi.y = fract(xi.y + jitter(pixel, params.frame, ray + 977u) / f32(rays));
            let h = importance_sample_ggx(xi, max(roughness * roughness, 1e-3), n);
            l = reflect(-v, h);
        }
        let n_dot_l = dot(n, l);
        if (n_dot_l <= 0.0) {
            continue;
        }
        let t = trace(origin, l);
        sum += t.radiance * t.confidence * n_dot_l;
        confidence += t.confidence * n_dot_l;
        weight += n_dot_l;
    }
    if (weight <= 0.0) {
        return Lobe(vec3<f32>(0.0), 0.0);
    }
    return Lobe(sum / weight, clamp(confidence / weight, 0.0, 1.0));
}

// This frame's reflection `c` at `pixel` blended with last frame's, with
// the view distance in alpha (the resolve, or TEMPORAL's trace).
fn blended(pixel: vec2<u32>, c: vec3<f32>) -> vec4<f32> {
    let now = clean(c);
    // Alpha keeps the view distance, so next frame can tell the same
    // surface: also on a frame with no history, which the next can blend.
    let d = textureLoad(depth, pixel, 0).r;
    if (d <= 0.0) {
        return vec4<f32>(now, 0.0);
    }
    let h = camera.projection_inverse * vec4<f32>(pixel_to_ndc(pixel, camera.size), d, 1.0);
    let p = h.xyz / h.w;
    let distance = min(-p.z, 65000.0);
    if ((params.flags & 1u) == 0u) {
        return vec4<f32>(now, distance);
    }
    let uv = (vec2<f32>(pixel) + 0.5) * camera.size.zw;
    let before = uv - textureLoad(velocity_uv, pixel, 0).xy;
    if (any(before < vec2<f32>(0.0)) || any(before >= vec2<f32>(1.0)) || any(before != before)) {
        return vec4<f32>(now, distance);
    }
    let old = textureLoad(history, vec2<u32>(before * camera.size.xy), 0);
    // Sanitized on read: a NaN or infinity in the history never spreads; and
    // only the same surface (its stored distance within 5% of this point's
    // distance from last frame's camera) is blended: no smearing across a
    // disocclusion.
    let finite = all(old == old) && all(abs(old) <= vec4<f32>(65000.0));
    let world = camera.view_inverse * vec4<f32>(p, 1.0);
    let expected = (camera.previous_view_projection * world).w;
    let same = old.a > 0.0 && old.a < 65000.0 && abs(old.a - expected) <= 0.05 * expected + 1e-3;
    if (!finite || !same) {
        return vec4<f32>(now, distance);
    }
    return vec4<f32>(clean(mix(old.rgb, now, clamp(params.blend, 0.0, 1.0))), distance);
}

@compute @workgroup_size(8, 8)
fn resolve(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = vec2<u32>(camera.size.xy);
    if (id.x >= size.x || id.y >= size.y) {
        return;
    }
    textureStore(output, id.xy, blended(id.xy, textureLoad(current, id.xy, 0).rgb));
}

// No material reflects: zero, nothing traced.
@compute @workgroup_size(8, 8)
fn clear(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = vec2<u32>(camera.size.xy);
    if (id.x >= size.x || id.y >= size.y) {
        return;
    }
    store(id.xy, vec3<f32>(0.0));
}
