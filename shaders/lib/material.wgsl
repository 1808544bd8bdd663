// Emeshe's material buffers and how to read them. A material's flag word has
// bit n set when it has feature n; its FeatureOffset entries are sorted by
// feature id, so feature f is entry `address + countOneBits(flags below f)`.
// Built by crates/render/src/material (MaterialWorld), whose FEATURE_*
// constants these mirror; crates/render/tests/material.rs ties them together.
#define_import_path spreadlight::material

const FEATURE_COOK_TORRANCE: u32 = 0u;
const FEATURE_EMISSION: u32 = 1u;
const FEATURE_FAKE_SSS: u32 = 2u;
const FEATURE_REFLECTION: u32 = 3u;
const FEATURE_MATCAP: u32 = 4u;
const FEATURE_AMBIENT_OCCLUSION: u32 = 5u;
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
    pad: u32,
}

@group(1) @binding(0) var<storage, read> material_meta: array<MaterialMeta>;
@group(1) @binding(1) var<storage, read> feature_offsets: array<FeatureOffset>;
@group(1) @binding(2) var<storage, read> material_data: array<vec4<f32>>;

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
