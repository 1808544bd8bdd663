// Screen-space helpers for passes over the G-buffer: view positions from
// reversed-Z depth, projection back to pixels, and per-pixel noise.
#define_import_path spreadlight::screen
#import spreadlight::camera::{Camera, pixel_to_ndc}
#import spreadlight::packing::safe_normalize

// The view-space position under a pixel centre at reversed-Z depth `d` (> 0).
fn view_position(camera: Camera, pixel: vec2<u32>, d: f32) -> vec3<f32> {
    let h = camera.projection_inverse * vec4<f32>(pixel_to_ndc(pixel, camera.size), d, 1.0);
    return h.xyz / h.w;
}

// The view-space position at a continuous pixel coordinate (x, y in
// pixels, 0 at the top-left corner) and view distance `z` (> 0, along -Z):
// the point on that pixel's ray at that depth. Perspective cameras.
fn view_position_at_distance(camera: Camera, xy: vec2<f32>, z: f32) -> vec3<f32> {
    let uv = xy * camera.size.zw;
    let ndc = vec2<f32>(uv.x * 2.0 - 1.0, 1.0 - uv.y * 2.0);
    let h = camera.projection_inverse * vec4<f32>(ndc, 1.0, 1.0);
    let ray = h.xyz / h.w;
    return ray * (z / max(-ray.z, 1e-20));
}

// Where a view-space point lands: xy in pixels (continuous), z its reversed-Z depth.
// Points behind the eye give w <= 0: the caller checks `valid`.
struct Projected {
    xy: vec2<f32>,
    depth: f32,
    valid: bool,
}

fn project(camera: Camera, p: vec3<f32>) -> Projected {
    let c = camera.projection * vec4<f32>(p, 1.0);
    var out: Projected;
    out.valid = c.w > 1e-6;
    let ndc = c.xyz / max(c.w, 1e-6);
    out.xy = vec2<f32>(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5) * camera.size.xy;
    out.depth = ndc.z;
    return out;
}

// Jimenez's interleaved gradient noise, 0..1: well spread over 8x8 pixels,
// so a blur of that width averages the per-pixel rotations away.
fn interleaved_gradient_noise(pixel: vec2<f32>, frame: u32) -> f32 {
    let p = pixel + 5.588238 * f32(frame % 64u);
    return fract(52.9829189 * fract(0.06711056 * p.x + 0.00583715 * p.y));
}

// Two orthonormal tangents to unit `n` (Frisvad, with the pole handled).
fn tangent_frame(n: vec3<f32>) -> mat3x3<f32> {
    let s = select(-1.0, 1.0, n.z >= 0.0);
    let a = -1.0 / (s + n.z);
    let b = n.x * n.y * a;
    let t = vec3<f32>(1.0 + s * n.x * n.x * a, s * b, -s * n.x);
    let u = vec3<f32>(b, s + n.y * n.y * a, -n.y);
    return mat3x3<f32>(t, u, n);
}

// The uniform the screen-space ray passes share (AO, SSGI): 64 bytes,
// written by `render::temporal::ray_params`.
struct RayParams {
    // World units a ray travels / occluders count.
    radius: f32,
    intensity: f32,
    // Last frame's weight in the temporal pass.
    blend: f32,
    // Self-occlusion offset, world units.
    bias: f32,
    samples: u32,
    steps: u32,
    // Turns the per-pixel pattern every frame.
    frame: u32,
    blur_radius: u32,
    // 1: drop the history this frame.
    reset: u32,
    spare_a: u32,
    spare_b: u32,
    spare_c: u32,
    spare_d: vec4<u32>,
}

// Ray `i` of `samples`, cosine-weighted about the frame's third axis: a
// stratified spiral turned by the pixel's `noise`.
fn cosine_direction(frame: mat3x3<f32>, i: u32, samples: u32, noise: f32) -> vec3<f32> {
    let u = (f32(i) + fract(noise + 0.5)) / f32(samples);
    let phi = 6.283185307 * fract(f32(i) * 0.618034 + noise);
    let s = sqrt(u);
    return frame * vec3<f32>(s * cos(phi), s * sin(phi), sqrt(max(1.0 - u, 0.0)));
}

