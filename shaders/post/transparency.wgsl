// Weighted blended order-independent transparency (McGuire and Bavoil,
// "Weighted Blended Order-Independent Transparency", JCGT 2013), as
// Castor3D's transparent pass does it: transparent meshes are rasterized in
// any order into two targets (cleared in compute first: see `clear`) with
// fixed-function blending,
//   accumulation += (premultiplied colour, alpha) * w(z, alpha)   (One, One)
//   revealage    *= 1 - alpha                                     (Zero, 1 - src)
// each fragment depth-tested by hand against the G-buffer's (opaque) depth,
// and a compute `resolve` composites the weighted average over the opaque
// image by the revealage: opaque * r + average * (1 - r).
//
// The weight is the paper's equation 7, 10 / (1e-5 + (z/5)^2 + (z/200)^6)
// clamped to 1e-2..3e3, divided by 3e3 so it is at most 1: with colours held
// at 600 or less, 100 overlapping layers sum to under 65504, so the
// half-float accumulation cannot overflow at the near plane, and at the far
// plane the smallest weight (3e-6) is still a half float.
//
// Lighting is deliberately simple (the transparent surfaces are not in the
// G-buffer): the layer's colour times an ambient term plus one directional
// key light, lit from both sides (a thin glass-like shell), all in `params`.
// Both faces are drawn, except for one-sided glTF materials (layers with a
// material world), whose back faces the pipeline culls.
//
// The colour and coverage are glTF's base colour: the instance colour
// (factor) x the base colour map (MATERIAL_MAPS: the layer's material world
// has surface maps; group 1 the world, group 3 its map arrays, sampled as
// the G-buffer resolve does, with the map's UV set, sampler and
// KHR_texture_transform) x COLOR_0 (VERTEX_EXTRAS: the arena's extra
// stream, binding 12), alpha included.
#import spreadlight::camera::Camera
#import spreadlight::mesh_fetch::{instances, triangle_vertex, view_right, view_up}
#import spreadlight::post::{sanitize, HALF_MAX}
#ifdef MATERIAL_MAPS
#import spreadlight::material_maps::{MapCoords, sample_map, MAP_BASE_COLOR}
#endif
#ifdef VERTEX_EXTRAS
#import spreadlight::mesh::vertex_color
#import spreadlight::vertex_extras::corner_extra
#endif

struct Params {
    // rgb: ambient radiance
    ambient: vec4<f32>,
    // xyz: direction towards the key light (world, unit)
    light_direction: vec4<f32>,
    // rgb: key light radiance
    light_color: vec4<f32>,
}

@group(0) @binding(0) var<uniform> camera: Camera;
@group(0) @binding(4) var opaque_depth: texture_2d<f32>;
@group(0) @binding(5) var<uniform> params: Params;
@group(0) @binding(6) var opaque: texture_2d<f32>;
@group(0) @binding(7) var accumulation: texture_2d<f32>;
@group(0) @binding(8) var revealage: texture_2d<f32>;
@group(0) @binding(9) var output: texture_storage_2d<rgba16float, write>;
@group(0) @binding(10) var clear_accumulation: texture_storage_2d<rgba16float, write>;
@group(0) @binding(11) var clear_revealage: texture_storage_2d<rgba16float, write>;

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) normal: vec3<f32>,
    @location(1) color: vec4<f32>,
    @location(2) distance: f32,
    @location(3) uv: vec2<f32>,
    @location(4) second_uv: vec2<f32>,
    @location(5) @interpolate(flat) material: u32,
}

