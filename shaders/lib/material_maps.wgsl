// Surface maps of glTF materials (crates/render/src/material/maps.rs packs
// them as the SurfaceMaps feature, map_textures.rs uploads the arrays):
// one 2D texture array per size class and colour space (array = class * 2
// + sRGB), all bound at once so any material's maps are read in one
// dispatch. Sampled with explicit screen derivatives (trilinear +
// anisotropic in compute, where there are no implicit ones).
//
// Slots 5..15 are the material extensions' maps (clearcoat factor in red,
// clearcoat roughness in green, specular in alpha, specular colour in rgb,
// thickness in green, the clearcoat's tangent-space normal in rgb, the
// anisotropy direction in rg and its strength in b, the sheen colour in rgb,
// the sheen roughness in alpha, the iridescence factor in red, the film's
// thickness in green); a
// material packs them, and the specular factors and the clearcoat normal's
// scale after them (MAP_SPECULAR_FACTORS, MAP_CLEARCOAT_NORMAL_SCALE), only
// when it has one, and a pass reads them only under EXTENSION_MAPS (the
// world has one): `has_map` reads "none" past a material's parameters.
#define_import_path spreadlight::material_maps
#import spreadlight::material::{feature_param, FEATURE_SURFACE_MAPS}

const MAP_BASE_COLOR: u32 = 0u;
const MAP_METALLIC_ROUGHNESS: u32 = 1u;
const MAP_NORMAL: u32 = 2u;
const MAP_OCCLUSION: u32 = 3u;
const MAP_EMISSIVE: u32 = 4u;
const MAP_CLEARCOAT: u32 = 5u;
const MAP_CLEARCOAT_ROUGHNESS: u32 = 6u;
const MAP_SPECULAR: u32 = 7u;
const MAP_SPECULAR_COLOR: u32 = 8u;
const MAP_THICKNESS: u32 = 9u;
const MAP_CLEARCOAT_NORMAL: u32 = 10u;
const MAP_ANISOTROPY: u32 = 11u;
const MAP_SHEEN_COLOR: u32 = 12u;
const MAP_SHEEN_ROUGHNESS: u32 = 13u;
const MAP_IRIDESCENCE: u32 = 14u;
const MAP_IRIDESCENCE_THICKNESS: u32 = 15u;
// The parameter after the last slot's: (ior's f0 x specular colour factor, specular factor).
const MAP_SPECULAR_FACTORS: u32 = 33u;
// The one after it: (the clearcoat normal map's scale, 0, 0, 0).
const MAP_CLEARCOAT_NORMAL_SCALE: u32 = 34u;

@group(3) @binding(0) var maps_0: texture_2d_array<f32>;
@group(3) @binding(1) var maps_1: texture_2d_array<f32>;
@group(3) @binding(2) var maps_2: texture_2d_array<f32>;
@group(3) @binding(3) var maps_3: texture_2d_array<f32>;
@group(3) @binding(4) var maps_4: texture_2d_array<f32>;
@group(3) @binding(5) var maps_5: texture_2d_array<f32>;
@group(3) @binding(6) var maps_6: texture_2d_array<f32>;
@group(3) @binding(7) var maps_7: texture_2d_array<f32>;
@group(3) @binding(8) var maps_8: texture_2d_array<f32>;
@group(3) @binding(9) var maps_9: texture_2d_array<f32>;
@group(3) @binding(10) var maps_10: texture_2d_array<f32>;
@group(3) @binding(11) var maps_11: texture_2d_array<f32>;
@group(3) @binding(12) var maps_linear: sampler;
@group(3) @binding(13) var maps_nearest: sampler;

// Texture coordinates at a pixel and their change one pixel right (dx)
// and one pixel down (dy): TEXCOORD_0 (uv) and TEXCOORD_1 (second_uv); a map
// reads the set its `texCoord` names.
struct MapCoords {
    uv: vec2<f32>,
    dx: vec2<f32>,
    dy: vec2<f32>,
    second_uv: vec2<f32>,
    second_dx: vec2<f32>,
    second_dy: vec2<f32>,
}

// (alpha mode 0 opaque / 1 mask / 2 blend, + 4 when double-sided;
// alpha cutoff; normal scale; occlusion strength).
fn map_settings(material: u32) -> vec4<f32> {
    return feature_param(material, FEATURE_SURFACE_MAPS, 0u, vec4<f32>(0.0, 0.5, 1.0, 1.0));
}

fn map_double_sided(material: u32) -> bool {
    return (u32(map_settings(material).x) & 4u) != 0u;
}

fn has_map(material: u32, slot: u32) -> bool {
    return feature_param(material, FEATURE_SURFACE_MAPS, 1u + 2u * slot, vec4<f32>(0.0)).x >= 0.5;
}

// glTF wrap modes: 0 repeat (the sampler's), 1 clamp to edge, 2 mirrored repeat.
fn map_wrap(t: f32, mode: u32) -> f32 {
    if (mode == 1u) {
        return clamp(t, 0.0, 1.0);
    }
    if (mode == 2u) {
        return 1.0 - abs(t - 2.0 * floor(t * 0.5) - 1.0);
    }
    return t;
}

