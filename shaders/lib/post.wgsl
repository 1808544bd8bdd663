// What the post passes share: sanitizing, clamped and bilinear loads (by
// hand, so any float format works, filterable or not), luminance, and the
// inverse view depth of a reversed-Z depth sample.
#define_import_path spreadlight::post

const HALF_MAX: f32 = 65000.0;

// NaN and infinity become 0; the rest is held within what a half float stores.
fn sanitize(c: vec4<f32>) -> vec4<f32> {
    let ok = (c == c) & (abs(c) < vec4<f32>(3.0e38));
    return clamp(select(vec4<f32>(0.0), c, ok), vec4<f32>(-HALF_MAX), vec4<f32>(HALF_MAX));
}

fn sanitize_scalar(v: f32) -> f32 {
    return select(0.0, v, v == v && abs(v) < 3.0e38);
}

fn load_clamped(t: texture_2d<f32>, p: vec2<i32>) -> vec4<f32> {
    let hi = vec2<i32>(textureDimensions(t)) - 1;
    return textureLoad(t, clamp(p, vec2<i32>(0), hi), 0);
}

fn bilinear(t: texture_2d<f32>, uv: vec2<f32>) -> vec4<f32> {
    let size = vec2<f32>(textureDimensions(t));
    let p = uv * size - 0.5;
    let base = floor(p);
    let f = p - base;
    let i = vec2<i32>(base);
    let a = load_clamped(t, i);
    let b = load_clamped(t, i + vec2<i32>(1, 0));
    let c = load_clamped(t, i + vec2<i32>(0, 1));
    let d = load_clamped(t, i + vec2<i32>(1, 1));
    return mix(mix(a, b, f.x), mix(c, d, f.x), f.y);
}

fn luminance(c: vec3<f32>) -> f32 {
    return dot(c, vec3<f32>(0.2126, 0.7152, 0.0722));
}

// 1 / (distance along the view axis) of a reversed-Z depth sample: 0 at
// infinity (the sky, an infinite far plane), never NaN.
fn inverse_view_depth(projection_inverse: mat4x4<f32>, d: f32) -> f32 {
    let h = projection_inverse * vec4<f32>(0.0, 0.0, d, 1.0);
    // View space looks down -z: the distance is -h.z / h.w.
    let inv = -h.w / min(h.z, -1e-30);
    return max(sanitize_scalar(inv), 0.0);
}

// A small integer hash (PCG), for per-pixel sample rotations.
fn hash(v: u32) -> u32 {
    let state = v * 747796405u + 2891336453u;
    let word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

fn hash2(p: vec2<u32>) -> f32 {
    return f32(hash(p.x ^ hash(p.y))) / 4294967295.0;
}
