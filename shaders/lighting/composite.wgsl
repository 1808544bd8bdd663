// CompositeLight: the lit image from CookTorrance's components, one pair
// (diffuse, specular) per light type, up to four pairs (LIGHTS_2..4), plus
// emission per material (EMISSION) from the material buffer, and ambient
// occlusion (AO), optionally weighted per material (AO_PER_MATERIAL).
// Diffuse already carries albedo; ambient is a constant term times albedo,
// darkened by AO; GI (indirect diffuse radiance: SSGI, image-based diffuse
// light) is times albedo too, not darkened again (SSGI occludes its own). REFLECTION adds specular reflection
// radiance times each material's Reflection strength (0 without it).
// MATCAP adds each MatCap material's matcap, looked up by the G-buffer's
// view-space normal (or the reflected view vector), times albedo or as light,
// times its strength; MATCAP_TEXTURE binds the material texture array its
// images are layers of (else the built-in matcap).
// Under EMISSION too (compiled when some material emits or is unlit):
// materials with the Unlit feature show their albedo (glTF's
// KHR_materials_unlit: base colour x maps x vertex colour), mixed over the
// lit colour by its strength; lights, ambient, GI and reflections do not
// reach them. One flag test per pixel, sharing the emission permutation
// rather than doubling the composite's permutations.
// MATERIALS: the material library is bound (emission, per-material AO,
// reflection, matcap or unlit need it). SURFACE_TARGET: what the G-buffer resolved
// per pixel (below). Clamped below half-float overflow.
#import spreadlight::camera::{Camera, pixel_to_ndc}

struct Params {
    // rgb ambient radiance, w unused
    ambient: vec4<f32>,
}

@group(0) @binding(0) var<uniform> camera: Camera;
@group(0) @binding(1) var<uniform> params: Params;
@group(0) @binding(2) var color: texture_2d<f32>;
@group(0) @binding(5) var depth: texture_2d<f32>;
@group(0) @binding(6) var output: texture_storage_2d<rgba16float, write>;
@group(0) @binding(3) var diffuse0: texture_2d<f32>;
@group(0) @binding(4) var specular0: texture_2d<f32>;
// Pairs beyond the first are cumulative switches: three light types set
// LIGHTS_2 and LIGHTS_3.
#ifdef LIGHTS_2
@group(0) @binding(7) var diffuse1: texture_2d<f32>;
@group(0) @binding(8) var specular1: texture_2d<f32>;
#endif
#ifdef LIGHTS_3
@group(0) @binding(9) var diffuse2: texture_2d<f32>;
@group(0) @binding(10) var specular2: texture_2d<f32>;
#endif
#ifdef LIGHTS_4
@group(0) @binding(11) var diffuse3: texture_2d<f32>;
@group(0) @binding(12) var specular3: texture_2d<f32>;
#endif
// Subsurface terms, per light type k (SSS_k), when its CookTorrance produced one.
#ifdef SSS_1
@group(0) @binding(13) var sss0: texture_2d<f32>;
#endif
#ifdef SSS_2
@group(0) @binding(14) var sss1: texture_2d<f32>;
#endif
#ifdef SSS_3
@group(0) @binding(15) var sss2: texture_2d<f32>;
#endif
#ifdef SSS_4
@group(0) @binding(16) var sss3: texture_2d<f32>;
#endif
// The material library, imported once, for EMISSION (only when some
// material has Emission), AO's per-material strength and REFLECTION's.
#ifdef MATERIALS
#import spreadlight::material::{feature_param, feature_param_at, FEATURE_COOK_TORRANCE, FEATURE_EMISSION, FEATURE_AMBIENT_OCCLUSION, FEATURE_REFLECTION}
#import spreadlight::packing::channel_to_id
#endif
// SURFACE_TARGET: the G-buffer has a surface target. Where the resolve
// wrote a pixel's surface (glTF surface maps, a shader node material), its
// occlusion darkens the ambient term and indirect diffuse light, its
// metallic takes its share of indirect diffuse light and its emission is
// added, with or without a material world (shaders/lib/surface_target.wgsl).
#ifdef SURFACE_TARGET
#import spreadlight::surface_target::surface_at
#endif
#ifdef EMISSION
#import spreadlight::material::FEATURE_UNLIT
#endif
#ifdef GI
@group(0) @binding(18) var gi: texture_2d<f32>;
#endif
#ifdef REFLECTION
@group(0) @binding(19) var reflection: texture_2d<f32>;
#endif
#ifdef MATCAP
#import spreadlight::material::{feature_texture, FEATURE_MATCAP}
#import spreadlight::matcap::{matcap_uv, default_matcap}
@group(0) @binding(22) var normals: texture_2d<f32>;
#ifdef MATCAP_TEXTURE
@group(0) @binding(20) var matcap_images: texture_2d_array<f32>;
@group(0) @binding(21) var matcap_sampler: sampler;
#endif
#endif