// March a view-space ray from `origin` along `dir` over `radius` in `steps`
// (offset by `jitter`, 0..1) against a reversed-Z depth buffer. The pixel
// where it first passes behind a surface by more than `bias` and less than
// `radius` (a surface farther in front is a separate object, not a
// blocker), or -1 when it leaves the screen or reaches its end unblocked.
fn march(camera: Camera, depth: texture_2d<f32>, origin: vec3<f32>, dir: vec3<f32>, radius: f32, steps: u32, jitter: f32, bias: f32) -> vec2<i32> {
    let size = vec2<i32>(camera.size.xy);
    for (var k = 0u; k < steps; k++) {
        let q = origin + dir * max(radius * (f32(k) + jitter) / f32(steps), 1e-6);
        let pr = project(camera, q);
        let tap = vec2<i32>(floor(pr.xy));
        if (!pr.valid || any(tap < vec2<i32>(0)) || any(tap >= size)) {
            break;
        }
        let d = textureLoad(depth, vec2<u32>(tap), 0).r;
        if (d <= 0.0) {
            continue;
        }
        let in_front = view_position(camera, vec2<u32>(tap), d).z - q.z;
        if (in_front > bias && in_front < radius) {
            return tap;
        }
    }
    return vec2<i32>(-1);
}

// How alike a neighbour is to a pixel for a depth- and normal-aware filter
// (the AO blur, the half-resolution upsample): 1 at the same view distance
// and facing, falling off with the depth gap relative to the pixel's
// distance `z0` (to 1/e at a gap of `falloff` x z0) and with the angle
// between the normals (cosine to the 8th).
fn surface_similarity(z: f32, z0: f32, n: vec3<f32>, n0: vec3<f32>, falloff: f32) -> f32 {
    return exp(-abs(z - z0) / (falloff * z0 + 1e-6)) * facing8(dot(n0, n));
}

// max(c, 0)^8 by squaring: three multiplies, where pow takes a log and an exp.
fn facing8(c: f32) -> f32 {
    let c2 = max(c, 0.0) * max(c, 0.0);
    let c4 = c2 * c2;
    return c4 * c4;
}

// A depth-aware blur's tap weight: a Gaussian in the tap offset `o` times
// `surface_similarity`, with one exp instead of two (the blurs' taps are
// bound by transcendentals). `spread` = 1 / (2 sigma^2), `reach` =
// 1 / (falloff z0 + 1e-6), `facing` = dot(n0, n), both per centre.
fn tap_weight(o: i32, spread: f32, dz: f32, reach: f32, facing: f32) -> f32 {
    return exp(-f32(o * o) * spread - abs(dz) * reach) * facing8(facing);
}

// A depth- and normal-aware separable blur about one pixel (AO's and
// SSGI's blurs, one axis a pass): a Gaussian of half-width `radius` (sigma
// radius / 2, at least 0.5) whose taps lose weight with their view
// distance's gap from the centre's `z0` (3% of it falls off by e) and
// their normal's angle from the centre's `n0` ([`tap_weight`]).
// (Members: naga_oil refuses imported names that end in a digit.)
struct SeparableBlur {
    radius: i32,
    spread: f32,
    reach: f32,
    centre_distance: f32,
    centre_normal: vec3<f32>,
}

fn separable_blur(radius: u32, z0: f32, n0: vec3<f32>) -> SeparableBlur {
    let r = i32(radius);
    let sigma = max(f32(r), 1.0) * 0.5;
    return SeparableBlur(r, 1.0 / (2.0 * sigma * sigma), 1.0 / (0.03 * z0 + 1e-6), z0, n0);
}

// One tap of a separable blur: the texel it reads and its weight. Not
// `valid` (left out) off the image or on the background (depth 0).
struct BlurTap {
    pixel: vec2<u32>,
    weight: f32,
    valid: bool,
}

// Tap `o` along `axis` of `blur` about `pixel` of a `size` image.
fn blur_tap(camera: Camera, depth: texture_2d<f32>, normals: texture_2d<f32>, blur: SeparableBlur, pixel: vec2<u32>, axis: vec2<i32>, o: i32, size: vec2<u32>) -> BlurTap {
    let q = vec2<i32>(pixel) + axis * o;
    if (any(q < vec2<i32>(0)) || any(q >= vec2<i32>(size))) {
        return BlurTap(vec2<u32>(0u), 0.0, false);
    }
    let qu = vec2<u32>(q);
    let dq = textureLoad(depth, qu, 0).r;
    if (dq <= 0.0) {
        return BlurTap(qu, 0.0, false);
    }
    let zq = -view_position(camera, qu, dq).z;
    let n0 = blur.centre_normal;
    let nq = safe_normalize(textureLoad(normals, qu, 0).xyz, n0);
    let w = tap_weight(o, blur.spread, zq - blur.centre_distance, blur.reach, dot(n0, nq));
    return BlurTap(qu, w, true);
}

