// Sampling ShadowMap layers in CookTorrance: where a world point lands in a
// layer, and how lit it is there under the filter compiled in: SHADOWS
// alone is Raw (one texel), SHADOW_PCF percentage-closer filtering over a
// kernel, SHADOW_PCSS percentage-closer soft shadows (blocker search,
// penumbra from the light's size, PCF over it), SHADOW_VSM variance shadow
// maps. Returns 1 lit .. 0 shadowed, never NaN: every division is guarded.
#define_import_path spreadlight::shadow_sampling

// Matches `GpuLayerView` in crates/render/src/shadows/views.rs.
struct ShadowView {
    view_projection: mat4x4<f32>,
    // near, far, world size of a texel (at distance 1 when perspective), orthographic (0/1)
    depth: vec4<f32>,
    // x: the camera depth where this sun cascade ends
    split: vec4<f32>,
}

// Matches `GpuShadowParams` in crates/render/src/shadows/mod.rs.
struct ShadowParams {
    // depth bias (world units), normal bias (texels), reach (PCF radius or VSM blur, texels), PCSS light size (world)
    bias: vec4<f32>,
    // PCSS samples, VSM bleeding reduction, resolution, layers per slice
    sampling: vec4<f32>,
}

#ifdef SHADOWS
// Conventional depth in R32F (compute writes it; it is not filterable), so
// comparisons are done here: 2x2 texels loaded, compared, weighted bilinearly.
@group(0) @binding(17) var shadow_maps: texture_2d_array<f32>;
@group(0) @binding(19) var<storage, read> shadow_views: array<ShadowView>;
@group(0) @binding(20) var<uniform> shadow_params: ShadowParams;
#ifdef SHADOW_VSM
@group(0) @binding(21) var shadow_moments: texture_2d_array<f32>;
#endif
#endif

// Conventional depth (0 near, 1 far) to distance along the view's axis.
fn linear_depth(v: ShadowView, d: f32) -> f32 {
    let n = v.depth.x;
    let f = v.depth.y;
    if (v.depth.w > 0.5) {
        return n + d * (f - n);
    }
    return n * f / max(f - d * (f - n), 1e-12);
}

// Distance along the view's axis to conventional depth.
fn depth_of(v: ShadowView, z: f32) -> f32 {
    let n = v.depth.x;
    let f = v.depth.y;
    if (v.depth.w > 0.5) {
        return (z - n) / max(f - n, 1e-12);
    }
    return f * (z - n) / max(z * (f - n), 1e-12);
}

#ifdef SHADOWS
// A hash of a position, 0..1: rotates the sample disk per pixel so too few
// samples make noise rather than bands.
fn shadow_noise(p: vec3<f32>) -> f32 {
    return fract(sin(dot(p, vec3<f32>(12.9898, 78.233, 37.719))) * 43758.5453);
}

// The i-th of n points of a Vogel (golden-angle) disk of radius 1.
fn vogel(i: u32, n: u32, phi: f32) -> vec2<f32> {
    let r = sqrt((f32(i) + 0.5) / f32(max(n, 1u)));
    let theta = f32(i) * 2.39996323 + phi;
    return r * vec2<f32>(cos(theta), sin(theta));
}

fn texel_of(uv: vec2<f32>) -> vec2<i32> {
    let size = shadow_params.sampling.z;
    return vec2<i32>(clamp(uv * size, vec2<f32>(0.0), vec2<f32>(size - 1.0)));
}

// How lit world point `pw` (world normal `nw`) is in shadow-map layer
// `layer`; `slope` is the tangent of the angle between the normal and the
// light. Outside the layer's frustum: lit.
//
// Bias: the depth bias, plus the slope times how far (in world units)
// the filter reaches from the pixel: a tilted receiver is that much deeper
// at the far end of the kernel, and without it wide filters shadow the
// receiver itself (acne), most at grazing angles.
fn shadow_in_layer(layer: u32, pw: vec3<f32>, nw: vec3<f32>, slope: f32) -> f32 {
    let v = shadow_views[layer];
    // Normal offset: a texel's world size at the receiver, times the bias.
    let first = v.view_projection * vec4<f32>(pw, 1.0);
    let distance = select(max(first.w, 0.0), 1.0, v.depth.w > 0.5);
    let texel_world = v.depth.z * distance;
    let moved = pw + nw * shadow_params.bias.y * texel_world;
    let clip = v.view_projection * vec4<f32>(moved, 1.0);
    if (clip.w <= 1e-12) {
        return 1.0;
    }
    let ndc = clip.xyz / clip.w;
    if (any(abs(ndc.xy) > vec2<f32>(1.0)) || ndc.z < 0.0 || ndc.z > 1.0) {
        return 1.0;
    }
    let uv = vec2<f32>(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5);
    let receiver = linear_depth(v, ndc.z);
    let bias = shadow_params.bias.x;
#ifdef SHADOW_VSM
    let reach = (shadow_params.bias.z + 1.0) * texel_world;
    return vsm(layer, uv, v, max(receiver - bias - slope * reach, v.depth.x));
#else
#ifdef SHADOW_PCSS
    return pcss(layer, uv, v, receiver, bias, slope, moved);
#else
#ifdef SHADOW_PCF
    let r = i32(shadow_params.bias.z);
    let reach = f32(r + 1) * texel_world;
    return pcf(layer, uv, depth_of(v, max(receiver - bias - slope * reach, v.depth.x)), r);
#else
    let reference = depth_of(v, max(receiver - bias - slope * texel_world, v.depth.x));
    let stored = textureLoad(shadow_maps, texel_of(uv), i32(layer), 0).r;
    return select(0.0, 1.0, reference <= stored);
#endif
#endif
#endif
}

