// DeferredBase, compute half (the MRE resolve): turns the visibility buffer
// into Emeshe's MRE layout. For each pixel of this layer it fetches the
// triangle, computes perspective-correct barycentrics from the pixel centre,
// and interpolates the attributes. Dispatched once per layer with that
// layer's feature switches, so a layer pays only for what it asked for.
//
// Without MOTION: color (RGB) + material id (A), view-space normal (RGB) + object id (A).
// With MOTION:    velocity in UV units per frame (RG) + texture coordinates (BA).
#import spreadlight::camera::{Camera, pixel_to_ndc}
#import spreadlight::mesh::{Vertex, Instance}
#import spreadlight::packing::{id_to_channel, safe_normalize}

struct Layer {
    first_instance: u32,
    end_instance: u32,
    // 1 for the first layer: it also clears the pixels no layer covers.
    write_background: u32,
    _pad: u32,
}

@group(0) @binding(0) var<uniform> camera: Camera;
@group(0) @binding(1) var<storage, read> vertices: array<Vertex>;
@group(0) @binding(2) var<storage, read> indices: array<u32>;
@group(0) @binding(3) var<storage, read> instances: array<Instance>;
@group(0) @binding(4) var visibility: texture_2d<u32>;
@group(0) @binding(5) var<uniform> layer: Layer;
#ifdef MOTION
@group(0) @binding(6) var out_velocity_uv: texture_storage_2d<rgba16float, write>;
#else
@group(0) @binding(6) var out_color: texture_storage_2d<rgba16float, write>;
@group(0) @binding(7) var out_normal: texture_storage_2d<rgba16float, write>;
#endif
#ifdef NORMAL_MAP
@group(1) @binding(0) var normal_map: texture_2d<f32>;
@group(1) @binding(1) var normal_sampler: sampler;
#endif

fn cross2(a: vec2<f32>, b: vec2<f32>) -> f32 {
    return a.x * b.y - a.y * b.x;
}

// Perspective-correct barycentrics of `p` (NDC) in the triangle with clip
// positions c0..c2. A degenerate (zero-area) triangle gives (1, 0, 0), never NaN.
fn barycentrics(p: vec2<f32>, c0: vec4<f32>, c1: vec4<f32>, c2: vec4<f32>) -> vec3<f32> {
    let inv_w = 1.0 / vec3<f32>(c0.w, c1.w, c2.w);
    let n0 = c0.xy * inv_w.x;
    let n1 = c1.xy * inv_w.y;
    let n2 = c2.xy * inv_w.z;
    let e1 = n1 - n0;
    let e2 = n2 - n0;
    let area = cross2(e1, e2);
    if (abs(area) < 1e-12) {
        return vec3<f32>(1.0, 0.0, 0.0);
    }
    let u = cross2(p - n0, e2) / area;
    let v = cross2(e1, p - n0) / area;
    let screen = vec3<f32>(1.0 - u - v, u, v);
    let weighted = screen * inv_w;
    let sum = weighted.x + weighted.y + weighted.z;
    if (abs(sum) < 1e-20) {
        return screen;
    }
    return weighted / sum;
}

fn interpolate3(b: vec3<f32>, a0: vec3<f32>, a1: vec3<f32>, a2: vec3<f32>) -> vec3<f32> {
    return a0 * b.x + a1 * b.y + a2 * b.z;
}

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = vec2<u32>(camera.size.xy);
    if (id.x >= size.x || id.y >= size.y) {
        return;
    }
    let pixel = id.xy;
    let ids = textureLoad(visibility, pixel, 0).xy;
    if (ids.x == 0u || ids.x - 1u < layer.first_instance || ids.x - 1u >= layer.end_instance) {
        if (ids.x == 0u && layer.write_background == 1u) {
#ifdef MOTION
            textureStore(out_velocity_uv, pixel, vec4<f32>(0.0));
#else
            textureStore(out_color, pixel, vec4<f32>(0.0));
            textureStore(out_normal, pixel, vec4<f32>(0.0));
#endif
        }
        return;
    }
    let instance = instances[ids.x - 1u];
    let first = instance.info.x + ids.y * 3u;
    let v0 = vertices[indices[first] + instance.info.y];
    let v1 = vertices[indices[first + 1u] + instance.info.y];
    let v2 = vertices[indices[first + 2u] + instance.info.y];
    let clip_from_object = camera.view_projection * instance.model;
    let c0 = clip_from_object * vec4<f32>(v0.position_u.xyz, 1.0);
    let c1 = clip_from_object * vec4<f32>(v1.position_u.xyz, 1.0);
    let c2 = clip_from_object * vec4<f32>(v2.position_u.xyz, 1.0);
    let b = barycentrics(pixel_to_ndc(pixel, camera.size), c0, c1, c2);

