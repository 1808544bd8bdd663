// The material world for shader nodes, by the names of Emeshe's
// Materials.fxh (MatMeta, FeatureOffset, MaterialData, KnowFeature,
// GetFloat...): what a `// @material` shader node or an image-effect shader
// node imports to read a material's features, their parameters and texture
// ids (docs/shader-nodes.md, "The material world"). Only a file that imports
// it binds it (group 3): a material node gets its DeferredBase's Material
// World, an image effect gets a `Material World` pin. The buffers are the
// ones crates/render/src/material packs (MaterialWorld, and
// shaders/lib/material.wgsl for the built-in passes); the layouts match
// GpuMaterialMeta and GpuFeatureOffset (crates/render/src/material/library.rs
// checks them).
//
// Feature ids, not flags, are passed (Emeshe passed both as a uint2): feature
// id n is flag 1 << n; 0..=5 are the built-ins, 16..=31 custom features.
// Material ids past the world's last read material 0, as every pass does.
// Emeshe's GetFloat2/3/4 are GetFloats(...).xy / .xyz / the whole vec4 (an
// imported name cannot end in a digit).
#define_import_path spreadlight::materials

const FEATURE_COOK_TORRANCE: u32 = 0u;
const FEATURE_EMISSION: u32 = 1u;
const FEATURE_FAKE_SSS: u32 = 2u;
const FEATURE_REFLECTION: u32 = 3u;
const FEATURE_MATCAP: u32 = 4u;
const FEATURE_AMBIENT_OCCLUSION: u32 = 5u;
const FEATURE_SURFACE_MAPS: u32 = 6u;
const FIRST_CUSTOM_FEATURE: u32 = 16u;
const MAX_FEATURES: u32 = 32u;

struct MaterialMeta {
    // Bit n: the material has feature n.
    Flags: u32,
    // Index of its first FeatureOffset entry.
    Address: u32,
    // Its number of features (entries).
    Size: u32,
    Pad: u32,
}

// One feature of one material; a material's entries are in ascending feature id.
struct FeatureEntry {
    Feature: u32,
    // Into MaterialData, in vec4s.
    Offset: u32,
    // Its parameters, in vec4s.
    Count: u32,
    // The feature's Texture ID + 1 (0: none).
    Texture: u32,
    // Per component of the first parameter vec4, the layer + 1 (low 24
    // bits; 0: none) and channel (bits 24..26) that scale it in shading.
    Maps: vec4<u32>,
}

@group(3) @binding(0) var<storage, read> MatMeta: array<MaterialMeta>;
@group(3) @binding(1) var<storage, read> FeatureOffset: array<FeatureEntry>;
@group(3) @binding(2) var<storage, read> MaterialData: array<vec4<f32>>;
// The MaterialBuffer's texture array (a white layer when it has none) and a
// repeating linear sampler: bound only for a file that samples it.
@group(3) @binding(3) var MaterialTextures: texture_2d_array<f32>;
@group(3) @binding(4) var MaterialSampler: sampler;

// How many materials the world has (at least 1).
fn MaterialCount() -> u32 {
    return arrayLength(&MatMeta);
}

// `MatID`, or 0 where the world has no such material.
fn MatIndex(MatID: u32) -> u32 {
    return select(0u, MatID, MatID < arrayLength(&MatMeta));
}

// The flag of feature `FeatureID`: 1 << id, 0 for an id past 31.
fn FeatureFlag(FeatureID: u32) -> u32 {
    return select(0u, 1u << min(FeatureID, 31u), FeatureID < MAX_FEATURES);
}

// Whether a flag word has every bit of `Filter` (Emeshe's CheckFeature).
fn CheckFeature(Features: u32, Filter: u32) -> bool {
    return (Features & Filter) == Filter;
}

// The flag word of material `MatID`.
fn GetFlags(MatID: u32) -> u32 {
    return MatMeta[MatIndex(MatID)].Flags;
}

// Whether material `MatID` has feature `FeatureID` (false for an id past 31).
fn KnowFeature(MatID: u32, FeatureID: u32) -> bool {
    let flag = FeatureFlag(FeatureID);
    return flag != 0u && CheckFeature(GetFlags(MatID), flag);
}

// The material's entry for the feature; Count 0 and Texture 0 when it lacks it.
fn GetFeatureEntry(MatID: u32, FeatureID: u32) -> FeatureEntry {
    var none: FeatureEntry;
    none.Feature = FeatureID;
    let m = MatMeta[MatIndex(MatID)];
    let flag = FeatureFlag(FeatureID);
    if (flag == 0u || (m.Flags & flag) == 0u) {
        return none;
    }
    // Entries are sorted by id: the features below this one come first.
    return FeatureOffset[m.Address + countOneBits(m.Flags & (flag - 1u))];
}

// How many vec4 parameters the material's feature has (0 without it).
fn GetParamCount(MatID: u32, FeatureID: u32) -> u32 {
    return GetFeatureEntry(MatID, FeatureID).Count;
}

// Parameter vec4 `Index` of the feature, or `Fallback` where the material
// lacks the feature or the feature has fewer parameters.
fn GetParam(MatID: u32, FeatureID: u32, Index: u32, Fallback: vec4<f32>) -> vec4<f32> {
    let e = GetFeatureEntry(MatID, FeatureID);
    if (Index >= e.Count) {
        return Fallback;
    }
    return MaterialData[e.Offset + Index];
}

// Float `ParamOffset` of the feature's parameters, counted in floats over its
// vec4s as Emeshe's MaterialData was (offset 5 is the second vec4's y); 0
// where there is none.
fn GetFloat(MatID: u32, FeatureID: u32, ParamOffset: u32) -> f32 {
    let e = GetFeatureEntry(MatID, FeatureID);
    let index = ParamOffset / 4u;
    if (index >= e.Count) {
        return 0.0;
    }
    return MaterialData[e.Offset + index][ParamOffset % 4u];
}

// Four floats from `ParamOffset` on (Emeshe's GetFloat4; .xy and .xyz for
// GetFloat2 and GetFloat3); 0 past the feature's parameters.
fn GetFloats(MatID: u32, FeatureID: u32, ParamOffset: u32) -> vec4<f32> {
    return vec4<f32>(
        GetFloat(MatID, FeatureID, ParamOffset),
        GetFloat(MatID, FeatureID, ParamOffset + 1u),
        GetFloat(MatID, FeatureID, ParamOffset + 2u),
        GetFloat(MatID, FeatureID, ParamOffset + 3u),
    );
}

// The layer of the MaterialBuffer's texture array the feature's Texture ID
// names, or -1 for none (or no such feature).
fn GetTexID(MatID: u32, FeatureID: u32) -> i32 {
    return i32(GetFeatureEntry(MatID, FeatureID).Texture) - 1;
}

// The feature's texture layer at `uv` (repeating; layers past the array's
// end wrap, as the built-in passes read them), or 1 where it has none.
fn SampleFeature(MatID: u32, FeatureID: u32, uv: vec2<f32>) -> vec4<f32> {
    let texture = GetFeatureEntry(MatID, FeatureID).Texture;
    if (texture == 0u) {
        return vec4<f32>(1.0);
    }
    let layer = (texture - 1u) % max(textureNumLayers(MaterialTextures), 1u);
    return textureSampleLevel(MaterialTextures, MaterialSampler, uv, layer, 0.0);
}
