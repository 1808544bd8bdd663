// EnvironmentProbe's faces (crates/render/src/environment/probe/faces.rs):
// the layer drawn from the probe into one cube face per render pass, each
// surface shaded forward with the probe's own lighting:
//   radiance = albedo * (ambient + sun_color * max(N.L, 0) * shadow)
// albedo the instance colour times the layer's Color Texture (COLOR_MAP);
// N turned towards the probe (both sides are drawn: a probe inside an
// object sees its inside lit, not black), then perturbed by the layer's
// Normal Map (NORMAL_MAP) as the G-buffer resolve perturbs it; both
// textures by the mesh's UVs (TEXCOORDS; the normal map with the mesh's
// tangents) or blended over three planar projections (TRIPLANAR); group 1.
// SHADOWS: the sun is shadowed by a ShadowMap (Sun)'s maps, slice
// `face.shadow.x`, in the finest cascade that holds the point (the cascades
// follow the camera, not the probe: beyond them all, lit), filtered with
// PCF over the maps' kernel (SHADOW_PCF, whatever the node's filter; its
// depth maps are there for every filter). A mirror needs the colours and
// the rough shape of its surroundings, at a fraction of a G-buffer's
// cost: no point or spot lights, no material world, no glTF surface maps.
// Vertices are pulled from the mesh arena by index (spreadlight::mesh_fetch),
// as the shadow depth pass pulls them. Clamped below half-float overflow;
// NaN is 0.
#import spreadlight::mesh_fetch::{instances, triangle_vertex, view_right, view_up}
#import spreadlight::packing::{safe_normalize}
#ifdef SHADOWS
#import spreadlight::shadow_sampling::sun_shadow_anywhere
#endif

struct ProbeFace {
    // World to clip: x = uv.x, y = -uv.y, z = near, w = distance along the face's axis.
    view_projection: mat4x4<f32>,
    // Where the probe is (w unused).
    position: vec4<f32>,
    // Towards the sun, unit (w unused).
    towards_sun: vec4<f32>,
    sun_color: vec4<f32>,
    ambient: vec4<f32>,
    // x: the sun's slice of the shadow maps (SHADOWS); yzw unused.
    shadow: vec4<u32>,
}

@group(0) @binding(0) var<uniform> face: ProbeFace;
#ifdef COLOR_MAP
@group(1) @binding(0) var color_map: texture_2d<f32>;
@group(1) @binding(1) var color_sampler: sampler;
#endif
#ifdef TRIPLANAR
struct ProbeLayer {
    // The exponent of the normal's components weighting the projections
    // (DeferredBase's Triplanar, Triplanar (Layer)'s Sharpness).
    triplanar_sharpness: f32,
    pad0: f32,
    pad1: f32,
    pad2: f32,
}
@group(1) @binding(2) var<uniform> probe_layer: ProbeLayer;
#endif
#ifdef NORMAL_MAP
@group(1) @binding(3) var normal_map: texture_2d<f32>;
@group(1) @binding(4) var normal_sampler: sampler;
#endif

const HALF_MAX: f32 = 65000.0;

struct Varyings {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) albedo: vec3<f32>,
    @location(3) uv: vec2<f32>,
    // World-space tangent (the model matrix's, as the resolve takes it), w its handedness.
    @location(4) tangent: vec4<f32>,
}

@vertex
fn vs(@builtin(vertex_index) vertex: u32, @builtin(instance_index) instance: u32) -> Varyings {
    // Sprites face the probe (the view-projection's rows point along the face's axes).
    let v = triangle_vertex(instance, vertex / 3u, vertex % 3u, view_right(face.view_projection), view_up(face.view_projection));
    let record = instances[instance];
    let world = record.model * vec4<f32>(v.position_u.xyz, 1.0);
    var out: Varyings;
    out.clip = face.view_projection * world;
    out.world = world.xyz / world.w;
    out.normal = (record.normal_matrix * vec4<f32>(v.normal_v.xyz, 0.0)).xyz;
    out.albedo = record.color.rgb;
    out.uv = vec2<f32>(v.position_u.w, v.normal_v.w);
    out.tangent = vec4<f32>((record.model * vec4<f32>(v.tangent.xyz, 0.0)).xyz, v.tangent.w);
    return out;
}

