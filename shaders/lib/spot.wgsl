// Spot lights as Emeshe has them: projectors, lit inside their frustum,
// through a layer of a texture array (SPOT_TEXTURE) or as a round cone with
// a soft edge. Shared by the deferred light loop (lighting/cook_torrance.wgsl)
// and the forward one of lit transparency (post/transparency.wgsl), so a
// spot lights a glass pane exactly as it lights the wall behind it. The
// bindings are the same numbers in both passes.
#define_import_path spreadlight::spot
#import spreadlight::lights::spot_attenuation

// World to each spot's clip space.
@group(0) @binding(14) var<storage, read> spot_projections: array<mat4x4<f32>>;
#ifdef SPOT_TEXTURE
@group(0) @binding(15) var spot_textures: texture_2d_array<f32>;
@group(0) @binding(16) var spot_sampler: sampler;
#endif

// What spot `light` projects onto world point `pw`: black outside its
// frustum, its texture layer (cone.y >= 0) or a round cone with a soft edge
// (cone.x) inside. `cone` is the light record's `cone`.
fn spot_mask(light: u32, cone: vec4<f32>, pw: vec3<f32>) -> vec3<f32> {
    let clip = spot_projections[light] * vec4<f32>(pw, 1.0);
    if (clip.w <= 0.0) {
        return vec3<f32>(0.0);
    }
    let ndc = clip.xyz / clip.w;
    if (any(abs(ndc.xy) > vec2<f32>(1.0)) || ndc.z < 0.0 || ndc.z > 1.0) {
        return vec3<f32>(0.0);
    }
#ifdef SPOT_TEXTURE
    if (cone.y >= 0.0) {
        let layers = textureNumLayers(spot_textures);
        let layer = u32(cone.y) % max(layers, 1u);
        let uv = vec2<f32>(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5);
        return max(textureSampleLevel(spot_textures, spot_sampler, uv, layer, 0.0).rgb, vec3<f32>(0.0));
    }
#endif
    // The cone's edge as the tested smooth step: 1 - radius against 0 (the
    // edge) and the softness (where it is fully lit).
    return vec3<f32>(spot_attenuation(1.0 - length(ndc.xy), 0.0, cone.x));
}