@vertex
fn vs(@builtin(vertex_index) vertex: u32, @builtin(instance_index) instance_index: u32) -> VertexOut {
    // A mirroring transform turns the winding around: corners taken in the
    // other order, so culling (one-sided glTF materials) culls back faces.
    let m = instances[instance_index].model;
    let mirrored = determinant(mat3x3<f32>(m[0].xyz, m[1].xyz, m[2].xyz)) < 0.0;
    let corner = select(vertex % 3u, (3u - vertex % 3u) % 3u, mirrored);
    let v = triangle_vertex(instance_index, vertex / 3u, corner, view_right(camera.view), view_up(camera.view));
    let world = instances[instance_index].model * vec4<f32>(v.position_u.xyz, 1.0);
    var out: VertexOut;
    out.clip = camera.view_projection * world;
    out.normal = (instances[instance_index].normal_matrix * vec4<f32>(v.normal_v.xyz, 0.0)).xyz;
    out.color = instances[instance_index].color;
    out.distance = -(camera.view * world).z;
    out.uv = vec2<f32>(v.position_u.w, v.normal_v.w);
    out.second_uv = out.uv;
    out.material = instances[instance_index].info.z;
#ifdef VERTEX_EXTRAS
    let extra = corner_extra(instance_index, vertex / 3u, corner, v);
    out.second_uv = extra.second_uv;
    // glTF: base colour = factor x texture x COLOR_0 (alpha too).
    out.color *= vertex_color(extra);
#endif
    return out;
}

struct Accumulated {
    @location(0) accumulation: vec4<f32>,
    @location(1) revealage: vec4<f32>,
}

fn weight(z: f32, alpha: f32) -> f32 {
    let d = max(z, 0.0);
    let w = 10.0 / (1e-5 + pow(d / 5.0, 2.0) + pow(min(d / 200.0, 1e5), 6.0));
    return alpha * clamp(w, 1e-2, 3e3) / 3e3;
}

@fragment
fn fs(in: VertexOut) -> Accumulated {
    var base = in.color;
#ifdef MATERIAL_MAPS
    // Derivatives first, in uniform control flow.
    var coords: MapCoords;
    coords.uv = in.uv;
    coords.dx = dpdx(in.uv);
    coords.dy = dpdy(in.uv);
    coords.second_uv = in.second_uv;
    coords.second_dx = dpdx(in.second_uv);
    coords.second_dy = dpdy(in.second_uv);
    base *= max(sample_map(in.material, MAP_BASE_COLOR, coords, vec4<f32>(1.0)), vec4<f32>(0.0));
#endif
    // Behind the opaque surface (reversed-Z: a smaller depth is further): hidden.
    let opaque_z = textureLoad(opaque_depth, vec2<i32>(in.clip.xy), 0).r;
    let alpha = clamp(sanitize(base).a, 0.0, 1.0);
    if (in.clip.z < opaque_z || alpha < 1e-4) {
        discard;
    }
    let n = normalize(in.normal + vec3<f32>(0.0, 0.0, 1e-12));
    let lambert = abs(dot(n, params.light_direction.xyz));
    let radiance = params.ambient.rgb + params.light_color.rgb * lambert;
    let color = clamp(sanitize(vec4<f32>(base.rgb * radiance, 0.0)).rgb, vec3<f32>(0.0), vec3<f32>(600.0));
    let w = weight(in.distance, alpha);
    var out: Accumulated;
    out.accumulation = vec4<f32>(color * alpha, alpha) * w;
    out.revealage = vec4<f32>(alpha);
    return out;
}

@compute @workgroup_size(8, 8)
fn resolve(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(output);
    if (id.x >= size.x || id.y >= size.y) {
        return;
    }
    let p = vec2<i32>(id.xy);
    let base = sanitize(textureLoad(opaque, p, 0));
    // An overflowed sum reads as infinity: held at the top of the range, never NaN.
    let sum = sanitize(min(textureLoad(accumulation, p, 0), vec4<f32>(HALF_MAX)));
    let r = clamp(sanitize(textureLoad(revealage, p, 0)).r, 0.0, 1.0);
    if (r >= 1.0 || sum.a <= 0.0) {
        textureStore(output, id.xy, base);
        return;
    }
    let average = sum.rgb / clamp(sum.a, 1e-7, HALF_MAX);
    let color = base.rgb * r + average * (1.0 - r);
    textureStore(output, id.xy, vec4<f32>(clamp(color, vec3<f32>(0.0), vec3<f32>(HALF_MAX)), base.a));
}

// The targets' starting values (nothing accumulated, everything revealed),
// written in compute before the accumulation loads them: a render pass's
// clear costs raster output bandwidth.
@compute @workgroup_size(8, 8)
fn clear(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(clear_accumulation);
    if (id.x >= size.x || id.y >= size.y) {
        return;
    }
    textureStore(clear_accumulation, id.xy, vec4<f32>(0.0));
    textureStore(clear_revealage, id.xy, vec4<f32>(1.0));
}
