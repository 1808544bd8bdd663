// AO's temporal accumulation. Each pixel looks up where it was last frame
// (its G-buffer velocity, UV units per frame), and blends last frame's
// result in when that texel saw the same surface: its stored view
// distance matches this point's distance from last frame's camera within
// 5%, and its stored world normal within ~37 degrees. Otherwise (a
// disocclusion, the screen's edge, a reset, a fresh history) the raw value
// stands alone. A history texel that is not finite is never used, so one
// NaN cannot spread. Output (the new history): visibility, view distance,
// world normal octahedron-encoded.
#import spreadlight::camera::Camera
#import spreadlight::packing::safe_normalize
#import spreadlight::screen::{RayParams, view_position}

struct Temporal {
    // 1: the history texture was created this frame and holds nothing.
    fresh: u32,
    _pad0: u32,
    _pad1: u32,
    _pad2: u32,
}

@group(0) @binding(0) var<uniform> camera: Camera;
@group(0) @binding(1) var<uniform> params: RayParams;
@group(0) @binding(2) var raw: texture_2d<f32>;
@group(0) @binding(3) var depth: texture_2d<f32>;
@group(0) @binding(4) var normals: texture_2d<f32>;
@group(0) @binding(5) var velocity_uv: texture_2d<f32>;
@group(0) @binding(6) var previous: texture_2d<f32>;
@group(0) @binding(7) var history: texture_storage_2d<rgba16float, write>;
@group(0) @binding(8) var<uniform> temporal: Temporal;

fn oct_encode(n: vec3<f32>) -> vec2<f32> {
    let p = n.xy / (abs(n.x) + abs(n.y) + abs(n.z));
    if (n.z >= 0.0) {
        return p;
    }
    return (1.0 - abs(p.yx)) * select(vec2<f32>(-1.0), vec2<f32>(1.0), p >= vec2<f32>(0.0));
}

fn oct_decode(e: vec2<f32>) -> vec3<f32> {
    var n = vec3<f32>(e, 1.0 - abs(e.x) - abs(e.y));
    if (n.z < 0.0) {
        n = vec3<f32>((1.0 - abs(n.yx)) * select(vec2<f32>(-1.0), vec2<f32>(1.0), n.xy >= vec2<f32>(0.0)), n.z);
    }
    return safe_normalize(n, vec3<f32>(0.0, 0.0, 1.0));
}

fn finite4(v: vec4<f32>) -> bool {
    // NaN fails every comparison; infinity fails the bound.
    return all(abs(v) <= vec4<f32>(1e30));
}

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = vec2<u32>(camera.size.xy);
    if (id.x >= size.x || id.y >= size.y) {
        return;
    }
    let pixel = id.xy;
    let d = textureLoad(depth, pixel, 0).r;
    if (d <= 0.0) {
        textureStore(history, pixel, vec4<f32>(1.0, 0.0, 0.0, 0.0));
        return;
    }
    let p = view_position(camera, pixel, d);
    let n_view = safe_normalize(textureLoad(normals, pixel, 0).xyz, vec3<f32>(0.0, 0.0, 1.0));
    let n = safe_normalize((camera.view_inverse * vec4<f32>(n_view, 0.0)).xyz, vec3<f32>(0.0, 1.0, 0.0));
    var ao = clamp(textureLoad(raw, pixel, 0).r, 0.0, 1.0);
    let uv = (vec2<f32>(pixel) + 0.5) * camera.size.zw;
    var velocity = textureLoad(velocity_uv, pixel, 0).xy;
    if (!all(abs(velocity) <= vec2<f32>(1e6))) {
        velocity = vec2<f32>(1e6);
    }
    let before = uv - velocity;
    if (params.reset == 0u && temporal.fresh == 0u && all(before >= vec2<f32>(0.0)) && all(before < vec2<f32>(1.0))) {
        let texel = min(vec2<u32>(before * camera.size.xy), size - 1u);
        let h = textureLoad(previous, texel, 0);
        let world = camera.view_inverse * vec4<f32>(p, 1.0);
        // Reversed-Z perspective: clip w is the view distance.
        let expected = (camera.previous_view_projection * world).w;
        let same_depth = abs(h.y - expected) <= 0.05 * expected + 1e-3;
        let same_normal = dot(oct_decode(h.zw), n) > 0.8;
        if (finite4(h) && h.y > 0.0 && h.y < 65000.0 && same_depth && same_normal) {
            ao = mix(ao, clamp(h.x, 0.0, 1.0), params.blend);
        }
    }
    // Beyond half-float range the distance would store inf: 65000 is "too far to reuse".
    textureStore(history, pixel, vec4<f32>(ao, min(-p.z, 65000.0), oct_encode(n)));
}
