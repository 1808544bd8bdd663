// Emeshe's material buffers and how to read them. A material's flag word has
// bit n set when it has feature n; its FeatureOffset entries are sorted by
// feature id, so feature f is entry `address + countOneBits(flags below f)`.
// Built by crates/render/src/material (MaterialWorld), whose FEATURE_*
// constants these mirror; crates/render/tests/material.rs ties them together.
#define_import_path spreadlight::material
#ifdef SURFACE_TARGET
#import spreadlight::surface_target::surface_at
#endif

const FEATURE_COOK_TORRANCE: u32 = 0u;
const FEATURE_EMISSION: u32 = 1u;
const FEATURE_FAKE_SSS: u32 = 2u;
const FEATURE_REFLECTION: u32 = 3u;
const FEATURE_MATCAP: u32 = 4u;
const FEATURE_AMBIENT_OCCLUSION: u32 = 5u;
// A glTF material's maps (shaders/lib/material_maps.wgsl); what the G-buffer
// resolve made of them is in the surface target (shaders/lib/surface_target.wgsl).
const FEATURE_SURFACE_MAPS: u32 = 6u;
// A clear coat over the base (factor, roughness): CookTorrance's CLEARCOAT.
const FEATURE_CLEARCOAT: u32 = 7u;
// Shown as its albedo (strength): CompositeLight, under EMISSION.
const FEATURE_UNLIT: u32 = 8u;
// Refracted transmission (factor, ior, thickness; absorption rgb): lit
// transparency's TRANSMISSION (post/transparency.wgsl).
const FEATURE_TRANSMISSION: u32 = 9u;
// An anisotropic specular lobe (strength, rotation): the G-buffer's
// anisotropy target carries its direction per pixel, CookTorrance's
// ANISOTROPY draws it (shaders/lib/anisotropy.wgsl).
const FEATURE_ANISOTROPY: u32 = 12u;
// A thin film over the surface (factor, film ior, thickness minimum and
// maximum in nm): CookTorrance's and Reflection's IRIDESCENCE.
const FEATURE_IRIDESCENCE: u32 = 11u;
// A sheen (rgb colour, roughness): CookTorrance's, Reflection's and lit
// transparency's SHEEN (shaders/lib/sheen.wgsl).
const FEATURE_SHEEN: u32 = 10u;
const FIRST_CUSTOM_FEATURE: u32 = 16u;
const MAX_FEATURES: u32 = 32u;

struct MaterialMeta {
    flags: u32,
    // Index of the material's first FeatureOffset entry.
    address: u32,
    // Its number of features.
    size: u32,
    pad: u32,
}

struct FeatureOffset {
    feature: u32,
    // Into material_data, in vec4s.
    offset: u32,
    // Number of vec4 parameters.
    count: u32,
    // The feature's Texture ID: its layer + 1; 0: none.
    texture: u32,
    // Per component of the first parameter: the layer + 1 (low 24 bits; 0:
    // nothing) and the channel of it (bits 24..26) that scales it
    // (Material::component_maps: the Texture ID gives component k channel k,
    // a parameter's own texture its red channel, or rgb for a colour).
    maps: vec4<u32>,
}

@group(1) @binding(0) var<storage, read> material_meta: array<MaterialMeta>;
@group(1) @binding(1) var<storage, read> feature_offsets: array<FeatureOffset>;
@group(1) @binding(2) var<storage, read> material_data: array<vec4<f32>>;
// MATERIAL_TEXTURES: the world's texture array, and the G-buffer's
// velocity_uv target (UV in zw) to map it by. Compiled only when some
// material of the world reads a texture. (What the G-buffer resolved per
// pixel, surface maps or a shader node material, is the surface target:
// spreadlight::surface_target, SURFACE_TARGET.)
#ifdef MATERIAL_TEXTURES
@group(1) @binding(3) var material_textures: texture_2d_array<f32>;
@group(1) @binding(4) var material_sampler: sampler;
@group(1) @binding(5) var material_uv: texture_2d<f32>;
#endif

// An id the world does not have reads material 0 (every world has one).
fn material_index(id: u32) -> u32 {
    return select(0u, id, id < arrayLength(&material_meta));
}

fn material_flags(id: u32) -> u32 {
    return material_meta[material_index(id)].flags;
}

fn has_feature(id: u32, feature: u32) -> bool {
    return feature < MAX_FEATURES && (material_flags(id) & (1u << feature)) != 0u;
}

// Parameter `index` of `feature` on material `id`; `fallback` when the
// material lacks the feature or the feature has fewer parameters.
fn feature_param(id: u32, feature: u32, index: u32, fallback: vec4<f32>) -> vec4<f32> {
    let m = material_meta[material_index(id)];
    if (feature >= MAX_FEATURES || (m.flags & (1u << feature)) == 0u) {
        return fallback;
    }
    let below = m.flags & ((1u << feature) - 1u);
    let entry = feature_offsets[m.address + countOneBits(below)];
    if (index >= entry.count) {
        return fallback;
    }
    return material_data[entry.offset + index];
}