#ifdef TEXCOORDS
    let uv = vec2<f32>(
        dot(b, vec3<f32>(v0.position_u.w, v1.position_u.w, v2.position_u.w)),
        dot(b, vec3<f32>(v0.normal_v.w, v1.normal_v.w, v2.normal_v.w)),
    );
#else
#ifdef TRIPLANAR
    // Planar projection on the axis the surface faces most: texture
    // coordinates for geometry that has none.
    let world = (instance.model * vec4<f32>(interpolate3(b, v0.position_u.xyz, v1.position_u.xyz, v2.position_u.xyz), 1.0)).xyz;
    let face_normal = abs(interpolate3(b, v0.normal_v.xyz, v1.normal_v.xyz, v2.normal_v.xyz));
    var uv = fract(world.xy);
    if (face_normal.x >= face_normal.y && face_normal.x >= face_normal.z) {
        uv = fract(world.zy);
    } else if (face_normal.y >= face_normal.z) {
        uv = fract(world.xz);
    }
#else
    let uv = vec2<f32>(0.0);
#endif
#endif

#ifdef MOTION
    let object_now = interpolate3(b, v0.position_u.xyz, v1.position_u.xyz, v2.position_u.xyz);
#ifdef VELOCITY_FROM_GEOMETRY
    let object_before = interpolate3(b, v0.previous_position.xyz, v1.previous_position.xyz, v2.previous_position.xyz);
#else
    let object_before = object_now;
#endif
    let now = camera.view_projection * instance.model * vec4<f32>(object_now, 1.0);
    let before = camera.previous_view_projection * instance.previous_model * vec4<f32>(object_before, 1.0);
    var velocity = vec2<f32>(0.0);
    if (now.w > 1e-6 && before.w > 1e-6) {
        velocity = (now.xy / now.w - before.xy / before.w) * vec2<f32>(0.5, -0.5);
    }
    textureStore(out_velocity_uv, pixel, vec4<f32>(velocity, uv));
#else
    let normal_object = interpolate3(b, v0.normal_v.xyz, v1.normal_v.xyz, v2.normal_v.xyz);
    var normal_world = safe_normalize((instance.normal_matrix * vec4<f32>(normal_object, 0.0)).xyz, vec3<f32>(0.0, 1.0, 0.0));
#ifdef NORMAL_MAP
    let tangent4 = v0.tangent * b.x + v1.tangent * b.y + v2.tangent * b.z;
    let tangent_world = safe_normalize((instance.model * vec4<f32>(tangent4.xyz, 0.0)).xyz, vec3<f32>(1.0, 0.0, 0.0));
    let sign = select(-1.0, 1.0, tangent4.w >= 0.0);
    let bitangent_world = cross(normal_world, tangent_world) * sign;
    let texel = textureSampleLevel(normal_map, normal_sampler, uv, 0.0).xyz * 2.0 - 1.0;
    normal_world = safe_normalize(
        tangent_world * texel.x + bitangent_world * texel.y + normal_world * texel.z,
        normal_world,
    );
#endif
    let normal_view = safe_normalize((camera.view * vec4<f32>(normal_world, 0.0)).xyz, vec3<f32>(0.0, 0.0, 1.0));
    textureStore(out_color, pixel, vec4<f32>(instance.color.rgb, id_to_channel(instance.info.z)));
    textureStore(out_normal, pixel, vec4<f32>(normal_view, id_to_channel(instance.info.w)));
#endif
}