// A texel from an effect's output: negative or non-finite values add nothing.
fn clean(v: vec3<f32>) -> vec3<f32> {
    return select(vec3<f32>(0.0), min(v, vec3<f32>(65000.0)), v >= vec3<f32>(0.0) & v <= vec3<f32>(3e38));
}
#ifdef AO
// Ambient visibility (R, 0..1) darkening the ambient term; AO_PER_MATERIAL
// weights it by each material's AmbientOcclusion strength (0 = unaffected).
@group(0) @binding(17) var occlusion: texture_2d<f32>;
#endif

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = vec2<u32>(camera.size.xy);
    if (id.x >= size.x || id.y >= size.y) {
        return;
    }
    let p = id.xy;
    var lit = vec3<f32>(0.0);
    if (textureLoad(depth, p, 0).r > 0.0) {
        let albedo = textureLoad(color, p, 0).rgb;
        var ambient = params.ambient.rgb * albedo;
#ifdef SURFACE_TARGET
        let resolved = surface_at(p);
        if (resolved.written) {
            ambient *= resolved.occlusion;
        }
#endif
#ifdef AO
        var strength = 1.0;
#ifdef AO_PER_MATERIAL
        strength = feature_param(channel_to_id(textureLoad(color, p, 0).a), FEATURE_AMBIENT_OCCLUSION, 0u, vec4<f32>(0.0)).x;
#endif
        let visibility = clamp(textureLoad(occlusion, p, 0).r, 0.0, 1.0);
        ambient *= mix(1.0, visibility, clamp(strength, 0.0, 1.0));
#endif
        lit = ambient + textureLoad(diffuse0, p, 0).rgb + textureLoad(specular0, p, 0).rgb;
#ifdef GI
        // Not under AO: GI brings what occluders bounce, and SSGI already lets
        // environment light in only along the rays that escape.
        var diffuse_share = 1.0;
#ifdef MATERIALS
        // Metals reflect, they do not diffuse: albedo x (1 - metallic).
        let ct = feature_param(channel_to_id(textureLoad(color, p, 0).a), FEATURE_COOK_TORRANCE, 0u, vec4<f32>(0.5, 0.0, 0.04, 0.0));
        diffuse_share = 1.0 - clamp(ct.y, 0.0, 1.0);
#endif
#ifdef SURFACE_TARGET
        if (resolved.written) {
            diffuse_share = (1.0 - resolved.metallic) * resolved.occlusion;
        }
#endif
        lit += clean(textureLoad(gi, p, 0).rgb) * albedo * diffuse_share;
#endif
#ifdef LIGHTS_2
        lit += textureLoad(diffuse1, p, 0).rgb + textureLoad(specular1, p, 0).rgb;
#endif
#ifdef LIGHTS_3
        lit += textureLoad(diffuse2, p, 0).rgb + textureLoad(specular2, p, 0).rgb;
#endif
#ifdef LIGHTS_4
        lit += textureLoad(diffuse3, p, 0).rgb + textureLoad(specular3, p, 0).rgb;
#endif
#ifdef SSS_1
        lit += textureLoad(sss0, p, 0).rgb;
#endif
#ifdef SSS_2
        lit += textureLoad(sss1, p, 0).rgb;
#endif
#ifdef SSS_3
        lit += textureLoad(sss2, p, 0).rgb;
#endif
#ifdef SSS_4
        lit += textureLoad(sss3, p, 0).rgb;
#endif
#ifdef REFLECTION
        let reflective = feature_param(channel_to_id(textureLoad(color, p, 0).a), FEATURE_REFLECTION, 0u, vec4<f32>(0.0)).x;
        lit += clean(textureLoad(reflection, p, 0).rgb) * clamp(reflective, 0.0, 1.0);
#endif
#ifdef EMISSION
        // A texture scales the emission colour and strength (MATERIAL_TEXTURES);
        // a resolved surface's emission replaces it (feature_param_at).
        let emission = feature_param_at(channel_to_id(textureLoad(color, p, 0).a), FEATURE_EMISSION, 0u, vec4<f32>(0.0), p);
        lit += max(emission.rgb, vec3<f32>(0.0)) * max(emission.a, 0.0);
#else
#ifdef SURFACE_TARGET
        // No material emits (or there is no material world): only resolved surfaces do.
        if (resolved.written) {
            lit += resolved.emission;
        }
#endif
#endif
#ifdef MATCAP
        lit += matcap_light(p, albedo);
#endif
#ifdef EMISSION
        let unlit = clamp(feature_param(channel_to_id(textureLoad(color, p, 0).a), FEATURE_UNLIT, 0u, vec4<f32>(0.0)).x, 0.0, 1.0);
        // Strength 1 is the albedo alone, whatever the lighting summed to.
        lit = select(mix(lit, albedo, unlit), albedo, unlit >= 1.0);
#endif
    }
    textureStore(output, p, vec4<f32>(min(lit, vec3<f32>(65000.0)), 1.0));
}

#ifdef MATCAP
// What pixel `p`'s MatCap adds: nothing on materials without the feature or
// at strength 0, so they stay exactly as without MATCAP.
fn matcap_light(p: vec2<u32>, albedo: vec3<f32>) -> vec3<f32> {
    let id = channel_to_id(textureLoad(color, p, 0).a);
    // x strength, y mode (1: add as light), z mapping (1: reflected).
    let settings = feature_param(id, FEATURE_MATCAP, 0u, vec4<f32>(0.0));
    if (!(settings.x > 0.0)) {
        return vec3<f32>(0.0);
    }
    let raw = textureLoad(normals, p, 0).xyz;
    let n = select(vec3<f32>(0.0, 0.0, 1.0), normalize(raw), dot(raw, raw) > 1e-12);
    let clip = camera.projection_inverse * vec4<f32>(pixel_to_ndc(p, camera.size), textureLoad(depth, p, 0).r, 1.0);
    let position = clip.xyz / clip.w;
    let v = select(vec3<f32>(0.0, 0.0, -1.0), normalize(position), dot(position, position) > 1e-20);
    let uv = matcap_uv(n, v, settings.z > 0.5);
    var image = default_matcap(uv);
#ifdef MATCAP_TEXTURE
    let texture = feature_texture(id, FEATURE_MATCAP);
    if (texture > 0u) {
        let layer = (texture - 1u) % max(textureNumLayers(matcap_images), 1u);
        image = textureSampleLevel(matcap_images, matcap_sampler, uv, layer, 0.0).rgb;
    }
#endif
    let tint = select(albedo, vec3<f32>(1.0), settings.y > 0.5);
    return clean(image * tint * settings.x);
}
#endif