// What a comparison sampler does: the four texels around uv compared with
// `reference` (lit when not deeper than the stored depth), weighted
// bilinearly, so edges move smoothly with the receiver.
fn compare_bilinear(layer: u32, uv: vec2<f32>, reference: f32) -> f32 {
    let res = shadow_params.sampling.z;
    let p = uv * res - 0.5;
    let base = floor(p);
    let f = p - base;
    let limit = vec2<i32>(i32(res) - 1);
    let t = vec2<i32>(base);
    let l = i32(layer);
    let d = vec4<f32>(
        textureLoad(shadow_maps, clamp(t, vec2<i32>(0), limit), l, 0).r,
        textureLoad(shadow_maps, clamp(t + vec2<i32>(1, 0), vec2<i32>(0), limit), l, 0).r,
        textureLoad(shadow_maps, clamp(t + vec2<i32>(0, 1), vec2<i32>(0), limit), l, 0).r,
        textureLoad(shadow_maps, clamp(t + vec2<i32>(1, 1), vec2<i32>(0), limit), l, 0).r,
    );
    let lit = select(vec4<f32>(0.0), vec4<f32>(1.0), vec4<f32>(reference) <= d);
    return mix(mix(lit.x, lit.y, f.x), mix(lit.z, lit.w, f.x), f.y);
}

// The mean of (2r + 1)^2 bilinear comparisons around uv.
fn pcf(layer: u32, uv: vec2<f32>, reference: f32, r: i32) -> f32 {
    let step = 1.0 / shadow_params.sampling.z;
    var sum = 0.0;
    for (var y = -r; y <= r; y++) {
        for (var x = -r; x <= r; x++) {
            sum += compare_bilinear(layer, uv + vec2<f32>(f32(x), f32(y)) * step, reference);
        }
    }
    let side = f32(2 * r + 1);
    return sum / (side * side);
}

#ifdef SHADOW_PCSS
// Fernando's PCSS. The light is a disk of `bias.w` world units (for a sun:
// the tangent of its angular radius); the penumbra it throws from a blocker
// at zb onto a receiver at zr is L (zr - zb) / zb wide for a light at a
// point (L (zr - zb) for a sun), which sets the PCF radius. Blockers are
// searched within the widest penumbra a receiver at zr can have.
fn pcss(layer: u32, uv: vec2<f32>, v: ShadowView, receiver: f32, bias: f32, slope: f32, pw: vec3<f32>) -> f32 {
    let n = u32(shadow_params.sampling.x);
    let light = shadow_params.bias.w;
    let ortho = v.depth.w > 0.5;
    let res = shadow_params.sampling.z;
    // The layer's width in world units at the receiver.
    let width = v.depth.z * res * select(max(receiver, 1e-6), 1.0, ortho);
    let texel = 1.0 / res;
    let search = clamp(select(light, light * receiver, ortho) / max(width, 1e-12), texel, 0.1);
    let phi = shadow_noise(pw) * 6.2831853;
    let searched = max(receiver - bias - slope * (search + texel) * width, v.depth.x);
    var blockers = 0.0;
    var blocker_sum = 0.0;
    for (var i = 0u; i < n; i++) {
        let d = textureLoad(shadow_maps, texel_of(uv + vogel(i, n, phi) * search), i32(layer), 0).r;
        let z = linear_depth(v, d);
        if (z < searched) {
            blockers += 1.0;
            blocker_sum += z;
        }
    }
    if (blockers < 0.5) {
        return 1.0;
    }
    let blocker = max(blocker_sum / blockers, 1e-6);
    let penumbra = select(light * (receiver - blocker) / blocker, light * (receiver - blocker), ortho);
    let radius = clamp(max(penumbra, 0.0) / max(width, 1e-12), texel, 0.1);
    let reference = depth_of(v, max(receiver - bias - slope * (radius + texel) * width, v.depth.x));
    var lit = 0.0;
    for (var i = 0u; i < n; i++) {
        lit += compare_bilinear(layer, uv + vogel(i, n, phi) * radius, reference);
    }
    return lit / f32(max(n, 1u));
}
#endif