// The texture layer + 1 of `feature` on material `id`; 0 for none.
fn feature_texture(id: u32, feature: u32) -> u32 {
    let m = material_meta[material_index(id)];
    if (feature >= MAX_FEATURES || (m.flags & (1u << feature)) == 0u) {
        return 0u;
    }
    let below = m.flags & ((1u << feature) - 1u);
    return feature_offsets[m.address + countOneBits(below)].texture;
}

// What scales each component of the feature's first parameter (zero: nothing).
fn feature_maps(id: u32, feature: u32) -> vec4<u32> {
    let m = material_meta[material_index(id)];
    if (feature >= MAX_FEATURES || (m.flags & (1u << feature)) == 0u) {
        return vec4<u32>(0u);
    }
    let below = m.flags & ((1u << feature) - 1u);
    return feature_offsets[m.address + countOneBits(below)].maps;
}

// `feature_param` at a pixel. Where the G-buffer resolved the pixel's
// surface (SURFACE_TARGET, written: glTF surface maps or a shader node
// material), CookTorrance's roughness and metallic and Emission's colour
// are what it wrote, whatever features the material has (CookTorrance keeps
// the material's reflectance, zw, unless a material extension's map wrote
// one; Emission's strength is 1: the resolve applied it). Otherwise, with MATERIAL_TEXTURES, each component of the
// first parameter that has a map (the feature's Texture ID, or its
// parameter's own layer) is scaled by that layer's channel at the pixel's
// G-buffer UV. Layers past the array's end wrap; a texture never makes a
// value negative.
fn feature_param_at(id: u32, feature: u32, index: u32, fallback: vec4<f32>, pixel: vec2<u32>) -> vec4<f32> {
    let value = feature_param(id, feature, index, fallback);
#ifdef SURFACE_TARGET
    if (index == 0u && (feature == FEATURE_COOK_TORRANCE || feature == FEATURE_EMISSION)) {
        let s = surface_at(pixel);
        if (s.written) {
            if (feature == FEATURE_COOK_TORRANCE) {
                // A specular map's reflectance, where the material has an extension's map.
                return vec4<f32>(s.roughness, s.metallic, select(value.z, s.reflectance, s.extended), value.w);
            }
            return vec4<f32>(s.emission, 1.0);
        }
    }
#endif
#ifdef MATERIAL_TEXTURES
    let maps = feature_maps(id, feature);
    if (index == 0u && any(maps != vec4<u32>(0u))) {
        let uv = textureLoad(material_uv, pixel, 0).zw;
        let layers = max(textureNumLayers(material_textures), 1u);
        var scaled = value;
        // One sample per component that has a map; a layer the component
        // before read is not sampled again (a Texture ID maps all four).
        var last = 0u;
        var texel = vec4<f32>(1.0);
        for (var k = 0u; k < 4u; k++) {
            let m = maps[k];
            let layer = m & 0xffffffu;
            if (layer == 0u) {
                continue;
            }
            if (layer != last) {
                texel = textureSampleLevel(material_textures, material_sampler, uv, (layer - 1u) % layers, 0.0);
                last = layer;
            }
            scaled[k] = value[k] * max(texel[min(m >> 24u, 3u)], 0.0);
        }
        return scaled;
    }
#endif
    return value;
}

// The Clearcoat feature's (factor, roughness) at a pixel: where the G-buffer
// resolve wrote a material extension's maps (SURFACE_TARGET), what its
// clearcoat maps made of them; else the material's. 0 without the feature.
fn clearcoat_at(id: u32, pixel: vec2<u32>) -> vec2<f32> {
    let coat = feature_param(id, FEATURE_CLEARCOAT, 0u, vec4<f32>(0.0)).xy;
#ifdef SURFACE_TARGET
    if (coat.x > 0.0) {
        let s = surface_at(pixel);
        if (s.extended) {
            return vec2<f32>(s.coat, s.coat_roughness);
        }
    }
#endif
    return coat;
}

// The coat's own view-space normal at a pixel: where the G-buffer resolve
// wrote a clearcoat normal map's (SURFACE_TARGET), that; else `n`, the
// pixel's normal, which the coat then shares.
fn clearcoat_normal_at(pixel: vec2<u32>, n: vec3<f32>) -> vec3<f32> {
#ifdef SURFACE_TARGET
    let s = surface_at(pixel);
    if (s.extended && s.coat_normal_written) {
        return s.coat_normal;
    }
#endif
    return n;
}

// The Iridescence feature's film at a pixel: (factor 0..1, the film's
// index >= 1, its thickness in nm >= 0). Without a thickness map the film
// is its maximum thickness (glTF's rule). A film of no thickness has no
// factor (as the Khronos sample viewer has it). 0 without the feature.
fn iridescence_at(id: u32, pixel: vec2<u32>) -> vec3<f32> {
    let film = feature_param(id, FEATURE_IRIDESCENCE, 0u, vec4<f32>(0.0, 1.3, 0.0, 0.0));
    let thickness = max(film.w, 0.0);
    let factor = select(0.0, clamp(film.x, 0.0, 1.0), thickness > 0.0);
    return vec3<f32>(factor, max(film.y, 1.0), thickness);
}
