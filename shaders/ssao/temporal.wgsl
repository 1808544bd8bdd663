// AO's temporal accumulation as a pass of its own: for an estimate made at
// half resolution and upsampled (a full-resolution estimate blends in its
// own pass, ssao/ao.wgsl's TEMPORAL). The blend is
// spreadlight::ao_history::accumulate (shaders/lib/ao_history.wgsl).
// HALF (AO's half-resolution chain): one thread per half texel, blending at
// the full pixel it stands for (2h: its depth, normal and velocity) into a
// half-size history; `accumulate` reads last frame's at the history's size.
#import spreadlight::camera::Camera
#import spreadlight::packing::safe_normalize
#import spreadlight::screen::{RayParams, view_position}
#import spreadlight::ao_history::{accumulate, SKY}

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

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = vec2<u32>(camera.size.xy);
#ifdef HALF
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
    if (d <= 0.0) {
        textureStore(history, id.xy, SKY);
        return;
    }
    let p = view_position(camera, pixel, d);
    let n_view = safe_normalize(textureLoad(normals, pixel, 0).xyz, vec3<f32>(0.0, 0.0, 1.0));
    let reuse = params.reset == 0u && temporal.fresh == 0u;
    let raw_ao = textureLoad(raw, id.xy, 0).r;
    textureStore(history, id.xy, accumulate(camera, raw_ao, pixel, p, n_view, velocity_uv, previous, reuse, params.blend));
}