// The same blur on a half-resolution image (crates/render/src/resolution.rs:
// half texel h stands for full pixel 2h): a full-resolution half-width of
// `radius` pixels becomes ceil(radius / 2) half texels and sigma halves
// with it, so the Gaussian covers the same screen extent.
fn separable_blur_half(radius: u32, z0: f32, n0: vec3<f32>) -> SeparableBlur {
    let sigma = max(f32(radius), 1.0) * 0.25;
    return SeparableBlur(i32((radius + 1u) / 2u), 1.0 / (2.0 * sigma * sigma), 1.0 / (0.03 * z0 + 1e-6), z0, n0);
}

// Tap `o` (in half texels) along `axis` of a half-resolution blur about
// half texel `texel`: its surface is read at full pixel 2 (texel + axis o)
// of the `size` G-buffer, its value at the half texel itself (`pixel`).
fn half_blur_tap(camera: Camera, depth: texture_2d<f32>, normals: texture_2d<f32>, blur: SeparableBlur, texel: vec2<u32>, axis: vec2<i32>, o: i32, size: vec2<u32>) -> BlurTap {
    let t = vec2<i32>(texel) + axis * o;
    let q = t * 2;
    if (any(t < vec2<i32>(0)) || any(q >= vec2<i32>(size))) {
        return BlurTap(vec2<u32>(0u), 0.0, false);
    }
    let qu = vec2<u32>(q);
    let dq = textureLoad(depth, qu, 0).r;
    if (dq <= 0.0) {
        return BlurTap(vec2<u32>(t), 0.0, false);
    }
    let zq = -view_position(camera, qu, dq).z;
    let n0 = blur.centre_normal;
    let nq = safe_normalize(textureLoad(normals, qu, 0).xyz, n0);
    let w = tap_weight(o, blur.spread, zq - blur.centre_distance, blur.reach, dot(n0, nq));
    return BlurTap(vec2<u32>(t), w, true);
}

// The packed surface (crates/render/src/packed_surface): one RG32Uint texel
// per pixel with what the depth-aware blurs read of the G-buffer, so a tap
// is one texture read instead of two (depth and normals) and no inverse
// projection. x: the view distance's f32 bits, exactly -view_position(..).z
// (NO_SURFACE where depth is empty); y: the unit normal, octahedron-encoded
// as two 16-bit snorms (NO_NORMAL where the G-buffer's normal has no length).
const NO_SURFACE: u32 = 0xffffffffu;
// pack2x16snorm writes -32767..32767, never 0x8000: free to mean "none".
const NO_NORMAL: u32 = 0x80008000u;

// `v` normalized as safe_normalize does, octahedron-encoded in 32 bits.
fn pack_surface_normal(v: vec3<f32>) -> u32 {
    let len2 = dot(v, v);
    if (!(len2 > 1e-20)) {
        return NO_NORMAL;
    }
    let n = v * inverseSqrt(len2);
    let p = n.xy / (abs(n.x) + abs(n.y) + abs(n.z));
    let folded = (1.0 - abs(p.yx)) * select(vec2<f32>(-1.0), vec2<f32>(1.0), p >= vec2<f32>(0.0));
    return pack2x16snorm(select(folded, p, n.z >= 0.0));
}

// The unit normal a packed texel holds, or `fallback` where it holds none.
fn surface_normal(bits: u32, fallback: vec3<f32>) -> vec3<f32> {
    if (bits == NO_NORMAL) {
        return fallback;
    }
    let e = unpack2x16snorm(bits);
    var n = vec3<f32>(e, 1.0 - abs(e.x) - abs(e.y));
    if (n.z < 0.0) {
        n = vec3<f32>((1.0 - abs(n.yx)) * select(vec2<f32>(-1.0), vec2<f32>(1.0), n.xy >= vec2<f32>(0.0)), n.z);
    }
    // The L1 norm of a decoded point is 1: never zero length.
    return normalize(n);
}

