// DeferredBase, compute half (the MRE resolve): turns the visibility buffer
// into Emeshe's MRE layout. For each pixel of this layer it fetches the
// triangle, computes perspective-correct barycentrics from the pixel centre,
// and interpolates the attributes. Dispatched once per layer with that
// layer's feature switches, so a layer pays only for what it asked for.
//
// Without MOTION: color (RGB) + material id (A), view-space normal (RGB) + object id (A),
//                 and depth (reversed-Z) as R32Float.
// With MOTION:    velocity in UV units per frame (RG) + texture coordinates (BA).
// COMPUTE_RASTER: read the compute rasterizer's 64-bit buffer instead of the
//                 raster hardware's visibility and depth textures.
// SURFACE_OUT:    the G-buffer has a surface target (some layer has surface
//                 maps or a shader node material); other layers, and
//                 materials without maps, mark it unwritten (lighting then
//                 reads their material's parameters).
// MATERIAL_MAPS:  this layer's material world has glTF surface maps: albedo,
//                 normal (mapped, flipped on back faces of double-sided
//                 materials), roughness, metallic, occlusion and emission per
//                 pixel (see shaders/lib/material_maps.wgsl).
// EXTENSION_MAPS: (with MATERIAL_MAPS) some material of the world has a
//                 material extension's map: for those materials, the coat's
//                 factor and roughness (clearcoat maps) and the reflectance
//                 (specular maps) too, in the surface target's w, and the
//                 coat's own normal (clearcoat normal map) in the bits
//                 pack_coat_normal frees for it.
// CUSTOM_SURFACE: this layer has a shader node material: its
//                 `surface` function (spreadlight::custom_surface, swapped
//                 for the material's file) shades each pixel; its bindings
//                 are group 1 (see shaders/lib/surface.wgsl).
// VELOCITY_OUT:   (without MOTION) also what MOTION writes, into binding 13:
//                 the surface and motion resolves in one dispatch when the
//                 frame reads both (crates/render/src/gbuffer/resolve.rs).
// ANISOTROPY:     (with MATERIAL_MAPS) some material of the world has the
//                 Anisotropy feature (KHR_materials_anisotropy): for those
//                 materials, the anisotropy direction (the tangent frame
//                 turned by the rotation and the anisotropy map, view
//                 space) and strength into the anisotropy target.
// SHEEN_FILM:     (with EXTENSION_MAPS) some material of the world has a
//                 sheen or iridescence map: for every glTF material, the
//                 sheen colour and roughness and the film's factor and
//                 thickness its factors and maps make into the sheen and
//                 film target (shaders/lib/sheen_film.wgsl; lighting reads
//                 the factors of materials it marks unwritten).
// VERTEX_EXTRAS:  some mesh of this layer has vertex colours (COLOR_0, they
//                 multiply albedo) or a second UV set (TEXCOORD_1, for maps
//                 whose texCoord is 1): read the arena's extra stream.
#import spreadlight::camera::{Camera, pixel_to_ndc}
#import spreadlight::mesh::{Vertex, Instance}
#import spreadlight::mesh_fetch::{instances, triangle_vertex, view_right, view_up}
#ifdef VERTEX_EXTRAS
#import spreadlight::mesh::vertex_color
#import spreadlight::vertex_extras::corner_extra
#endif
#import spreadlight::packing::{id_to_channel, safe_normalize}
#ifdef MATERIAL_MAPS
#import spreadlight::material::{feature_param, has_feature, FEATURE_COOK_TORRANCE, FEATURE_EMISSION, FEATURE_SURFACE_MAPS}
#import spreadlight::surface_target::pack_surface
#import spreadlight::material_maps::{MapCoords, sample_map, has_map, map_settings, MAP_BASE_COLOR, MAP_METALLIC_ROUGHNESS, MAP_NORMAL, MAP_OCCLUSION, MAP_EMISSIVE}
#ifdef EXTENSION_MAPS
#import spreadlight::material::FEATURE_CLEARCOAT
#import spreadlight::material_maps::{has_extension_maps, mapped_reflectance, mapped_clearcoat, clearcoat_normal_texel, MAP_CLEARCOAT_NORMAL}
#import spreadlight::surface_target::{pack_extension, pack_coat_normal}
#endif
#ifdef ANISOTROPY
#import spreadlight::material::FEATURE_ANISOTROPY
#import spreadlight::material_maps::mapped_anisotropy
#endif
#ifdef SHEEN_FILM
#import spreadlight::material::{FEATURE_SHEEN, FEATURE_IRIDESCENCE}
#import spreadlight::material_maps::{mapped_sheen, mapped_film}
#import spreadlight::sheen_film::pack_sheen_film
#endif
#endif
#ifdef CUSTOM_SURFACE
#import spreadlight::surface::{SurfaceInput, surface_finite}
#import spreadlight::custom_surface::surface
#import spreadlight::surface_target::pack_surface
#endif

