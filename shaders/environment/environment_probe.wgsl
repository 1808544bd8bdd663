// EnvironmentProbe's faces (crates/render/src/environment/probe/faces.rs):
// the layer drawn from the probe into one cube face per render pass, each
// surface shaded forward with the probe's own lighting:
//   radiance = albedo * (ambient * occlusion + sun_color * max(N.L, 0) * shadow) + emission
// albedo the instance colour times the layer's Color Texture (COLOR_MAP);
// N turned towards the probe (both sides are drawn: a probe inside an
// object sees its inside lit, not black), then perturbed by the layer's
// Normal Map (NORMAL_MAP) as the G-buffer resolve perturbs it; both
// textures by the mesh's UVs (TEXCOORDS; the normal map with the mesh's
// tangents) or blended over three planar projections (TRIPLANAR); group 2.
// MATERIAL_MAPS: a glTF layer's surface maps (group 1 its material world,
// group 3 the map arrays, read as the G-buffer resolve reads them, by
// TEXCOORD_0): base colour, normal (with its scale), metallic-roughness,
// occlusion (of the ambient) and emissive (times the Emission feature).
// SHADOWS (base pass): the sun is shadowed by a ShadowMap (Sun)'s maps, slice
// `face.shadow.x`, in the finest cascade that holds the point (the cascades
// follow the camera, not the probe: beyond them all, lit), filtered with
// PCF over the maps' kernel (SHADOW_PCF, whatever the node's filter; its
// depth maps are there for every filter).
// LIGHT_PASS: the same surface drawn again, per point or spot light buffer
// (LIGHT_SPOT, SPOT_TEXTURE; SHADOWS and its filter: that buffer's shadow
// maps), adding the Cook-Torrance light of its first `face.light_params.x` lights
// (lib/forward_light.wgsl: the very function lit transparency calls, so a
// light reaches the probe's view of a wall as it reaches the wall), the
// viewer at the probe; roughness and metallic the material world's
// CookTorrance feature and metallic-roughness map (MATERIAL_MAPS), else
// `face.light_params.yz`. A mirror needs the colours and the rough shape of its
// surroundings, at a fraction of a G-buffer's cost: no alpha (a glTF MASK
// or BLEND surface is seen opaque).
// The material extensions' lobes (light passes over surface maps, each
// compiled only when the layer's world has such a material, and branched
// per material inside): CLEARCOAT the coat's lobe on its own normal and the
// dimming under it (factor and roughness by its maps, the clearcoat normal
// map), SHEEN the Charlie lobe and the base's dimming, ANISOTROPY the
// stretched specular lobe (direction by the tangent, rotation and map), each
// by lib/forward_light.wgsl's functions as lit transparency calls them;
// IRIDESCENCE the film's Fresnel at N.V (lib/iridescence.wgsl) in place of
// Schlick's, mixed by its factor, as CookTorrance mixes it (its diffuse
// takes each light's N.L (1 - w) for N.L: within w = (1 - V.H)^5). The
// probe's own sun and ambient light the diffuse alone, as before.
// Vertices are pulled from the mesh arena by index (spreadlight::mesh_fetch),
// as the shadow depth pass pulls them. Clamped below half-float overflow;
// NaN is 0.
#import spreadlight::mesh_fetch::{instances, triangle_vertex, view_right, view_up}
#import spreadlight::packing::{safe_normalize}
#ifdef MATERIAL_MAPS
#import spreadlight::material::{feature_param, FEATURE_COOK_TORRANCE, FEATURE_EMISSION}
#import spreadlight::material_maps::{MapCoords, sample_map, has_map, map_settings, MAP_BASE_COLOR, MAP_METALLIC_ROUGHNESS, MAP_NORMAL, MAP_OCCLUSION, MAP_EMISSIVE}
#endif
#ifdef LIGHT_PASS
#import spreadlight::brdf::{brdf_surface, no_light_sums, light_sums_brdf, surface_energy_compensation}
#import spreadlight::forward_light::{lights, add_forward_light}
#ifdef CLEARCOAT
#import spreadlight::brdf::DIELECTRIC_F0
#import spreadlight::material::FEATURE_CLEARCOAT
#import spreadlight::material_maps::{mapped_clearcoat, clearcoat_normal_texel, MAP_CLEARCOAT_NORMAL}
#import spreadlight::forward_light::{coat_factor, coat_surface, coat_sum, coated_specular}
#endif
#ifdef SHEEN
#import spreadlight::material::FEATURE_SHEEN
#import spreadlight::forward_light::{sheen_color, sheen_roughness, sheen_sum, sheened_specular}
#endif
#ifdef ANISOTROPY
#import spreadlight::material::{has_feature, FEATURE_ANISOTROPY}
#import spreadlight::material_maps::mapped_anisotropy
#import spreadlight::anisotropy::anisotropic_surface
#import spreadlight::forward_light::aniso
#endif
#ifdef IRIDESCENCE
#import spreadlight::material::iridescence_at
#import spreadlight::iridescence::iridescence_fresnel
#endif
#else
#ifdef SHADOWS
#import spreadlight::shadow_sampling::sun_shadow_anywhere
#endif
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
    // LIGHT_PASS: x the most lights a face adds of the buffer (the
    // Max Lights pin); y, z the roughness and metallic of surfaces without
    // a material world (as bits); w unused.
    light_params: vec4<u32>,
}