fn sample_array(s: sampler, array: u32, uv: vec2<f32>, layer: u32, dx: vec2<f32>, dy: vec2<f32>) -> vec4<f32> {
    switch (array) {
        case 0u: { return textureSampleGrad(maps_0, s, uv, layer, dx, dy); }
        case 1u: { return textureSampleGrad(maps_1, s, uv, layer, dx, dy); }
        case 2u: { return textureSampleGrad(maps_2, s, uv, layer, dx, dy); }
        case 3u: { return textureSampleGrad(maps_3, s, uv, layer, dx, dy); }
        case 4u: { return textureSampleGrad(maps_4, s, uv, layer, dx, dy); }
        case 5u: { return textureSampleGrad(maps_5, s, uv, layer, dx, dy); }
        case 6u: { return textureSampleGrad(maps_6, s, uv, layer, dx, dy); }
        case 7u: { return textureSampleGrad(maps_7, s, uv, layer, dx, dy); }
        case 8u: { return textureSampleGrad(maps_8, s, uv, layer, dx, dy); }
        case 9u: { return textureSampleGrad(maps_9, s, uv, layer, dx, dy); }
        case 10u: { return textureSampleGrad(maps_10, s, uv, layer, dx, dy); }
        default: { return textureSampleGrad(maps_11, s, uv, layer, dx, dy); }
    }
}

// Map `slot` of `material` at `coords`, or `fallback` when it has none.
// KHR_texture_transform: uv' = T * R * S * uv, derivatives by the linear part.
fn sample_map(material: u32, slot: u32, coords: MapCoords, fallback: vec4<f32>) -> vec4<f32> {
    let a = feature_param(material, FEATURE_SURFACE_MAPS, 1u + 2u * slot, vec4<f32>(0.0));
    if (a.x < 0.5) {
        return fallback;
    }
    let b = feature_param(material, FEATURE_SURFACE_MAPS, 2u + 2u * slot, vec4<f32>(0.0, 0.0, 1.0, 1.0));
    let place = u32(a.x) - 1u;
    let bits = u32(a.z);
    let c = cos(a.w);
    let s = sin(a.w);
    let row0 = vec2<f32>(c * b.z, s * b.w);
    let row1 = vec2<f32>(-s * b.z, c * b.w);
    let second = a.y >= 0.5;
    let chosen_uv = select(coords.uv, coords.second_uv, second);
    let chosen_dx = select(coords.dx, coords.second_dx, second);
    let chosen_dy = select(coords.dy, coords.second_dy, second);
    let uv = vec2<f32>(dot(row0, chosen_uv), dot(row1, chosen_uv)) + b.xy;
    let dx = vec2<f32>(dot(row0, chosen_dx), dot(row1, chosen_dx));
    let dy = vec2<f32>(dot(row0, chosen_dy), dot(row1, chosen_dy));
    let wrapped = vec2<f32>(map_wrap(uv.x, bits & 3u), map_wrap(uv.y, (bits >> 2u) & 3u));
    if ((bits & 16u) != 0u) {
        return sample_array(maps_nearest, place >> 16u, wrapped, place & 0xffffu, dx, dy);
    }
    return sample_array(maps_linear, place >> 16u, wrapped, place & 0xffffu, dx, dy);
}

// Whether the material has a map of a material extension (it packs the long layout).
fn has_extension_maps(material: u32) -> bool {
    return feature_param(material, FEATURE_SURFACE_MAPS, MAP_SPECULAR_FACTORS, vec4<f32>(-1.0)).w >= 0.0;
}

// The dielectric f0 (CookTorrance's reflectance) where a specular map is:
// min(f0 x colour factor x colour map, 1), made one number by its Rec. 709
// luminance, x factor x specular map (KHR_materials_specular; the CPU twin
// is spreadlight-gltf's MaterialData::reflectance). `reflectance` (the
// material's) where the material has neither specular map.
fn mapped_reflectance(material: u32, coords: MapCoords, reflectance: f32) -> f32 {
    if (!has_map(material, MAP_SPECULAR) && !has_map(material, MAP_SPECULAR_COLOR)) {
        return reflectance;
    }
    let s = feature_param(material, FEATURE_SURFACE_MAPS, MAP_SPECULAR_FACTORS, vec4<f32>(0.04, 0.04, 0.04, 1.0));
    let tint = max(sample_map(material, MAP_SPECULAR_COLOR, coords, vec4<f32>(1.0)).rgb, vec3<f32>(0.0));
    let f0 = min(max(s.rgb, vec3<f32>(0.0)) * tint, vec3<f32>(1.0));
    let grey = dot(f0, vec3<f32>(0.2126, 0.7152, 0.0722));
    let scale = clamp(s.a, 0.0, 1.0) * clamp(sample_map(material, MAP_SPECULAR, coords, vec4<f32>(1.0)).a, 0.0, 1.0);
    return clamp(grey * scale, 0.0, 1.0);
}