struct Layer {
    first_instance: u32,
    end_instance: u32,
    // 1 for the first layer: it also clears the pixels no layer covers.
    write_background: u32,
    // 1: add the triangle's geometry id (its first vertex's previous_position.w) to the object id.
    geometry_ids: u32,
    // TRIPLANAR: the exponent of the normal's components that weights the
    // three projections (4, or what a Triplanar (Layer) node set).
    triplanar_sharpness: f32,
    pad0: u32,
    pad1: u32,
    pad2: u32,
}

@group(0) @binding(0) var<uniform> camera: Camera;
#ifdef COMPUTE_RASTER
// The compute rasterizer's 64-bit words, read as (id + 1, depth bits).
@group(0) @binding(4) var<storage, read> visibility: array<vec2<u32>>;
// Per instance, its first global triangle id (ascending), to find a pixel's instance.
@group(0) @binding(10) var<storage, read> first_triangle: array<u32>;
#else
@group(0) @binding(4) var visibility: texture_2d<u32>;
#endif
@group(0) @binding(5) var<uniform> layer: Layer;
#ifdef MOTION
@group(0) @binding(6) var out_velocity_uv: texture_storage_2d<rgba16float, write>;
#else
@group(0) @binding(6) var out_color: texture_storage_2d<rgba16float, write>;
@group(0) @binding(7) var out_normal: texture_storage_2d<rgba16float, write>;
@group(0) @binding(8) var out_depth: texture_storage_2d<r32float, write>;
#ifndef COMPUTE_RASTER
@group(0) @binding(9) var hardware_depth: texture_depth_2d;
#endif
#ifdef SURFACE_OUT
@group(0) @binding(11) var out_surface: texture_storage_2d<rgba32uint, write>;
#endif
#ifdef VELOCITY_OUT
@group(0) @binding(13) var out_velocity_uv: texture_storage_2d<rgba16float, write>;
#endif
#ifdef ANISOTROPY
// View-space anisotropy direction (rgb) and strength (a).
@group(0) @binding(16) var out_anisotropy: texture_storage_2d<rgba16float, write>;
#endif
#ifdef SHEEN_FILM
// Sheen colour and roughness, film factor and thickness (lib/sheen_film.wgsl).
@group(0) @binding(17) var out_sheen_film: texture_storage_2d<rgba32uint, write>;
#endif
#endif
// Group 1 is the material world (MATERIAL_MAPS), group 3 its map arrays.
#ifdef NORMAL_MAP
@group(2) @binding(0) var normal_map: texture_2d<f32>;
@group(2) @binding(1) var normal_sampler: sampler;
#endif
// COLOR_MAP: a texture (sRGB decoded by the sampler) that scales the instance colour.
#ifdef COLOR_MAP
@group(2) @binding(2) var color_map: texture_2d<f32>;
@group(2) @binding(3) var color_sampler: sampler;
#endif

