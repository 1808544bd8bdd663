// GBufferView: one G-buffer channel made visible, for debugging. Exactly one
// channel feature is set per permutation, and only its target is bound, so
// the frame graph can cull the passes the other channels would need.
#import spreadlight::camera::Camera

struct ViewParams {
    // Velocity is tiny in UV units; this scales it into view.
    velocity_scale: f32,
    _pad0: f32,
    _pad1: f32,
    _pad2: f32,
}

@group(0) @binding(0) var<uniform> camera: Camera;
@group(0) @binding(1) var<uniform> params: ViewParams;
@group(0) @binding(2) var output: texture_storage_2d<rgba16float, write>;
#ifdef ALBEDO
@group(0) @binding(3) var source: texture_2d<f32>;
#endif
#ifdef MATERIAL_ID
@group(0) @binding(3) var source: texture_2d<f32>;
#endif
#ifdef NORMALS
@group(0) @binding(3) var source: texture_2d<f32>;
#endif
#ifdef OBJECT_ID
@group(0) @binding(3) var source: texture_2d<f32>;
#endif
#ifdef VELOCITY
@group(0) @binding(3) var source: texture_2d<f32>;
#endif
#ifdef UV
@group(0) @binding(3) var source: texture_2d<f32>;
#endif
#ifdef DEPTH
@group(0) @binding(3) var source: texture_2d<f32>;
#endif

// A stable, distinct colour per id, so neighbouring ids are told apart.
fn id_color(id: u32) -> vec3<f32> {
    if (id == 0u) {
        return vec3<f32>(0.0);
    }
    var h = id * 2654435761u;
    h = h ^ (h >> 15u);
    return vec3<f32>(f32(h & 255u), f32((h >> 8u) & 255u), f32((h >> 16u) & 255u)) / 255.0;
}

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = vec2<u32>(camera.size.xy);
    if (id.x >= size.x || id.y >= size.y) {
        return;
    }
    let p = id.xy;
    var value = vec3<f32>(0.0);
#ifdef ALBEDO
    value = textureLoad(source, p, 0).rgb;
#endif
#ifdef MATERIAL_ID
    value = id_color(u32(round(textureLoad(source, p, 0).a)));
#endif
#ifdef NORMALS
    let n = textureLoad(source, p, 0).xyz;
    value = select(n * 0.5 + 0.5, vec3<f32>(0.0), dot(n, n) == 0.0);
#endif
#ifdef OBJECT_ID
    value = id_color(u32(round(textureLoad(source, p, 0).a)));
#endif
#ifdef VELOCITY
    value = vec3<f32>(abs(textureLoad(source, p, 0).xy) * params.velocity_scale, 0.0);
#endif
#ifdef UV
    value = vec3<f32>(textureLoad(source, p, 0).zw, 0.0);
#endif
#ifdef DEPTH
    // Reversed-Z: 1 at the near plane. Shown as 1 / (1 + view distance).
    let d = textureLoad(source, p, 0).r;
    if (d > 0.0) {
        let view = camera.projection_inverse * vec4<f32>(0.0, 0.0, d, 1.0);
        value = vec3<f32>(1.0 / (1.0 + abs(view.z / view.w)));
    }
#endif
    textureStore(output, p, vec4<f32>(value, 1.0));
}
