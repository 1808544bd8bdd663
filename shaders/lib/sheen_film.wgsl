// The G-buffer's sheen and film target (`sheen_film`, Rgba32Uint): per
// pixel of a glTF material, its sheen colour and roughness and its thin
// film's factor and thickness as KHR_materials_sheen's and
// KHR_materials_iridescence's maps make them (the G-buffer resolve writes
// it under SHEEN_FILM, only for a world with such a map; lighting reads it
// under SHEEN or IRIDESCENCE, a 1x1 "never written" texel bound in its
// place without one). Four unorm16 pairs, finer than the 8-bit maps:
//   x: sheen red, green    y: sheen blue, roughness
//   z: film factor, where its thickness lies from minimum (0) to maximum (1)
//   w: 1 where written (a maps material's pixel), else 0: lighting then
//      reads the material's factors.
// Its own target rather than spare bits of the surface target, which has none.
#define_import_path spreadlight::sheen_film
#import spreadlight::material::{feature_param, has_feature, iridescence_at, FEATURE_SHEEN, FEATURE_IRIDESCENCE, FEATURE_SURFACE_MAPS}

const SHEEN_FILM_WRITTEN: u32 = 1u;

// What the resolve stores for a maps material: `sheen` (rgb colour, a
// roughness; 0..1) and `film` (factor, thickness mix; 0..1).
fn pack_sheen_film(sheen: vec4<f32>, film: vec2<f32>) -> vec4<u32> {
    let s = clamp(sheen, vec4<f32>(0.0), vec4<f32>(1.0));
    let f = clamp(film, vec2<f32>(0.0), vec2<f32>(1.0));
    return vec4<u32>(pack2x16unorm(s.rg), pack2x16unorm(s.ba), pack2x16unorm(f), SHEEN_FILM_WRITTEN);
}

// Whether `texel` holds what the resolve made of material `id`'s maps.
fn sheen_film_written(id: u32, texel: vec4<u32>) -> bool {
    return texel.w == SHEEN_FILM_WRITTEN && has_feature(id, FEATURE_SURFACE_MAPS);
}

// The pixel's sheen, colour (rgb) and roughness (a), each 0..1: the maps'
// where the resolve wrote them, else the material's factors; black (no
// sheen) without the feature.
fn sheen_at(id: u32, texel: vec4<u32>) -> vec4<f32> {
    if (!has_feature(id, FEATURE_SHEEN)) {
        return vec4<f32>(0.0);
    }
    if (sheen_film_written(id, texel)) {
        return vec4<f32>(unpack2x16unorm(texel.x), unpack2x16unorm(texel.y));
    }
    return clamp(feature_param(id, FEATURE_SHEEN, 0u, vec4<f32>(0.0)), vec4<f32>(0.0), vec4<f32>(1.0));
}

// The pixel's film as `iridescence_at` gives it (factor, film index,
// thickness in nm), the factor and thickness from the maps where the
// resolve wrote them: the thickness mixed from the minimum to the maximum.
fn film_at(id: u32, pixel: vec2<u32>, texel: vec4<u32>) -> vec3<f32> {
    if (!sheen_film_written(id, texel)) {
        return iridescence_at(id, pixel);
    }
    return film_of(id, unpack2x16unorm(texel.z));
}

// Material `id`'s film as its maps make it: `mapped` the factor (0..1)
// and where the thickness lies from the minimum (0) to the maximum (1)
// (`mapped_film`); the index is the material's.
fn film_of(id: u32, mapped: vec2<f32>) -> vec3<f32> {
    let params = feature_param(id, FEATURE_IRIDESCENCE, 0u, vec4<f32>(0.0, 1.3, 0.0, 0.0));
    let thickness = max(mix(params.z, params.w, clamp(mapped.y, 0.0, 1.0)), 0.0);
    // A film of no thickness has no factor (as `iridescence_at`).
    let factor = select(0.0, clamp(mapped.x, 0.0, 1.0), thickness > 0.0);
    return vec3<f32>(factor, max(params.y, 1.0), thickness);
}