// Barycentrics of where the pixel's view ray meets the triangle (world
// space). Exact for any triangle, including ones that cross the near plane;
// a ray parallel to the triangle gives (1, 0, 0), never NaN.
fn barycentrics(ndc: vec2<f32>, p0: vec3<f32>, p1: vec3<f32>, p2: vec3<f32>) -> vec3<f32> {
    let world_from_clip = camera.view_inverse * camera.projection_inverse;
    let near = world_from_clip * vec4<f32>(ndc, 1.0, 1.0);
    let mid = world_from_clip * vec4<f32>(ndc, 0.5, 1.0);
    let origin = near.xyz / near.w;
    let direction = mid.xyz / mid.w - origin;
    let e1 = p1 - p0;
    let e2 = p2 - p0;
    let pv = cross(direction, e2);
    let det = dot(e1, pv);
    if (abs(det) < 1e-20) {
        return vec3<f32>(1.0, 0.0, 0.0);
    }
    let tv = origin - p0;
    let u = dot(tv, pv) / det;
    let v = dot(direction, cross(tv, e1)) / det;
    return vec3<f32>(1.0 - u - v, u, v);
}

// The pixel's (instance, triangle, depth), or instance u32::MAX for none.
fn visible(pixel: vec2<u32>) -> vec3<u32> {
#ifdef COMPUTE_RASTER
    let word = visibility[pixel.y * u32(camera.size.x) + pixel.x];
    if (word.x == 0u) {
        return vec3<u32>(0xffffffffu, 0u, 0u);
    }
    let id = word.x - 1u;
    // Largest instance whose first triangle is <= id.
    var lo = 0u;
    var hi = arrayLength(&first_triangle);
    while (hi - lo > 1u) {
        let mid = (lo + hi) / 2u;
        if (first_triangle[mid] <= id) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    return vec3<u32>(lo, id - first_triangle[lo], word.y);
#else
    let ids = textureLoad(visibility, pixel, 0).xy;
    if (ids.x == 0u) {
        return vec3<u32>(0xffffffffu, 0u, 0u);
    }
#ifdef MOTION
    let depth = 0.0;
#else
    let depth = textureLoad(hardware_depth, pixel, 0);
#endif
    return vec3<u32>(ids.x - 1u, ids.y, bitcast<u32>(depth));
#endif
}

#ifdef TRIPLANAR
// How much each of the three planar projections (along x: the zy plane,
// along y: xz, along z: xy) counts where the surface's unit normal is `n`:
// |n|^sharpness, summing to 1. Continuous in n, so no seam where the axis
// the surface faces most changes; the larger the sharpness, the narrower
// the blend between projections.
fn triplanar_weights(n: vec3<f32>, sharpness: f32) -> vec3<f32> {
    let w = pow(abs(n) + vec3<f32>(1e-5), vec3<f32>(max(sharpness, 1.0)));
    return w / (w.x + w.y + w.z);
}
#endif

fn interpolate3(b: vec3<f32>, a0: vec3<f32>, a1: vec3<f32>, a2: vec3<f32>) -> vec3<f32> {
    return a0 * b.x + a1 * b.y + a2 * b.z;
}

// The world-space direction of the pixel's view ray (any length).
fn view_ray(ndc: vec2<f32>) -> vec3<f32> {
    let world_from_clip = camera.view_inverse * camera.projection_inverse;
    let near = world_from_clip * vec4<f32>(ndc, 1.0, 1.0);
    let mid = world_from_clip * vec4<f32>(ndc, 0.5, 1.0);
    return mid.xyz / mid.w - near.xyz / near.w;
}

// The pixel's motion since last frame in UV units: its point on the
// triangle now and (VELOCITY_FROM_GEOMETRY: where the geometry was; else
// the same point) under last frame's camera and transform.
fn velocity(instance: Instance, b: vec3<f32>, v0: Vertex, v1: Vertex, v2: Vertex) -> vec2<f32> {
    let object_now = interpolate3(b, v0.position_u.xyz, v1.position_u.xyz, v2.position_u.xyz);
#ifdef VELOCITY_FROM_GEOMETRY
    let object_before = interpolate3(b, v0.previous_position.xyz, v1.previous_position.xyz, v2.previous_position.xyz);
#else
    let object_before = object_now;
#endif
    let now = camera.view_projection * instance.model * vec4<f32>(object_now, 1.0);
    let before = camera.previous_view_projection * instance.previous_model * vec4<f32>(object_before, 1.0);
    if (now.w > 1e-6 && before.w > 1e-6) {
        return (now.xy / now.w - before.xy / before.w) * vec2<f32>(0.5, -0.5);
    }
    return vec2<f32>(0.0);
}

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = vec2<u32>(camera.size.xy);
    if (id.x >= size.x || id.y >= size.y) {
        return;
    }
    let pixel = id.xy;
    let hit = visible(pixel);
    let covered = hit.x != 0xffffffffu;
    if (!covered || hit.x < layer.first_instance || hit.x >= layer.end_instance) {
        if (!covered && layer.write_background == 1u) {
#ifdef MOTION
            textureStore(out_velocity_uv, pixel, vec4<f32>(0.0));
#else
            textureStore(out_color, pixel, vec4<f32>(0.0));
            textureStore(out_normal, pixel, vec4<f32>(0.0));
            textureStore(out_depth, pixel, vec4<f32>(0.0));
#ifdef SURFACE_OUT
            textureStore(out_surface, pixel, vec4<u32>(0u));
#endif
#ifdef ANISOTROPY
            textureStore(out_anisotropy, pixel, vec4<f32>(0.0));
#endif
#ifdef SHEEN_FILM
            textureStore(out_sheen_film, pixel, vec4<u32>(0u));
#endif
#ifdef VELOCITY_OUT
            textureStore(out_velocity_uv, pixel, vec4<f32>(0.0));
#endif
#endif
        }
        return;
    }
    let instance = instances[hit.x];
    let right = view_right(camera.view);
    let up = view_up(camera.view);
    let v0 = triangle_vertex(hit.x, hit.y, 0u, right, up);
    let v1 = triangle_vertex(hit.x, hit.y, 1u, right, up);
    let v2 = triangle_vertex(hit.x, hit.y, 2u, right, up);
#ifdef VERTEX_EXTRAS
    let e0 = corner_extra(hit.x, hit.y, 0u, v0);
    let e1 = corner_extra(hit.x, hit.y, 1u, v1);
    let e2 = corner_extra(hit.x, hit.y, 2u, v2);
#endif
    let w0 = (instance.model * vec4<f32>(v0.position_u.xyz, 1.0)).xyz;
    let w1 = (instance.model * vec4<f32>(v1.position_u.xyz, 1.0)).xyz;
    let w2 = (instance.model * vec4<f32>(v2.position_u.xyz, 1.0)).xyz;
    let b = barycentrics(pixel_to_ndc(pixel, camera.size), w0, w1, w2);

#ifdef TEXCOORDS
    let uv = vec2<f32>(
        dot(b, vec3<f32>(v0.position_u.w, v1.position_u.w, v2.position_u.w)),
        dot(b, vec3<f32>(v0.normal_v.w, v1.normal_v.w, v2.normal_v.w)),
    );
#else
#ifdef TRIPLANAR
    // Planar projection on the axis the surface faces most: the texture
    // coordinates the G-buffer stores (and a material reads) for geometry
    // that has none. The layer's own Color and Normal Textures blend all
    // three projections instead (triplanar_weights), without seams.
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
    textureStore(out_velocity_uv, pixel, vec4<f32>(velocity(instance, b, v0, v1, v2), uv));
#else
#ifdef VELOCITY_OUT
    textureStore(out_velocity_uv, pixel, vec4<f32>(velocity(instance, b, v0, v1, v2), uv));
#endif
    let normal_object = interpolate3(b, v0.normal_v.xyz, v1.normal_v.xyz, v2.normal_v.xyz);
    var normal_world = safe_normalize((instance.normal_matrix * vec4<f32>(normal_object, 0.0)).xyz, vec3<f32>(0.0, 1.0, 0.0));
#ifdef MATERIAL_MAPS
    let material = instance.info.z;
    let settings = map_settings(material);
    // Back faces of double-sided materials: the geometric normal (its
    // winding flipped by a mirroring transform) faces along the view ray.
    if ((u32(settings.x) & 4u) != 0u) {
        let m = mat3x3<f32>(instance.model[0].xyz, instance.model[1].xyz, instance.model[2].xyz);
        let geometric = cross(w1 - w0, w2 - w0) * select(1.0, -1.0, determinant(m) < 0.0);
        if (dot(geometric, view_ray(pixel_to_ndc(pixel, camera.size))) > 0.0) {
            normal_world = -normal_world;
        }
    }
    // Texture coordinates and their screen derivatives, from the
    // barycentrics of the neighbouring pixels' rays on this triangle's plane.
    let ndc = pixel_to_ndc(pixel, camera.size);
    let us = vec3<f32>(v0.position_u.w, v1.position_u.w, v2.position_u.w);
    let vs = vec3<f32>(v0.normal_v.w, v1.normal_v.w, v2.normal_v.w);
    let b_dx = barycentrics(ndc + vec2<f32>(2.0 * camera.size.z, 0.0), w0, w1, w2);
    let b_dy = barycentrics(ndc - vec2<f32>(0.0, 2.0 * camera.size.w), w0, w1, w2);
    var coords: MapCoords;
    coords.uv = vec2<f32>(dot(b, us), dot(b, vs));
    coords.dx = vec2<f32>(dot(b_dx, us), dot(b_dx, vs)) - coords.uv;
    coords.dy = vec2<f32>(dot(b_dy, us), dot(b_dy, vs)) - coords.uv;
#ifdef VERTEX_EXTRAS
    let us1 = vec3<f32>(e0.second_uv.x, e1.second_uv.x, e2.second_uv.x);
    let vs1 = vec3<f32>(e0.second_uv.y, e1.second_uv.y, e2.second_uv.y);
    coords.second_uv = vec2<f32>(dot(b, us1), dot(b, vs1));
    coords.second_dx = vec2<f32>(dot(b_dx, us1), dot(b_dx, vs1)) - coords.second_uv;
    coords.second_dy = vec2<f32>(dot(b_dy, us1), dot(b_dy, vs1)) - coords.second_uv;
#else
    coords.second_uv = coords.uv;
    coords.second_dx = coords.dx;
    coords.second_dy = coords.dy;
#endif
    // What the coat's normal map bends (glTF: the geometric normal, not the base map's).
    let geometric_world = normal_world;
    if (has_map(material, MAP_NORMAL)) {
        let t4 = v0.tangent * b.x + v1.tangent * b.y + v2.tangent * b.z;
        let t = safe_normalize((instance.model * vec4<f32>(t4.xyz, 0.0)).xyz, vec3<f32>(1.0, 0.0, 0.0));
        let bt = cross(normal_world, t) * select(-1.0, 1.0, t4.w >= 0.0);
        var texel = sample_map(material, MAP_NORMAL, coords, vec4<f32>(0.5, 0.5, 1.0, 1.0)).xyz * 2.0 - 1.0;
        texel = vec3<f32>(texel.xy * settings.z, texel.z);
        normal_world = safe_normalize(t * texel.x + bt * texel.y + normal_world * texel.z, normal_world);
    }
    let metal_rough = sample_map(material, MAP_METALLIC_ROUGHNESS, coords, vec4<f32>(1.0));
    let ct = feature_param(material, FEATURE_COOK_TORRANCE, 0u, vec4<f32>(0.5, 0.0, 0.04, 0.0));
    let roughness = clamp(ct.x * metal_rough.g, 0.0, 1.0);
    let metallic = clamp(ct.y * metal_rough.b, 0.0, 1.0);
    let occlusion = clamp(1.0 + settings.w * (sample_map(material, MAP_OCCLUSION, coords, vec4<f32>(1.0)).r - 1.0), 0.0, 1.0);
    let em = feature_param(material, FEATURE_EMISSION, 0u, vec4<f32>(0.0));
    let emission = clamp(
        max(em.rgb, vec3<f32>(0.0)) * max(em.a, 0.0) * sample_map(material, MAP_EMISSIVE, coords, vec4<f32>(1.0)).rgb,
        vec3<f32>(0.0), vec3<f32>(65000.0),
    );
    // Written (and so read by lighting in place of the material's
    // parameters) only for materials with maps: the others of the world
    // shade from their parameters, unquantized.
    var surface_texel = vec4<u32>(0u);
    if (has_feature(material, FEATURE_SURFACE_MAPS)) {
        surface_texel = pack_surface(roughness, metallic, occlusion, emission);
#ifdef EXTENSION_MAPS
        if (has_extension_maps(material)) {
            let coat = mapped_clearcoat(material, coords, feature_param(material, FEATURE_CLEARCOAT, 0u, vec4<f32>(0.0)).xy);
            let reflectance = mapped_reflectance(material, coords, ct.z);
            if (has_map(material, MAP_CLEARCOAT_NORMAL)) {
                let t4 = v0.tangent * b.x + v1.tangent * b.y + v2.tangent * b.z;
                let t = safe_normalize((instance.model * vec4<f32>(t4.xyz, 0.0)).xyz, vec3<f32>(1.0, 0.0, 0.0));
                let bt = cross(geometric_world, t) * select(-1.0, 1.0, t4.w >= 0.0);
                let texel = clearcoat_normal_texel(material, coords);
                // A texel of length zero (or one that cancels the frame) keeps the geometric normal.
                let coat_world = safe_normalize(t * texel.x + bt * texel.y + geometric_world * texel.z, geometric_world);
                let coat_view = safe_normalize((camera.view * vec4<f32>(coat_world, 0.0)).xyz, vec3<f32>(0.0, 0.0, 1.0));
                surface_texel = pack_coat_normal(surface_texel, coat.x, coat.y, reflectance, coat_view);
            } else {
                surface_texel.w = pack_extension(coat.x, coat.y, reflectance);
            }
        }
#endif
    }
    textureStore(out_surface, pixel, surface_texel);
#ifdef ANISOTROPY
    if (has_feature(material, FEATURE_ANISOTROPY)) {
        // The direction in the geometric normal's tangent frame (as the
        // Khronos sample viewer: not bent by the normal map; lighting makes
        // it orthogonal to the shaded normal), turned by the rotation and
        // the map. A zero tangent or a map texel of no direction stores no
        // direction: that pixel is lit isotropic.
        let t4 = v0.tangent * b.x + v1.tangent * b.y + v2.tangent * b.z;
        let t = safe_normalize((instance.model * vec4<f32>(t4.xyz, 0.0)).xyz, vec3<f32>(1.0, 0.0, 0.0));
        let bt = cross(geometric_world, t) * select(-1.0, 1.0, t4.w >= 0.0);
        let aniso = mapped_anisotropy(material, coords, feature_param(material, FEATURE_ANISOTROPY, 0u, vec4<f32>(0.0)).xy);
        let along = (camera.view * vec4<f32>(t * aniso.x + bt * aniso.y, 0.0)).xyz;
        let length2 = dot(along, along);
        var texel = vec4<f32>(0.0);
        if (length2 > 1e-12) {
            texel = vec4<f32>(along * inverseSqrt(length2), aniso.z);
        }
        textureStore(out_anisotropy, pixel, texel);
    }
#endif
#ifdef SHEEN_FILM
    // Every pixel of this layer: a glTF material's sheen and film (its
    // factors where it has no map), others marked unwritten.
    var sheen_film = vec4<u32>(0u);
    if (has_feature(material, FEATURE_SURFACE_MAPS)) {
        let sheen = mapped_sheen(material, coords, feature_param(material, FEATURE_SHEEN, 0u, vec4<f32>(0.0)));
        let film = mapped_film(material, coords, feature_param(material, FEATURE_IRIDESCENCE, 0u, vec4<f32>(0.0)).x);
        sheen_film = pack_sheen_film(sheen, film);
    }
    textureStore(out_sheen_film, pixel, sheen_film);
#endif
#else
#ifdef SURFACE_OUT
#ifndef CUSTOM_SURFACE
    textureStore(out_surface, pixel, vec4<u32>(0u));
#endif
#endif
#endif
#ifdef TRIPLANAR
    // The blend's weights, from the surface's normal before any normal map.
    let tri = triplanar_weights(normal_world, layer.triplanar_sharpness);
#endif
#ifdef NORMAL_MAP
#ifdef TRIPLANAR
    // Three tangent-space samples, each reoriented onto the surface by the
    // whiteout blend of its projection's axis (Ben Golus, "Normal Mapping for
    // a Triplanar Shader"), then weighted like the colour.
    let tri_n = normal_world;
    let tx = textureSampleLevel(normal_map, normal_sampler, fract(world.zy), 0.0).xyz * 2.0 - 1.0;
    let ty = textureSampleLevel(normal_map, normal_sampler, fract(world.xz), 0.0).xyz * 2.0 - 1.0;
    let tz = textureSampleLevel(normal_map, normal_sampler, fract(world.xy), 0.0).xyz * 2.0 - 1.0;
    let bx = vec3<f32>(tx.xy + tri_n.zy, abs(tx.z) * tri_n.x);
    let by = vec3<f32>(ty.xy + tri_n.xz, abs(ty.z) * tri_n.y);
    let bz = vec3<f32>(tz.xy + tri_n.xy, abs(tz.z) * tri_n.z);
    normal_world = safe_normalize(bx.zyx * tri.x + by.xzy * tri.y + bz * tri.z, normal_world);
#else
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
#endif
    var albedo = instance.color.rgb;
#ifdef COLOR_MAP
#ifdef TRIPLANAR
    let color_x = textureSampleLevel(color_map, color_sampler, fract(world.zy), 0.0).rgb;
    let color_y = textureSampleLevel(color_map, color_sampler, fract(world.xz), 0.0).rgb;
    let color_z = textureSampleLevel(color_map, color_sampler, fract(world.xy), 0.0).rgb;
    albedo *= max(color_x * tri.x + color_y * tri.y + color_z * tri.z, vec3<f32>(0.0));
#else
    albedo *= max(textureSampleLevel(color_map, color_sampler, uv, 0.0).rgb, vec3<f32>(0.0));
#endif
#endif
#ifdef MATERIAL_MAPS
    albedo *= max(sample_map(material, MAP_BASE_COLOR, coords, vec4<f32>(1.0)).rgb, vec3<f32>(0.0));
#endif
#ifdef VERTEX_EXTRAS
    // glTF: base colour = factor x texture x COLOR_0.
    albedo *= vertex_color(e0).rgb * b.x + vertex_color(e1).rgb * b.y + vertex_color(e2).rgb * b.z;
#endif
#ifdef CUSTOM_SURFACE
    var surface_in: SurfaceInput;
    let object_position = interpolate3(b, v0.position_u.xyz, v1.position_u.xyz, v2.position_u.xyz);
    surface_in.position = (instance.model * vec4<f32>(object_position, 1.0)).xyz;
    surface_in.object_position = object_position;
    surface_in.normal = normal_world;
    surface_in.uv = uv;
    surface_in.color = vec4<f32>(albedo, instance.color.a);
    surface_in.view = safe_normalize(-view_ray(pixel_to_ndc(pixel, camera.size)), vec3<f32>(0.0, 0.0, 1.0));
    surface_in.pixel = pixel;
    surface_in.material_id = instance.info.z;
    surface_in.object_id = instance.info.w;
    // Whatever the material returns, no NaN or infinity reaches a target.
    let shaded = surface_finite(surface(surface_in), normal_world);
    albedo = shaded.albedo;
    normal_world = shaded.normal;
    // Lighting reads these in place of the material world's (or its pins')
    // roughness, metallic, occlusion and emission (shaders/lib/surface_target.wgsl).
    textureStore(out_surface, pixel, pack_surface(shaded.roughness, shaded.metallic, shaded.occlusion, shaded.emission));
#endif
    let normal_view = safe_normalize((camera.view * vec4<f32>(normal_world, 0.0)).xyz, vec3<f32>(0.0, 0.0, 1.0));
    textureStore(out_color, pixel, vec4<f32>(albedo, id_to_channel(instance.info.z)));
    let geometry_id = select(0u, u32(max(v0.previous_position.w, 0.0)), layer.geometry_ids == 1u);
    textureStore(out_normal, pixel, vec4<f32>(normal_view, id_to_channel(instance.info.w + geometry_id)));
    textureStore(out_depth, pixel, vec4<f32>(bitcast<f32>(hit.z), 0.0, 0.0, 0.0));
#endif
}