// The coat's (factor, roughness) scaled by its maps (clearcoatTexture's
// red, clearcoatRoughnessTexture's green), from the Clearcoat feature's `coat`.
fn mapped_clearcoat(material: u32, coords: MapCoords, coat: vec2<f32>) -> vec2<f32> {
    let factor = coat.x * sample_map(material, MAP_CLEARCOAT, coords, vec4<f32>(1.0)).r;
    let roughness = coat.y * sample_map(material, MAP_CLEARCOAT_ROUGHNESS, coords, vec4<f32>(1.0)).g;
    return clamp(vec2<f32>(factor, roughness), vec2<f32>(0.0), vec2<f32>(1.0));
}

// The anisotropy direction in the tangent frame (x along the tangent, y
// along the bitangent; unnormalised, (0, 0) for a map texel of no
// direction) and strength (0..1), from the Anisotropy feature's
// (strength, rotation) and anisotropyTexture (rg: the direction as 0..1,
// b: a factor of the strength; (1, 0) and 1 without one), the direction
// turned by the rotation (KHR_materials_anisotropy; the CPU twin is
// spreadlight-reference's anisotropy::anisotropy_direction).
fn mapped_anisotropy(material: u32, coords: MapCoords, params: vec2<f32>) -> vec3<f32> {
    var direction = vec2<f32>(1.0, 0.0);
    var strength = clamp(params.x, 0.0, 1.0);
    if (has_map(material, MAP_ANISOTROPY)) {
        let texel = sample_map(material, MAP_ANISOTROPY, coords, vec4<f32>(1.0, 0.5, 1.0, 1.0));
        direction = texel.xy * 2.0 - 1.0;
        strength *= clamp(texel.z, 0.0, 1.0);
    }
    let c = cos(params.y);
    let s = sin(params.y);
    return vec3<f32>(c * direction.x - s * direction.y, s * direction.x + c * direction.y, strength);
}

// The sheen's colour (rgb, 0..1) and roughness (a, 0..1) from the Sheen
// feature's (colour, roughness) `params`, times sheenColorTexture's rgb and
// sheenRoughnessTexture's alpha where the material has them
// (KHR_materials_sheen; the CPU twin is the test's factor x texel).
fn mapped_sheen(material: u32, coords: MapCoords, params: vec4<f32>) -> vec4<f32> {
    var sheen = params;
    if (has_map(material, MAP_SHEEN_COLOR)) {
        sheen = vec4<f32>(sheen.rgb * sample_map(material, MAP_SHEEN_COLOR, coords, vec4<f32>(1.0)).rgb, sheen.a);
    }
    if (has_map(material, MAP_SHEEN_ROUGHNESS)) {
        sheen.a *= sample_map(material, MAP_SHEEN_ROUGHNESS, coords, vec4<f32>(1.0)).a;
    }
    return clamp(sheen, vec4<f32>(0.0), vec4<f32>(1.0));
}

// The film's factor (0..1) and where its thickness lies from the minimum
// (0) to the maximum (1), from the Iridescence feature's factor,
// iridescenceTexture's red and iridescenceThicknessTexture's green
// (KHR_materials_iridescence: without a thickness map the film is its
// maximum thick).
fn mapped_film(material: u32, coords: MapCoords, factor: f32) -> vec2<f32> {
    var film = vec2<f32>(factor, 1.0);
    if (has_map(material, MAP_IRIDESCENCE)) {
        film.x *= sample_map(material, MAP_IRIDESCENCE, coords, vec4<f32>(1.0)).r;
    }
    if (has_map(material, MAP_IRIDESCENCE_THICKNESS)) {
        film.y = sample_map(material, MAP_IRIDESCENCE_THICKNESS, coords, vec4<f32>(1.0)).g;
    }
    return clamp(film, vec2<f32>(0.0), vec2<f32>(1.0));
}

// The coat's tangent-space normal (-1..1, x and y times the map's scale)
// from clearcoatNormalTexture, or straight up (0, 0, 1) without one: the
// caller turns it into its space by the tangent frame of the surface's
// geometric normal (glTF: not the base normal map's), as for the base
// normal map. Any texel is finite; a texel of length zero is the
// caller's to guard (safe_normalize with the geometric normal).
fn clearcoat_normal_texel(material: u32, coords: MapCoords) -> vec3<f32> {
    if (!has_map(material, MAP_CLEARCOAT_NORMAL)) {
        return vec3<f32>(0.0, 0.0, 1.0);
    }
    let scale = feature_param(material, FEATURE_SURFACE_MAPS, MAP_CLEARCOAT_NORMAL_SCALE, vec4<f32>(1.0)).x;
    let texel = sample_map(material, MAP_CLEARCOAT_NORMAL, coords, vec4<f32>(0.5, 0.5, 1.0, 1.0)).xyz * 2.0 - 1.0;
    return vec3<f32>(texel.xy * scale, texel.z);
}
