// Screen-space helpers for passes over the G-buffer: view positions from
// reversed-Z depth, projection back to pixels, and per-pixel noise.
#define_import_path spreadlight::screen
#import spreadlight::camera::{Camera, pixel_to_ndc}

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