@fragment
fn fs(in: Varyings) -> @location(0) vec4<f32> {
    let to_probe = face.position.xyz - in.world;
    var n = safe_normalize(in.normal, safe_normalize(to_probe, vec3<f32>(0.0, 1.0, 0.0)));
    if (dot(n, to_probe) < 0.0) {
        n = -n;
    }
    // The surface's own normal, for the shadow's normal offset.
    let geometric = n;
    var albedo = max(in.albedo, vec3<f32>(0.0));
    // Level 0: a probe's faces are small and the prefilter blurs them anyway.
#ifdef TRIPLANAR
    let world_n = safe_normalize(in.normal, vec3<f32>(0.0, 1.0, 0.0));
    var w = pow(abs(world_n) + vec3<f32>(1e-5), vec3<f32>(max(probe_layer.triplanar_sharpness, 1.0)));
    w = w / (w.x + w.y + w.z);
#endif
#ifdef COLOR_MAP
#ifdef TRIPLANAR
    let texel = textureSampleLevel(color_map, color_sampler, fract(in.world.zy), 0.0).rgb * w.x
        + textureSampleLevel(color_map, color_sampler, fract(in.world.xz), 0.0).rgb * w.y
        + textureSampleLevel(color_map, color_sampler, fract(in.world.xy), 0.0).rgb * w.z;
#else
    let texel = textureSampleLevel(color_map, color_sampler, in.uv, 0.0).rgb;
#endif
    albedo *= max(texel, vec3<f32>(0.0));
#endif
#ifdef NORMAL_MAP
#ifdef TRIPLANAR
    // Three tangent-space samples, each reoriented onto the surface by the
    // whiteout blend of its projection's axis, weighted like the colour
    // (gbuffer/resolve.wgsl's TRIPLANAR normal map).
    let tx = textureSampleLevel(normal_map, normal_sampler, fract(in.world.zy), 0.0).xyz * 2.0 - 1.0;
    let ty = textureSampleLevel(normal_map, normal_sampler, fract(in.world.xz), 0.0).xyz * 2.0 - 1.0;
    let tz = textureSampleLevel(normal_map, normal_sampler, fract(in.world.xy), 0.0).xyz * 2.0 - 1.0;
    let bx = vec3<f32>(tx.xy + n.zy, abs(tx.z) * n.x);
    let by = vec3<f32>(ty.xy + n.xz, abs(ty.z) * n.y);
    let bz = vec3<f32>(tz.xy + n.xy, abs(tz.z) * n.z);
    n = safe_normalize(bx.zyx * w.x + by.xzy * w.y + bz * w.z, n);
#else
    // The mesh's tangent frame, as the resolve builds it.
    let t = safe_normalize(in.tangent.xyz, vec3<f32>(1.0, 0.0, 0.0));
    let bt = cross(n, t) * select(-1.0, 1.0, in.tangent.w >= 0.0);
    let tangent_texel = textureSampleLevel(normal_map, normal_sampler, in.uv, 0.0).xyz * 2.0 - 1.0;
    n = safe_normalize(t * tangent_texel.x + bt * tangent_texel.y + n * tangent_texel.z, n);
#endif
#endif
    let towards_sun = face.towards_sun.xyz;
    var sun = max(dot(n, towards_sun), 0.0);
#ifdef SHADOWS
    if (sun > 0.0) {
        sun *= sun_shadow_anywhere(face.shadow.x, in.world, geometric, dot(geometric, towards_sun));
    }
#endif
    let light = face.ambient.rgb + face.sun_color.rgb * sun;
    let c = min(max(albedo * light, vec3<f32>(0.0)), vec3<f32>(HALF_MAX));
    return vec4<f32>(select(vec3<f32>(0.0), c, c == c), 1.0);
}