#ifdef SHADOW_VSM
// Chebyshev's upper bound on the lit fraction from the filtered moments,
// with light bleeding cut: values under `sampling.y` go to 0. The moments are
// read bilinearly by hand (RG32F is not filterable everywhere).
fn vsm(layer: u32, uv: vec2<f32>, v: ShadowView, biased: f32) -> f32 {
    let res = shadow_params.sampling.z;
    let p = uv * res - 0.5;
    let base = floor(p);
    let f = p - base;
    let limit = vec2<i32>(i32(res) - 1);
    let t00 = textureLoad(shadow_moments, clamp(vec2<i32>(base), vec2<i32>(0), limit), i32(layer), 0).xy;
    let t10 = textureLoad(shadow_moments, clamp(vec2<i32>(base) + vec2<i32>(1, 0), vec2<i32>(0), limit), i32(layer), 0).xy;
    let t01 = textureLoad(shadow_moments, clamp(vec2<i32>(base) + vec2<i32>(0, 1), vec2<i32>(0), limit), i32(layer), 0).xy;
    let t11 = textureLoad(shadow_moments, clamp(vec2<i32>(base) + vec2<i32>(1, 1), vec2<i32>(0), limit), i32(layer), 0).xy;
    let m = mix(mix(t00, t10, f.x), mix(t01, t11, f.x), f.y);
    let t = clamp((biased - v.depth.x) / max(v.depth.y - v.depth.x, 1e-12), 0.0, 1.0);
    if (t <= m.x) {
        return 1.0;
    }
    // Negative variance from rounding is clamped, never a square root of it.
    let variance = max(m.y - m.x * m.x, 1e-7);
    let d = t - m.x;
    let upper = variance / (variance + d * d);
    let amount = clamp(shadow_params.sampling.y, 0.0, 0.99);
    return clamp((upper - amount) / (1.0 - amount), 0.0, 1.0);
}
#endif

// How lit world point `pw` is by a light whose shadow is slice `slice`:
// spots read layer `slice`; point lights the cube face `from_light` points
// at; suns the cascade that holds camera depth `view_depth` (beyond the
// last: lit).
fn light_shadow(slice: u32, pw: vec3<f32>, nw: vec3<f32>, from_light: vec3<f32>, view_depth: f32, n_dot_l: f32) -> f32 {
    let per = u32(shadow_params.sampling.w);
    // tan of the angle of incidence, capped where the light grazes the surface.
    let c = clamp(abs(n_dot_l), 0.1, 1.0);
    let slope = sqrt(1.0 - c * c) / c;
#ifdef LIGHT_SUN
    for (var c = 0u; c < per; c++) {
        let layer = slice * per + c;
        if (view_depth <= shadow_views[layer].split.x) {
            return shadow_in_layer(layer, pw, nw, slope);
        }
    }
    return 1.0;
#else
#ifdef LIGHT_SPOT
    return shadow_in_layer(slice, pw, nw, slope);
#else
    // The face where the point lands after its normal offset (a texel of a
    // face is 2 / resolution at distance 1 along its axis), so a point near
    // a face border is not moved off the face it was sampled on.
    let d = abs(from_light);
    let axis = max(d.x, max(d.y, d.z));
    let moved = from_light + nw * shadow_params.bias.y * (2.0 / shadow_params.sampling.z) * axis;
    let a = abs(moved);
    var face = 0u;
    if (a.x >= a.y && a.x >= a.z) {
        face = select(1u, 0u, moved.x > 0.0);
    } else if (a.y >= a.z) {
        face = select(3u, 2u, moved.y > 0.0);
    } else {
        face = select(5u, 4u, moved.z > 0.0);
    }
    return shadow_in_layer(slice * 6u + face, pw, nw, slope);
#endif
#endif
}

// How lit world point `pw` (world normal `nw`, `n_dot_l` towards the sun)
// is by the sun whose cascades are slice `slice`, wherever the point is,
// for passes that shade what the camera does not see (EnvironmentProbe's
// faces): the finest cascade whose view holds it (inside its inner 98%,
// so the filter's taps stay on the layer); beyond them all, lit.
fn sun_shadow_anywhere(slice: u32, pw: vec3<f32>, nw: vec3<f32>, n_dot_l: f32) -> f32 {
    let per = u32(shadow_params.sampling.w);
    let c = clamp(abs(n_dot_l), 0.1, 1.0);
    let slope = sqrt(1.0 - c * c) / c;
    for (var k = 0u; k < per; k++) {
        let layer = slice * per + k;
        let clip = shadow_views[layer].view_projection * vec4<f32>(pw, 1.0);
        if (clip.w > 1e-12) {
            let ndc = clip.xyz / clip.w;
            if (all(abs(ndc.xy) <= vec2<f32>(0.98)) && ndc.z >= 0.0 && ndc.z <= 1.0) {
                return shadow_in_layer(layer, pw, nw, slope);
            }
        }
    }
    return 1.0;
}
#endif
