// AO's temporal accumulation, shared by ssao/temporal.wgsl (after a
// half-resolution estimate is upsampled) and ssao/ao.wgsl's TEMPORAL
// (a full-resolution estimate blended in the pass that makes it, so no raw
// target and no second pass). Each pixel looks up where it was last frame
// (its G-buffer velocity, UV units per frame), and blends last frame's
// result in when that texel saw the same surface: its stored view distance
// matches this point's distance from last frame's camera within 5%, and its
// stored world normal within ~37 degrees. Otherwise (a disocclusion, the
// screen's edge, a reset, a fresh history) the raw value stands alone. A
// history texel that is not finite is never used, so one NaN cannot spread.
// The history texel: visibility, view distance, world normal
// octahedron-encoded.
#define_import_path spreadlight::ao_history
#import spreadlight::camera::Camera
#import spreadlight::packing::safe_normalize

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

// The history texel where nothing was seen (the sky): never reused.
const SKY: vec4<f32> = vec4<f32>(1.0, 0.0, 0.0, 0.0);

// The history texel of `pixel`: this frame's visibility `raw`, at view
// position `p` with the G-buffer's view-space normal `n_view`, blended with
// last frame's (`previous`, reprojected along `velocity_uv`) unless
// `reuse` is false (a reset or a fresh history).
fn accumulate(
    camera: Camera,
    raw: f32,
    pixel: vec2<u32>,
    p: vec3<f32>,
    n_view: vec3<f32>,
    velocity_uv: texture_2d<f32>,
    previous: texture_2d<f32>,
    reuse: bool,
    blend: f32,
) -> vec4<f32> {
    let n = safe_normalize((camera.view_inverse * vec4<f32>(n_view, 0.0)).xyz, vec3<f32>(0.0, 1.0, 0.0));
    var ao = clamp(raw, 0.0, 1.0);
    let uv = (vec2<f32>(pixel) + 0.5) * camera.size.zw;
    var velocity = textureLoad(velocity_uv, pixel, 0).xy;
    if (!all(abs(velocity) <= vec2<f32>(1e6))) {
        velocity = vec2<f32>(1e6);
    }
    let before = uv - velocity;
    if (reuse && all(before >= vec2<f32>(0.0)) && all(before < vec2<f32>(1.0))) {
        // The history's own size: the frame's, or half of it (AO's half
        // chain, whose texel t stands for full pixel 2t).
        let history_size = textureDimensions(previous);
        let texel = min(vec2<u32>(before * vec2<f32>(history_size)), history_size - 1u);
        let h = textureLoad(previous, texel, 0);
        let world = camera.view_inverse * vec4<f32>(p, 1.0);
        // Reversed-Z perspective: clip w is the view distance.
        let expected = (camera.previous_view_projection * world).w;
        let same_depth = abs(h.y - expected) <= 0.05 * expected + 1e-3;
        let same_normal = dot(oct_decode(h.zw), n) > 0.8;
        if (finite4(h) && h.y > 0.0 && h.y < 65000.0 && same_depth && same_normal) {
            ao = mix(ao, clamp(h.x, 0.0, 1.0), blend);
        }
    }
    // Beyond half-float range the distance would store inf: 65000 is "too far to reuse".
    return vec4<f32>(ao, min(-p.z, 65000.0), oct_encode(n));
}