// `blur_tap` over the packed surface: the same weight from the same view
// distance, with the normal to 16-bit octahedron precision.
fn packed_blur_tap(surface: texture_2d<u32>, blur: SeparableBlur, pixel: vec2<u32>, axis: vec2<i32>, o: i32, size: vec2<u32>) -> BlurTap {
    let q = vec2<i32>(pixel) + axis * o;
    if (any(q < vec2<i32>(0)) || any(q >= vec2<i32>(size))) {
        return BlurTap(vec2<u32>(0u), 0.0, false);
    }
    let qu = vec2<u32>(q);
    let s = textureLoad(surface, qu, 0).xy;
    if (s.x == NO_SURFACE) {
        return BlurTap(qu, 0.0, false);
    }
    let n0 = blur.centre_normal;
    let nq = surface_normal(s.y, n0);
    let w = tap_weight(o, blur.spread, bitcast<f32>(s.x) - blur.centre_distance, blur.reach, dot(n0, nq));
    return BlurTap(qu, w, true);
}

// The packed surface's second target (R32Float): view_position(..).z of
// every pixel, the same bits, and EMPTY_Z where depth is empty (no view z
// reaches it). Read by `march_packed`.
const EMPTY_Z: f32 = 3.0e38;

// Step `k` of `steps` of `march`'s ray: the pixel it projects to and the
// ray point's view z; not `on` past the ray's end or off the screen.
struct MarchStep {
    tap: vec2<i32>,
    z: f32,
    on: bool,
}

fn march_step(camera: Camera, origin: vec3<f32>, dir: vec3<f32>, radius: f32, steps: u32, jitter: f32, k: u32) -> MarchStep {
    let size = vec2<i32>(camera.size.xy);
    let q = origin + dir * max(radius * (f32(k) + jitter) / f32(steps), 1e-6);
    let pr = project(camera, q);
    let tap = vec2<i32>(floor(pr.xy));
    let on = k < steps && pr.valid && all(tap >= vec2<i32>(0)) && all(tap < size);
    return MarchStep(tap, q.z, on);
}

// Whether a step blocks the ray: the surface under it (view z `surface`)
// is in front of the ray point by more than `bias` and less than `radius`.
fn march_blocks(surface: f32, s: MarchStep, radius: f32, bias: f32) -> bool {
    let in_front = surface - s.z;
    return surface < EMPTY_Z && in_front > bias && in_front < radius;
}

// The view z under a step's pixel (clamped onto the image: a step that is
// not `on` reads a texel that is never looked at).
fn march_read(view_z: texture_2d<f32>, s: MarchStep, size: vec2<i32>) -> f32 {
    return textureLoad(view_z, vec2<u32>(clamp(s.tap, vec2<i32>(0), size - 1)), 0).r;
}

// `march` over the packed surface's view z, four steps at a time: the four
// pixels first, then their four reads, then the tests in order. The same
// steps, the same z and the same tests as `march`, so the same pixel (or
// -1); what changes is that a ray's reads are in flight together instead
// of each waiting on the test before it, and no step turns a depth into a
// view z. The reads of steps after a hit are made and not used.
fn march_packed(camera: Camera, view_z: texture_2d<f32>, origin: vec3<f32>, dir: vec3<f32>, radius: f32, steps: u32, jitter: f32, bias: f32) -> vec2<i32> {
    let size = vec2<i32>(camera.size.xy);
    for (var k = 0u; k < steps; k += 4u) {
        let a = march_step(camera, origin, dir, radius, steps, jitter, k);
        let b = march_step(camera, origin, dir, radius, steps, jitter, k + 1u);
        let c = march_step(camera, origin, dir, radius, steps, jitter, k + 2u);
        let d = march_step(camera, origin, dir, radius, steps, jitter, k + 3u);
        let za = march_read(view_z, a, size);
        let zb = march_read(view_z, b, size);
        let zc = march_read(view_z, c, size);
        let zd = march_read(view_z, d, size);
        // A step that is not on ends the ray (its end, or the screen's edge).
        if (!a.on) {
            break;
        }
        if (march_blocks(za, a, radius, bias)) {
            return a.tap;
        }
        if (!b.on) {
            break;
        }
        if (march_blocks(zb, b, radius, bias)) {
            return b.tap;
        }
        if (!c.on) {
            break;
        }
        if (march_blocks(zc, c, radius, bias)) {
            return c.tap;
        }
        if (!d.on) {
            break;
        }
        if (march_blocks(zd, d, radius, bias)) {
            return d.tap;
        }
    }
    return vec2<i32>(-1);
}