@group(0) @binding(0) var<uniform> face: ProbeFace;
#ifdef COLOR_MAP
@group(2) @binding(0) var color_map: texture_2d<f32>;
@group(2) @binding(1) var color_sampler: sampler;
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
@group(2) @binding(2) var<uniform> probe_layer: ProbeLayer;
#endif
#ifdef NORMAL_MAP
@group(2) @binding(3) var normal_map: texture_2d<f32>;
@group(2) @binding(4) var normal_sampler: sampler;
#endif

const HALF_MAX: f32 = 65000.0;

struct Varyings {
    // Invariant: a light pass depth-tests equal against the base pass's depths,
    // so every pipeline must compute the same position from the same vertex.
    @builtin(position) @invariant clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) albedo: vec3<f32>,
    @location(3) uv: vec2<f32>,
    // World-space tangent (the model matrix's, as the resolve takes it), w its handedness.
    @location(4) tangent: vec4<f32>,
    // The instance's material (its world's id; MATERIAL_MAPS).
    @location(5) @interpolate(flat) material: u32,
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
    out.material = record.info.z;
    return out;
}

@fragment
fn fs(in: Varyings) -> @location(0) vec4<f32> {
#ifdef MATERIAL_MAPS
    // Derivatives first, in uniform control flow.
    var coords: MapCoords;
    coords.uv = in.uv;
    coords.dx = dpdx(in.uv);
    coords.dy = dpdy(in.uv);
    coords.second_uv = in.uv;
    coords.second_dx = coords.dx;
    coords.second_dy = coords.dy;
#endif
    let to_probe = face.position.xyz - in.world;
    var n = safe_normalize(in.normal, safe_normalize(to_probe, vec3<f32>(0.0, 1.0, 0.0)));
    if (dot(n, to_probe) < 0.0) {
        n = -n;
    }
    // The surface's own normal, for the shadow's normal offset (and what
    // a clearcoat normal map and the anisotropy direction are taken on).
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
    var roughness = bitcast<f32>(face.light_params.y);
    var metallic = bitcast<f32>(face.light_params.z);
    var reflectance = 0.04;
    var occlusion = 1.0;
    var emission = vec3<f32>(0.0);
#ifdef MATERIAL_MAPS
    let ct = feature_param(in.material, FEATURE_COOK_TORRANCE, 0u, vec4<f32>(roughness, metallic, reflectance, 0.0));
    roughness = ct.x;
    metallic = ct.y;
    reflectance = ct.z;
    let em = feature_param(in.material, FEATURE_EMISSION, 0u, vec4<f32>(0.0));
    emission = max(em.rgb, vec3<f32>(0.0)) * max(em.a, 0.0);
    albedo *= max(sample_map(in.material, MAP_BASE_COLOR, coords, vec4<f32>(1.0)).rgb, vec3<f32>(0.0));
    let settings = map_settings(in.material);
    if (has_map(in.material, MAP_NORMAL)) {
        var texel = sample_map(in.material, MAP_NORMAL, coords, vec4<f32>(0.5, 0.5, 1.0, 1.0)).xyz * 2.0 - 1.0;
        texel = vec3<f32>(texel.xy * settings.z, texel.z);
        // The mesh's tangent frame, as the resolve builds it.
        let mt = safe_normalize(in.tangent.xyz - n * dot(n, in.tangent.xyz), vec3<f32>(1.0, 0.0, 0.0));
        let mb = cross(n, mt) * select(-1.0, 1.0, in.tangent.w >= 0.0);
        n = safe_normalize(mt * texel.x + mb * texel.y + n * texel.z, n);
    }
    let metal_rough = sample_map(in.material, MAP_METALLIC_ROUGHNESS, coords, vec4<f32>(1.0));
    roughness *= metal_rough.g;
    metallic *= metal_rough.b;
    occlusion = clamp(1.0 + settings.w * (sample_map(in.material, MAP_OCCLUSION, coords, vec4<f32>(1.0)).r - 1.0), 0.0, 1.0);
    emission *= max(sample_map(in.material, MAP_EMISSIVE, coords, vec4<f32>(1.0)).rgb, vec3<f32>(0.0));
#endif
#ifdef LIGHT_PASS
    // The buffer's lights as CookTorrance shades them, seen from the probe.
    let v = safe_normalize(to_probe, n);
    let s = brdf_surface(n, v, albedo, roughness, metallic, reflectance);
#ifdef ANISOTROPY
    // The direction in the geometric normal's tangent frame, turned by the
    // rotation and the map (as lit transparency makes it); the lobe makes
    // it orthogonal to the shaded normal. None: the isotropic lobe.
    var aniso_direction = vec3<f32>(0.0);
    var aniso_strength = 0.0;
    if (has_feature(in.material, FEATURE_ANISOTROPY)) {
        let a = mapped_anisotropy(in.material, coords, feature_param(in.material, FEATURE_ANISOTROPY, 0u, vec4<f32>(0.0)).xy);
        let aniso_t = safe_normalize(in.tangent.xyz, vec3<f32>(1.0, 0.0, 0.0));
        let aniso_b = cross(geometric, aniso_t) * select(-1.0, 1.0, in.tangent.w >= 0.0);
        aniso_direction = aniso_t * a.x + aniso_b * a.y;
        aniso_strength = a.z;
    }
    aniso = anisotropic_surface(s, aniso_direction, aniso_strength);
#endif
#ifdef CLEARCOAT
    // The coat's (factor, roughness) by its maps, on its normal map's normal
    // (bent from the geometric one), else the surface's.
    let coat_params = feature_param(in.material, FEATURE_CLEARCOAT, 0u, vec4<f32>(0.0)).xy;
    let coat = mapped_clearcoat(in.material, coords, clamp(select(vec2<f32>(0.0), coat_params, coat_params == coat_params), vec2<f32>(0.0), vec2<f32>(1.0)));
    var coat_n = n;
    if (has_map(in.material, MAP_CLEARCOAT_NORMAL)) {
        let texel = clearcoat_normal_texel(in.material, coords);
        let ct_t = safe_normalize(in.tangent.xyz - geometric * dot(geometric, in.tangent.xyz), vec3<f32>(1.0, 0.0, 0.0));
        let ct_b = cross(geometric, ct_t) * select(-1.0, 1.0, in.tangent.w >= 0.0);
        coat_n = safe_normalize(ct_t * texel.x + ct_b * texel.y + geometric * texel.z, geometric);
    }
    coat_factor = coat.x;
    coat_surface = brdf_surface(coat_n, v, vec3<f32>(0.0), coat.y, 0.0, DIELECTRIC_F0);
    coat_sum = vec3<f32>(0.0);
#endif
#ifdef SHEEN
    let sheen_params = feature_param(in.material, FEATURE_SHEEN, 0u, vec4<f32>(0.0));
    let sheen = clamp(select(vec4<f32>(0.0), sheen_params, sheen_params == sheen_params), vec4<f32>(0.0), vec4<f32>(1.0));
    sheen_color = sheen.rgb;
    sheen_roughness = sheen.a;
    sheen_sum = vec3<f32>(0.0);
#endif
    var sums = no_light_sums();
    let count = min(arrayLength(&lights), face.light_params.x);
    for (var i = 0u; i < count; i++) {
        add_forward_light(i, in.world, s, 0.0, &sums);
    }
    let lit = light_sums_brdf(s, sums);
    var specular = lit.specular;
    var diffuse = lit.diffuse;
#ifdef IRIDESCENCE
    // The film's F at N.V for Schlick's, mixed by its factor (CookTorrance's
    // IRIDESCENCE); the diffuse's 1 - F the film's too.
    let film = iridescence_at(in.material, vec2<u32>(0u));
    if (film.x > 0.0) {
        let film_fresnel = iridescence_fresnel(reflectance, albedo, metallic, s.n_dot_v, film.y, film.z);
        specular = mix(specular, film_fresnel * sums.specular, film.x);
        diffuse = mix(diffuse, (vec3<f32>(1.0) - film_fresnel) * s.diffuse * sums.diffuse, film.x);
    }
#endif
    specular *= surface_energy_compensation(s);
#ifdef SHEEN
    let sheened = sheened_specular(s, specular);
    specular = sheened.xyz;
    diffuse *= sheened.w;
#endif
#ifdef CLEARCOAT
    let over = coated_specular(specular);
    specular = over.xyz;
    diffuse *= over.w;
#endif
    let c = min(max(diffuse + specular, vec3<f32>(0.0)), vec3<f32>(HALF_MAX));
#else
    let towards_sun = face.towards_sun.xyz;
    var sun = max(dot(n, towards_sun), 0.0);
#ifdef SHADOWS
    if (sun > 0.0) {
        sun *= sun_shadow_anywhere(face.shadow.x, in.world, geometric, dot(geometric, towards_sun));
    }
#endif
    let light = face.ambient.rgb * occlusion + face.sun_color.rgb * sun;
    let c = min(max(albedo * light + emission, vec3<f32>(0.0)), vec3<f32>(HALF_MAX));
#endif
    return vec4<f32>(select(vec3<f32>(0.0), c, c == c), 1.0);
}
