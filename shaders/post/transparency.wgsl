// Weighted blended order-independent transparency (McGuire and Bavoil,
// "Weighted Blended Order-Independent Transparency", JCGT 2013), as
// Castor3D's transparent pass does it: transparent meshes are rasterized in
// any order into two targets (cleared in compute first: see `clear`) with
// fixed-function blending,
//   accumulation += (premultiplied colour, alpha) * w(z, alpha)   (One, One)
//   revealage    *= 1 - alpha                                     (Zero, 1 - src)
// each fragment depth-tested by hand against the G-buffer's (opaque) depth,
// and a compute `resolve` composites the weighted average over the opaque
// image by the revealage: opaque * r + average * (1 - r).
//
// The weight is the paper's equation 7, 10 / (1e-5 + (z/5)^2 + (z/200)^6)
// clamped to 1e-2..3e3, divided by 3e3 so it is at most 1: with colours held
// at 600 or less, 100 overlapping layers sum to under 65504, so the
// half-float accumulation cannot overflow at the near plane, and at the far
// plane the smallest weight (3e-6) is still a half float.
//
// Lighting is forward+ (breezEngine's "mixing forward and deferred"): the
// transparent surfaces are not in the G-buffer, so each layer is drawn once
// for its unlit part (the base pass: the colour times Ambient, emission,
// ENVIRONMENT's image-based light, and, when no light buffer is connected,
// one two-sided directional key light from `params`), then once more per
// connected light buffer
// (LIGHT_PASS, the light type compiled in as CookTorrance compiles it:
// point by default, LIGHT_SPOT, LIGHT_SUN; SHADOWS and its filter;
// CLUSTERED walks the froxel lists of lighting/clusters.wgsl, made as
// CookTorrance's are, else every light; FROXEL_MARKS: the base pass marks
// the froxels its fragments lie in, and only those get lists). The sum is
// linear in the colour, so a light pass adds its Cook-Torrance diffuse and
// specular times alpha times the same weight to the accumulation's colour
// alone (its pipeline masks alpha and the revealage): the result is the one
// pass the paper draws, with each light type's code compiled only when a
// scene has that type.
//
// The colour and coverage are glTF's base colour: the instance colour
// (factor) x the base colour map (MATERIAL_MAPS: the layer's material world
// has surface maps; group 1 the world, group 3 its map arrays, sampled as
// the G-buffer resolve does, with the map's UV set, sampler and
// KHR_texture_transform) x COLOR_0 (VERTEX_EXTRAS: the arena's extra
// stream, binding 12), alpha included; a DeferredBase layer's Color Texture
// (COLOR_MAP) and normal map (NORMAL_MAP, group 2) by its UVs (TEXCOORDS)
// or a planar projection (TRIPLANAR). MATERIALS: roughness, metallic,
// reflectance and emission from the material world's CookTorrance and
// Emission features by the instance's material id (with surface maps,
// scaled by the metallic-roughness and emissive maps), else the node's pins.
// EXTENSION_MAPS (with MATERIAL_MAPS; the world has a material extension's
// map): the reflectance by the specular maps, the thickness by the
// thickness map, the coat by the clearcoat maps.
// ANISOTROPY (a light pass or a recording base pass with MATERIAL_MAPS;
// the layer's world has an Anisotropy material, KHR_materials_anisotropy):
// the specular lobe stretched along the fragment's anisotropy direction (its
// tangent turned by the rotation and the anisotropy map), as CookTorrance
// draws it on opaque surfaces (lib/anisotropy.wgsl through
// lib/forward_light.wgsl). Compute shading: the recording base pass keeps
// each fragment's direction and strength in `anisotropy_records` (8 bytes a
// slot, bound and cleared only when some layer of the node is anisotropic)
// and the shade passes of such a node compile ANISOTROPY and set the lobe
// per fragment before its lights; a cleared record is strength 0, the
// isotropic lobe.
// CLEARCOAT (with MATERIALS; the layer's world has a Clearcoat material):
// the light passes add the coat's lobe (GGX, f0 0.04, on the coat's own
// normal: the clearcoat normal map's, else the surface's, normal mapped)
// and dim what is under it by the coat's Fresnel at N.V, as CookTorrance
// does for opaque surfaces. Compute shading keeps each fragment's coat in
// a record of its own (`coat_records`, 8 bytes a slot, bound and cleared
// only when some layer of the node is coated), so the records of uncoated
// frames stay as they are; the shade passes of a node with a coated layer
// compile CLEARCOAT, the base passes of its coated layers write it, and a
// fragment no coated layer wrote reads a cleared record: no coat.
// SHEEN (light passes and recording base passes of a layer whose world has
// a Sheen material): the sheen's Charlie lobe and the base's dimming under
// it, as CookTorrance draws them (lib/forward_light.wgsl's sheened_specular),
// under the coat; with EXTENSION_MAPS the sheen's colour and roughness maps
// scale it. Compute shading keeps each fragment's sheen colour and
// roughness in `sheen_records` (8 bytes a slot, bound and cleared only when
// some layer of the node has a sheen; a cleared record is black: none), and
// the shade passes of such a node compile SHEEN. The same switch (a light
// pass of a layer whose world has an Iridescence material) draws a thin
// film: its Fresnel at N.V (lib/iridescence.wgsl) mixed into the specular
// and diffuse weights by the factor, as CookTorrance's IRIDESCENCE draws it
// (lib/forward_light.wgsl's filmed_light); with EXTENSION_MAPS the
// iridescence and thickness maps set the factor and thickness per fragment.
// A soap bubble is a BLEND film. Forward light passes only: the compute
// records keep no film, so Auto shades a filmed layer forward. (One switch
// for both lobes, branched per material: a switch of its own would double
// the light passes.)
// MATCAP (base pass, with MATERIALS): a layer whose material has MatCap
// gets it as CompositeLight gives opaque surfaces, looked up by the
// view-space normal of the face shown (MATCAP_TEXTURE: the world's texture
// array holds its images; else the built-in clay). SSR, Reflection's
// screen-space input and SSAO are the G-buffer's, which transparent layers
// are not in: they get the Environment (ENVIRONMENT) and no SSR; a coated
// layer's base pass (CLEARCOAT with ENVIRONMENT) adds the coat's own
// reflection of it and dims the base's (`coated_environment`).
// TRANSMISSION (base pass; a layer whose world has a Transmission material,
// or any layer when the node's Transmission is on): of what shows through
// a fragment (1 - alpha), the material's share is refracted instead of
// blended, as glTF viewers draw KHR_materials_transmission: the opaque lit
// image (`lit_opaque`, before this composite) sampled where the ray, bent
// by Snell's law into a slab `thickness` deep and leaving it parallel,
// meets the opaque depth (`exit_uv`: a few steps walking the ray onto the
// depth under its guess), blurred by roughness over a few taps, or with
// REFRACTION_MIPS by one trilinear read of the opaque image's mip chain
// (`refraction_mips`, built by `refraction_mips_first` / `_down` below) at
// the level as wide as the taps' disc, tinted by the base colour and
// absorbed by Beer-Lambert over the path inside; a dispersive material
// (KHR_materials_dispersion) walks red, green and blue at their own index
// (`transmitted`, a branch on its dispersion). The fragment then covers
// alpha + share (the weight and the revealage see that); its diffuse keeps
// alpha, emission, reflections and speculars take the coverage. Only the
// opaque scene is seen refracted (other transparent layers behind are not
// in `lit_opaque`); a ray that leaves the screen sees the Environment
// (ENVIRONMENT) along it, faded in over a band beyond the border, else the
// screen's edge.
// Compute shading (crates/render/src/post/transparency/compute.rs): instead
// of drawing each layer again per light buffer, the base pass stores each
// fragment it keeps (FRAGMENT_RECORDS: position, facing normal, albedo,
// roughness, metallic, reflectance, alpha, coverage; 40 bytes) in its
// pixel's slots, and a compute pass per light buffer (COMPUTE_SHADE, entry
// `shade`) walks each pixel's records with the same light walk and adds
// what the light pass would have added to the colour, summed in f32, to a
// buffer the resolve adds (LIGHT_SUMS). No fragment is shaded twice for a
// light buffer, no helper lanes shade, and nothing goes through the
// blender but the base pass.
// Both faces are drawn, except for one-sided glTF materials, whose back
// faces the pipeline culls; a back face is lit with its normal turned to
// the viewer (a glass shell's inside).
#import spreadlight::camera::Camera
#import spreadlight::mesh_fetch::{instances, triangle_vertex, view_right, view_up}
#import spreadlight::post::{sanitize, HALF_MAX, bilinear}
#import spreadlight::packing::safe_normalize
#ifdef MATERIALS
#import spreadlight::material::{feature_param, FEATURE_COOK_TORRANCE, FEATURE_EMISSION, FEATURE_REFLECTION, FEATURE_TRANSMISSION}
#endif
#ifdef ENVIRONMENT
#import spreadlight::ibl::{split_sum, facing_normal}
#endif
#ifdef MATCAP
#import spreadlight::material::{feature_texture, FEATURE_MATCAP}
#import spreadlight::matcap::{matcap_uv, default_matcap}
#endif
#ifdef MATERIAL_MAPS
#import spreadlight::material_maps::{MapCoords, sample_map, has_map, map_settings, MAP_BASE_COLOR, MAP_METALLIC_ROUGHNESS, MAP_NORMAL, MAP_OCCLUSION, MAP_EMISSIVE}
#ifdef EXTENSION_MAPS
#import spreadlight::material_maps::{mapped_reflectance, MAP_THICKNESS}
#ifdef CLEARCOAT
#import spreadlight::material_maps::{mapped_clearcoat, clearcoat_normal_texel, MAP_CLEARCOAT_NORMAL}
#endif
#endif
#endif
#ifdef VERTEX_EXTRAS
#import spreadlight::mesh::vertex_color
#import spreadlight::vertex_extras::corner_extra
#endif
#ifdef LIGHT_PASS
#import spreadlight::brdf::{BrdfSurface, LightSums, brdf_surface, no_light_sums, light_sums_brdf, surface_energy_compensation}
// A light's share: the forward passes' one copy of CookTorrance's `shade`
// (lib/forward_light.wgsl), which the environment probe's faces use too.
#import spreadlight::forward_light::{Light, lights, add_forward_light, add_light_record}
#endif
#ifdef ANISOTROPY
#ifdef MATERIAL_MAPS
// (Surface maps only.) The fragment's anisotropy direction and strength.
#import spreadlight::material::{has_feature, FEATURE_ANISOTROPY}
#import spreadlight::material_maps::mapped_anisotropy
#endif
#ifdef LIGHT_PASS
// The fragment's anisotropic lobe, which the light function reads
// (lib/forward_light.wgsl holds it; the compute shading sets it per record).
#import spreadlight::anisotropy::anisotropic_surface
#import spreadlight::forward_light::aniso
#endif
#endif
#ifdef CLEARCOAT
#ifdef MATERIALS
#import spreadlight::material::FEATURE_CLEARCOAT
#endif
#ifdef LIGHT_PASS
#import spreadlight::brdf::DIELECTRIC_F0
// The shaded fragment's coat, which the light function sums into
// (lib/forward_light.wgsl holds it beside the coat's lobe).
#import spreadlight::forward_light::{coat_factor, coat_surface, coat_sum, coated_specular}
#endif
#ifdef ENVIRONMENT
// The coat's reflection of the environment (the base pass's; ENVIRONMENT
// is never a light pass's).
#import spreadlight::brdf::{schlick_weight, DIELECTRIC_F0}
#endif
#endif
#ifdef SHEEN
#ifdef MATERIALS
// The fragment's sheen parameters (a light or recording base pass of a
// layer whose world has a Sheen material), scaled by its maps.
#import spreadlight::material::FEATURE_SHEEN
#ifdef EXTENSION_MAPS
#import spreadlight::material_maps::mapped_sheen
#endif
#endif
#ifdef LIGHT_PASS
// The shaded fragment's sheen, summed by the light function as the coat is.
#import spreadlight::forward_light::{sheen_color, sheen_roughness, sheen_sum, sheened_specular}
// The shaded fragment's film (a light pass of a layer whose world has an
// Iridescence material), whose diffuse light the light function sums.
#import spreadlight::material::iridescence_at
#import spreadlight::iridescence::iridescence_fresnel
#import spreadlight::forward_light::{film_factor, film_fresnel, film_lit, filmed_light}
#ifdef EXTENSION_MAPS
#import spreadlight::material::FEATURE_IRIDESCENCE
#import spreadlight::material_maps::mapped_film
#import spreadlight::sheen_film::film_of
#endif
#endif
#endif

struct Params {
    // rgb: ambient radiance
    ambient: vec4<f32>,
    // xyz: direction towards the key light (world, unit)
    light_direction: vec4<f32>,
    // rgb: key light radiance (black when light buffers are connected)
    light_color: vec4<f32>,
    // x roughness, y metallic (layers without a material world), z energy
    // compensation (0/1), w the environment's prefiltered levels
    surface: vec4<f32>,
    // Layers without a Transmission material: x the refracted share of what
    // shows through (0: off), y ior, z thickness (world units); w blur taps
    transmission: vec4<f32>,
    // rgb: the same layers' absorption coefficient (1 / world unit); w depth-search steps
    absorption: vec4<f32>,
}

@group(0) @binding(0) var<uniform> camera: Camera;
@group(0) @binding(4) var opaque_depth: texture_2d<f32>;
@group(0) @binding(5) var<uniform> params: Params;
@group(0) @binding(6) var opaque: texture_2d<f32>;
@group(0) @binding(7) var accumulation: texture_2d<f32>;
@group(0) @binding(8) var revealage: texture_2d<f32>;
@group(0) @binding(9) var output: texture_storage_2d<rgba16float, write>;
@group(0) @binding(10) var clear_accumulation: texture_storage_2d<rgba16float, write>;
@group(0) @binding(11) var clear_revealage: texture_storage_2d<rgba16float, write>;

// A fragment's transmission: x the share of what shows through it that is
// refracted (0..1), y ior, z thickness. Its material's Transmission
// feature, else the node's settings (x is 0 when the node's is off and the
// world has none: then nothing refracts and coverage is alpha, as before).
fn transmission_of(material: u32) -> vec4<f32> {
    var t = params.transmission;
#ifdef MATERIALS
    t = feature_param(material, FEATURE_TRANSMISSION, 0u, t);
#endif
    return vec4<f32>(clamp(sanitize(t).x, 0.0, 1.0), t.yzw);
}

#ifdef TRANSMISSION
#ifdef REFRACTION_MIPS
// The opaque lit image's mip chain (half float, every level a box average
// of the one above), read trilinearly: one tap for any roughness.
@group(0) @binding(32) var refraction_mips: texture_2d<f32>;
@group(0) @binding(33) var refraction_sampler: sampler;
#else
// The opaque lit image (before this node's composite), sampled along the
// refracted ray by hand (`bilinear`: any float format, filterable or not).
@group(0) @binding(30) var lit_opaque: texture_2d<f32>;
#endif

// The band outside the screen's border (uv) over which a ray leaving the
// screen fades from the screen's edge to the environment: no seam where the
// screen-space image ends, and a ray that lands on screen, however near the
// border, sees the image alone.
const EDGE_BAND: f32 = 0.05;

fn finite2(v: vec2<f32>) -> bool {
    // False for NaN (every comparison with NaN is) and for infinities.
    return all(abs(v) < vec2<f32>(1e30));
}

// Homogeneous world point `p` (w 0: a direction, the point at infinity) on
// screen as uv, off the screen too (held to -1..2, past the fade band: the
// caller clamps it to sample and fades to the environment beyond);
// `fallback` behind the eye or for anything not finite.
fn screen_uv(p: vec4<f32>, fallback: vec2<f32>) -> vec2<f32> {
    let clip = camera.view_projection * p;
    if (!(clip.w > 1e-6)) {
        return fallback;
    }
    let ndc = clip.xy / clip.w;
    let uv = vec2<f32>(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5);
    if (!finite2(uv)) {
        return fallback;
    }
    return clamp(uv, vec2<f32>(-1.0), vec2<f32>(2.0));
}

// How much of a sample at `uv` is off screen: 0 on the screen, 1 further
// than EDGE_BAND beyond its border, smooth between.
fn off_screen(uv: vec2<f32>) -> f32 {
    let outside = max(max(-uv.x, uv.x - 1.0), max(-uv.y, uv.y - 1.0));
    return smoothstep(0.0, EDGE_BAND, outside);
}

// Where the ray from `start` (world) along `dir` meets the opaque scene,
// as uv: `steps` times, the opaque depth under the current guess gives the
// camera depth the ray is walked to (exact in one step over a background at
// one depth); 0 steps is `start`'s own projection (Khronos' viewer). An
// empty pixel (the far plane) sends the ray to infinity: its vanishing point.
fn exit_uv(start: vec3<f32>, dir: vec3<f32>, steps: u32, fallback: vec2<f32>) -> vec2<f32> {
    var uv = screen_uv(vec4<f32>(start, 1.0), fallback);
    let start_depth = -(camera.view * vec4<f32>(start, 1.0)).z;
    let dir_depth = -(camera.view * vec4<f32>(dir, 0.0)).z;
    // A ray that does not go away from the eye never meets what is behind.
    if (!(dir_depth > 1e-4)) {
        return uv;
    }
    let size = vec2<i32>(textureDimensions(opaque_depth));
    for (var k = 0u; k < min(steps, 8u); k++) {
        let pixel = clamp(vec2<i32>(uv * vec2<f32>(size)), vec2<i32>(0), size - 1);
        let z = textureLoad(opaque_depth, pixel, 0).r;
        let ndc = vec2<f32>(uv.x * 2.0 - 1.0, 1.0 - uv.y * 2.0);
        let view = camera.projection_inverse * vec4<f32>(ndc, z, 1.0);
        if (!(z > 0.0) || !(view.w > 1e-20)) {
            uv = screen_uv(vec4<f32>(dir, 0.0), uv);
            break;
        }
        let depth = -view.z / view.w;
        let t = clamp((depth - start_depth) / dir_depth, 0.0, 1e6);
        uv = screen_uv(vec4<f32>(start + dir * t, 1.0), uv);
    }
    return uv;
}

// The opaque image blurred over a disc of `radius` (uv, of the screen's
// height) about `uv` (on screen).
#ifdef REFRACTION_MIPS
// One trilinear read at the level whose filter matches the disc: a level-L
// texel is 2^L pixels, and its box average read bilinearly spreads like a
// uniform disc of radius 2^L pixels (per axis, variance 4^L (1/12 + 1/6)
// against r^2 / 4), so L = log2(radius in pixels). Under half a pixel is
// level 0, the image itself, as the taps take one tap there.
fn blurred(uv: vec2<f32>, radius: f32) -> vec3<f32> {
    let pixels = radius * f32(textureDimensions(refraction_mips).y);
    let top = f32(textureNumLevels(refraction_mips) - 1u);
    let level = clamp(log2(max(pixels, 1e-6)), 0.0, top);
    return textureSampleLevel(refraction_mips, refraction_sampler, uv, level).rgb;
}
#else
fn blurred(uv: vec2<f32>, radius: f32) -> vec3<f32> {
    let size = vec2<f32>(textureDimensions(lit_opaque));
    let taps = clamp(u32(params.transmission.w), 1u, 32u);
    if (radius * size.y < 0.5 || taps == 1u) {
        return bilinear(lit_opaque, uv).rgb;
    }
    // A Vogel disc (golden-angle spiral), the first tap at the centre.
    let aspect = vec2<f32>(size.y / size.x, 1.0);
    var color = vec3<f32>(0.0);
    for (var i = 0u; i < taps; i++) {
        let rho = sqrt(f32(i) / f32(taps)) * radius;
        let theta = f32(i) * 2.3999632;
        let at = clamp(uv + vec2<f32>(cos(theta), sin(theta)) * rho * aspect, vec2<f32>(0.0), vec2<f32>(1.0));
        color += bilinear(lit_opaque, at).rgb;
    }
    return color / f32(taps);
}
#endif

// The light reaching the eye through a transmissive surface at `world`
// (facing normal `n`, towards-eye `v`, pixel `frag`): the ray refracted
// into a slab `thickness` deep (Snell, index `ior`: NaN, zero or negative
// is 1; total internal reflection goes straight on), leaving parallel to
// where it came from, meeting the opaque scene (`exit_uv`), blurred in a
// disc that grows with `roughness` (`blurred`), and absorbed along the path
// inside (Beer-Lambert, coefficients `sigma`). Where the ray leaves the
// screen, the environment along it (ENVIRONMENT), faded in over EDGE_BAND;
// without one, the screen's edge. Finite for every input.
// `dispersion` (KHR_materials_dispersion, 20 / the Abbe number): red, green
// and blue refract by their own index, spread (ior - 1) x dispersion / 20
// about the green's (the extension's and Khronos' viewer's form); each
// channel is the whole walk at its index. A material without dispersion (0,
// the Transmission feature's default) takes the one walk it always did: a
// branch uniform over the material, so no permutation for it.
fn transmitted(world: vec3<f32>, n: vec3<f32>, v: vec3<f32>, ior_in: f32, thickness_in: f32, roughness: f32, sigma: vec3<f32>, frag: vec2<f32>, dispersion: f32) -> vec3<f32> {
    if (dispersion > 0.0 && dispersion < 1e6) {
        let ior = select(1.0, ior_in, ior_in > 0.0 && ior_in < 1e6);
        let half_spread = (ior - 1.0) * 0.025 * dispersion;
        let red = transmitted_at(world, n, v, ior - half_spread, thickness_in, roughness, sigma, frag).r;
        let green = transmitted_at(world, n, v, ior, thickness_in, roughness, sigma, frag).g;
        let blue = transmitted_at(world, n, v, ior + half_spread, thickness_in, roughness, sigma, frag).b;
        return vec3<f32>(red, green, blue);
    }
    return transmitted_at(world, n, v, ior_in, thickness_in, roughness, sigma, frag);
}

// [`transmitted`] at one index of refraction for every channel.
fn transmitted_at(world: vec3<f32>, n: vec3<f32>, v: vec3<f32>, ior_in: f32, thickness_in: f32, roughness: f32, sigma: vec3<f32>, frag: vec2<f32>) -> vec3<f32> {
    let own = clamp(frag / vec2<f32>(textureDimensions(opaque_depth)), vec2<f32>(0.0), vec2<f32>(1.0));
    let ior = select(1.0, ior_in, ior_in > 0.0 && ior_in < 1e6);
    let thickness = select(0.0, thickness_in, thickness_in > 0.0 && thickness_in < 1e6);
    let incident = -v;
    var r = refract(incident, n, 1.0 / ior);
    if (!(dot(r, r) > 1e-8)) {
        r = incident;
    }
    // Through a slab: thickness / cos(refracted angle), held finite at grazing.
    let path = thickness / max(dot(-n, r), 0.05);
    let uv = exit_uv(world + r * path, incident, u32(params.absorption.w), own);
    // The blur disc: none for smooth glass, none without a bend (ior 1).
    let radius = 0.1 * clamp(roughness, 0.0, 1.0) * clamp(2.0 * ior - 2.0, 0.0, 1.0);
    let on_screen = clamp(uv, vec2<f32>(0.0), vec2<f32>(1.0));
    var color = blurred(on_screen, radius);
#ifdef ENVIRONMENT
    // Off screen: the environment along the ray (it leaves the slab
    // parallel to where it came from), as blurred as Environment's
    // reflection is at this roughness.
    let fade = off_screen(uv);
    if (fade > 0.0) {
        let lod = clamp(roughness, 0.0, 1.0) * max(params.surface.w - 1.0, 0.0);
        let far = textureSampleLevel(prefiltered, cube_sampler, incident, lod).rgb;
        color = mix(color, max(sanitize(vec4<f32>(far, 0.0)).rgb, vec3<f32>(0.0)), fade);
    }
#endif
    let absorbed = exp(-clamp(sanitize(vec4<f32>(sigma, 0.0)).rgb, vec3<f32>(0.0), vec3<f32>(1e6)) * path);
    return clamp(sanitize(vec4<f32>(color * absorbed, 0.0)).rgb, vec3<f32>(0.0), vec3<f32>(HALF_MAX));
}
#endif
#ifdef NORMAL_MAP
@group(2) @binding(0) var normal_map: texture_2d<f32>;
@group(2) @binding(1) var normal_sampler: sampler;
#endif
#ifdef COLOR_MAP
@group(2) @binding(2) var color_map: texture_2d<f32>;
@group(2) @binding(3) var color_sampler: sampler;
#endif
#ifdef ENVIRONMENT
// The Environment node's maps, as Reflection reads them.
@group(0) @binding(26) var prefiltered: texture_cube<f32>;
@group(0) @binding(27) var irradiance: texture_cube<f32>;
@group(0) @binding(28) var lut: texture_2d<f32>;
@group(0) @binding(29) var cube_sampler: sampler;

// Image-based light on the surface (the base pass's): the irradiance times
// the diffuse albedo, and the prefiltered reflection times the split-sum
// factor, scaled by `reflective` (the material's Reflection strength).
fn environment_light(n: vec3<f32>, v: vec3<f32>, albedo: vec3<f32>, roughness: f32, metallic: f32, reflectance: f32, reflective: f32) -> vec3<f32> {
    let nf = facing_normal(n, v);
    let r = clamp(roughness, 0.0, 1.0);
    let m = clamp(metallic, 0.0, 1.0);
    let diffuse = textureSampleLevel(irradiance, cube_sampler, nf, 0.0).rgb * albedo * (1.0 - m);
    let f0 = mix(vec3<f32>(clamp(reflectance, 0.0, 1.0)), albedo, m);
    let factor = split_sum(lut, cube_sampler, f0, clamp(dot(nf, v), 1e-4, 1.0), r);
    let lod = r * max(params.surface.w - 1.0, 0.0);
    let specular = textureSampleLevel(prefiltered, cube_sampler, reflect(-v, nf), lod).rgb * factor;
    return max(diffuse, vec3<f32>(0.0)) + max(specular, vec3<f32>(0.0)) * max(reflective, 0.0);
}

#ifdef CLEARCOAT
// `base` (environment_light's) under a coat (`coat`: factor, roughness;
// its normal `n`, the face shown): what the coat reflects does not reach
// the base, nor leave it (1 - factor x F(N.V), as the light walk dims it),
// and the coat's own reflection of the environment (f0 0.04 at its
// roughness) adds, scaled by `reflective` as the base's specular is.
// Reflection does the same for opaque surfaces.
fn coated_environment(base: vec3<f32>, n: vec3<f32>, v: vec3<f32>, coat: vec2<f32>, reflective: f32) -> vec3<f32> {
    if (!(coat.x > 0.0)) {
        return base;
    }
    let nf = facing_normal(n, v);
    let n_dot_v = clamp(dot(nf, v), 1e-4, 1.0);
    let dim = 1.0 - coat.x * (DIELECTRIC_F0 + (1.0 - DIELECTRIC_F0) * schlick_weight(n_dot_v));
    let factor = split_sum(lut, cube_sampler, vec3<f32>(DIELECTRIC_F0), n_dot_v, coat.y);
    let lod = coat.y * max(params.surface.w - 1.0, 0.0);
    let lobe = textureSampleLevel(prefiltered, cube_sampler, reflect(-v, nf), lod).rgb * factor;
    return base * dim + max(lobe, vec3<f32>(0.0)) * coat.x * max(reflective, 0.0);
}
#endif
#endif

#ifdef MATCAP
#ifdef MATCAP_TEXTURE
@group(0) @binding(20) var matcap_images: texture_2d_array<f32>;
@group(0) @binding(21) var matcap_sampler: sampler;
#endif

// What `material`'s MatCap adds to a surface of world normal `n` (the face
// shown) at `world`: as CompositeLight's matcap_light, nothing without the
// feature or at strength 0.
fn matcap_light(material: u32, n: vec3<f32>, world: vec3<f32>, albedo: vec3<f32>) -> vec3<f32> {
    // x strength, y mode (1: add as light), z mapping (1: reflected).
    let settings = feature_param(material, FEATURE_MATCAP, 0u, vec4<f32>(0.0));
    if (!(settings.x > 0.0)) {
        return vec3<f32>(0.0);
    }
    let view_n = safe_normalize((camera.view * vec4<f32>(n, 0.0)).xyz, vec3<f32>(0.0, 0.0, 1.0));
    let v = safe_normalize((camera.view * vec4<f32>(world, 1.0)).xyz, vec3<f32>(0.0, 0.0, -1.0));
    let uv = matcap_uv(view_n, v, settings.z > 0.5);
    var image = default_matcap(uv);
#ifdef MATCAP_TEXTURE
    let texture = feature_texture(material, FEATURE_MATCAP);
    if (texture > 0u) {
        let layer = (texture - 1u) % max(textureNumLayers(matcap_images), 1u);
        image = textureSampleLevel(matcap_images, matcap_sampler, uv, layer, 0.0).rgb;
    }
#endif
    let tint = select(albedo, vec3<f32>(1.0), settings.y > 0.5);
    return max(image * tint * settings.x, vec3<f32>(0.0));
}
#endif

#ifdef FROXELS
// The forward grid (ClusterGrid::forward; lighting/clusters.wgsl's `Grid`:
// tiles x, tiles y, slices, light count; near, far, log(far / near), tile
// pixels), bound to the base pass that marks it and the light passes that
// walk its lists.
struct Grid {
    dims: vec4<u32>,
    depth: vec4<f32>,
}
@group(0) @binding(22) var<uniform> grid: Grid;

// The froxel of pixel `frag` at view depth `view_depth` (the view-space
// -z, as clusters.wgsl's `slice_of` takes it, not the distance to the eye).
// Depths before the first slice or past the last are clamped into them,
// which clusters.wgsl (OCCUPIED) makes unbounded.
fn froxel_of(frag: vec2<f32>, view_depth: f32) -> u32 {
    let tile = vec2<u32>(clamp(floor(frag / grid.depth.w), vec2<f32>(0.0), vec2<f32>(grid.dims.xy - 1u)));
    return (slice_of(view_depth) * grid.dims.y + tile.y) * grid.dims.x + tile.x;
}

// The slice of view depth `view_depth`, clamped into the grid.
fn slice_of(view_depth: f32) -> u32 {
    return u32(clamp(floor(log(max(view_depth, grid.depth.x) / grid.depth.x) / grid.depth.z * f32(grid.dims.z)), 0.0, f32(grid.dims.z - 1u)));
}
#endif

#ifdef FROXEL_MARKS
// A word per froxel of the forward grid, cleared each frame: the base pass
// marks the froxels its fragments lie in, and the light assignment lists
// lights only there (clusters.wgsl, OCCUPIED).
@group(0) @binding(31) var<storage, read_write> froxel_marks: array<atomic<u32>>;

// Marks the froxel a light pass will read for this fragment. The light
// pass is another permutation, compiled apart: the froxels of depths a
// hair either side are marked too, so a rounding difference at a slice
// boundary still finds a list (slices are 7.5% of their depth thick).
fn mark_froxels(frag: vec2<f32>, view_depth: f32) {
    let lo = froxel_of(frag, view_depth * (1.0 - 1e-4));
    let hi = froxel_of(frag, view_depth * (1.0 + 1e-4));
    atomicStore(&froxel_marks[lo], 1u);
    if (hi != lo) {
        atomicStore(&froxel_marks[hi], 1u);
    }
}
#endif

#ifdef FRAGMENT_RECORDS
// The fragment lists (compute.rs): a counter per pixel and then one more
// that counts the fragments no slot was left for, and `slots` records per
// pixel (the records buffer's length over the pixel count), RECORD_WORDS
// words each. A pixel's counter keeps counting past its slots, so the
// shading knows how many fragments it missed.
@group(0) @binding(40) var<storage, read_write> fragment_counts: array<atomic<u32>>;
@group(0) @binding(41) var<storage, read_write> fragment_records: array<u32>;
#ifdef CLEARCOAT
// Two words a slot, beside the fragment's record (compute.rs's coat buffer).
@group(0) @binding(44) var<storage, read_write> coat_records: array<u32>;
// What `record_fragment` stores in it: set by `fs` before the call.
var<private> record_coat: vec2<f32>;
var<private> record_coat_normal: vec3<f32>;
#endif
#ifdef SHEEN
// Two words a slot (compute.rs's sheen buffer): the sheen's colour and roughness.
@group(0) @binding(45) var<storage, read_write> sheen_records: array<u32>;
// What `record_fragment` stores in it (rgb colour, a roughness): set by `fs`.
var<private> record_sheen: vec4<f32>;
#endif
#ifdef ANISOTROPY
// Two words a slot (compute.rs's anisotropy buffer): the direction and strength.
@group(0) @binding(46) var<storage, read_write> anisotropy_records: array<u32>;
// What `record_fragment` stores in it (xyz the world direction, any
// length; w the strength): set by `fs`.
var<private> record_anisotropy: vec4<f32>;
#endif

// World position and albedo as f32 (6), the normal (1), reflectance as f32
// (1), roughness with metallic and alpha with coverage in 16 bits each (2).
// Half floats would need a capability naga does not grant by default.
const RECORD_WORDS: u32 = 10u;

// A unit vector on the octahedron, unfolded onto -1..1 squared (two
// 16-bit numbers keep it to about 5e-5 radians).
fn octahedral(n: vec3<f32>) -> vec2<f32> {
    let p = n.xy / max(abs(n.x) + abs(n.y) + abs(n.z), 1e-20);
    if (n.z < 0.0) {
        return (1.0 - abs(p.yx)) * select(vec2<f32>(-1.0), vec2<f32>(1.0), p >= vec2<f32>(0.0));
    }
    return p;
}

// Stores a kept fragment's lighting inputs in the next slot of its pixel
// (pixel `frag`), or counts it as missed when the pixel's slots are full.
// Every value is made finite and held in its packing's range first.
fn record_fragment(frag: vec2<f32>, world: vec3<f32>, n: vec3<f32>, albedo: vec3<f32>, roughness: f32, metallic: f32, reflectance: f32, alpha: f32, coverage: f32) {
    let size = textureDimensions(opaque_depth);
    let pixels = size.x * size.y;
    let pixel = min(u32(frag.y), size.y - 1u) * size.x + min(u32(frag.x), size.x - 1u);
    let slots = arrayLength(&fragment_records) / (RECORD_WORDS * max(pixels, 1u));
    let k = atomicAdd(&fragment_counts[pixel], 1u);
    if (k >= slots) {
        atomicAdd(&fragment_counts[pixels], 1u);
        return;
    }
    let at = RECORD_WORDS * (pixel * slots + k);
    let colour = clamp(sanitize(vec4<f32>(albedo, reflectance)), vec4<f32>(0.0), vec4<f32>(HALF_MAX));
    let unit = clamp(sanitize(vec4<f32>(roughness, metallic, alpha, coverage)), vec4<f32>(0.0), vec4<f32>(1.0));
    fragment_records[at] = bitcast<u32>(world.x);
    fragment_records[at + 1u] = bitcast<u32>(world.y);
    fragment_records[at + 2u] = bitcast<u32>(world.z);
    fragment_records[at + 3u] = pack2x16snorm(octahedral(n));
    fragment_records[at + 4u] = bitcast<u32>(colour.x);
    fragment_records[at + 5u] = bitcast<u32>(colour.y);
    fragment_records[at + 6u] = bitcast<u32>(colour.z);
    fragment_records[at + 7u] = bitcast<u32>(colour.w);
    fragment_records[at + 8u] = pack2x16unorm(unit.xy);
    fragment_records[at + 9u] = pack2x16unorm(unit.zw);
#ifdef CLEARCOAT
    // The coat's record: its normal (octahedral), then factor and roughness.
    let coat_at = 2u * (pixel * slots + k);
    coat_records[coat_at] = pack2x16snorm(octahedral(record_coat_normal));
    coat_records[coat_at + 1u] = pack2x16unorm(clamp(sanitize(vec4<f32>(record_coat, 0.0, 0.0)).xy, vec2<f32>(0.0), vec2<f32>(1.0)));
#endif
#ifdef SHEEN
    // The sheen's record: colour and roughness, 16 bits each (0..1, as the light pass clamps them).
    let sheen_at = 2u * (pixel * slots + k);
    let sheen = clamp(sanitize(record_sheen), vec4<f32>(0.0), vec4<f32>(1.0));
    sheen_records[sheen_at] = pack2x16unorm(sheen.xy);
    sheen_records[sheen_at + 1u] = pack2x16unorm(sheen.zw);
#endif
#ifdef ANISOTROPY
    // The anisotropy's record: the unit direction (octahedral), then the
    // strength; a direction too short to have one is strength 0 (what the
    // light function makes of it too).
    let aniso_at = 2u * (pixel * slots + k);
    let direction = sanitize(vec4<f32>(record_anisotropy.xyz, 0.0)).xyz;
    let has_direction = dot(direction, direction) > 1e-12;
    let strength = select(0.0, clamp(sanitize(record_anisotropy).w, 0.0, 1.0), has_direction);
    anisotropy_records[aniso_at] = pack2x16snorm(octahedral(safe_normalize(direction, vec3<f32>(1.0, 0.0, 0.0))));
    anisotropy_records[aniso_at + 1u] = pack2x16unorm(vec2<f32>(strength, 0.0));
#endif
}
#endif

#ifdef COMPUTE_SHADE
@group(0) @binding(40) var<storage, read> fragment_counts: array<u32>;
@group(0) @binding(41) var<storage, read> fragment_records: array<u32>;
#ifdef CLEARCOAT
@group(0) @binding(44) var<storage, read> coat_records: array<u32>;
#endif
#ifdef SHEEN
@group(0) @binding(45) var<storage, read> sheen_records: array<u32>;
#endif
#ifdef ANISOTROPY
@group(0) @binding(46) var<storage, read> anisotropy_records: array<u32>;
#endif
// As FRAGMENT_RECORDS writes them.
const RECORD_WORDS: u32 = 10u;
// Per pixel: the light the compute passes add to the accumulation's colour.
@group(0) @binding(42) var<storage, read_write> shaded_light: array<vec4<f32>>;
// The base passes' accumulation: its alpha is the weight of every fragment,
// recorded or missed.
@group(0) @binding(43) var shade_accumulation: texture_2d<f32>;

fn unoctahedral(e: vec2<f32>) -> vec3<f32> {
    var n = vec3<f32>(e, 1.0 - abs(e.x) - abs(e.y));
    let t = max(-n.z, 0.0);
    n = vec3<f32>(n.x + select(t, -t, n.x >= 0.0), n.y + select(t, -t, n.y >= 0.0), n.z);
    return safe_normalize(n, vec3<f32>(0.0, 0.0, 1.0));
}
#endif
#ifdef LIGHT_SUMS
@group(0) @binding(42) var<storage, read> shaded_light: array<vec4<f32>>;
#endif

#ifdef LIGHT_PASS
#ifdef CLUSTERED
// Named apart from the mesh's `indices` (bindings are found by name).
@group(0) @binding(23) var<storage, read> light_counts: array<u32>;
@group(0) @binding(24) var<storage, read> light_offsets: array<u32>;
@group(0) @binding(25) var<storage, read> light_indices: array<u32>;
#endif

// Every light of the buffer that reaches `pw`: with CLUSTERED, those listed
// in the froxel of the fragment (pixel `frag`, camera depth `view_depth`).
fn light_sums(frag: vec2<f32>, pw: vec3<f32>, s: BrdfSurface, view_depth: f32) -> LightSums {
    var sums = no_light_sums();
#ifdef CLUSTERED
    // The base pass marked this froxel (mark_froxels), so it has a list.
    let froxel = froxel_of(frag, view_depth);
    let first = light_offsets[froxel];
    // Never past the list's end (an overfull frame's lists are cut: clusters.rs).
    let end = min(first + light_counts[froxel], arrayLength(&light_indices));
    for (var k = first; k < end; k++) {
        add_forward_light(light_indices[k], pw, s, view_depth, &sums);
    }
#else
    let count = arrayLength(&lights);
    for (var i = 0u; i < count; i++) {
        add_forward_light(i, pw, s, view_depth, &sums);
    }
#endif
    return sums;
}
#endif

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) normal: vec3<f32>,
    @location(1) color: vec4<f32>,
    @location(2) distance: f32,
    @location(3) uv: vec2<f32>,
    @location(4) second_uv: vec2<f32>,
    @location(5) @interpolate(flat) material: u32,
    @location(6) world: vec3<f32>,
    // xyz world tangent, w handedness
    @location(7) tangent: vec4<f32>,
    // The object-space normal, whose largest axis picks TRIPLANAR's projection.
    @location(8) object_normal: vec3<f32>,
}

@vertex
fn vs(@builtin(vertex_index) vertex: u32, @builtin(instance_index) instance_index: u32) -> VertexOut {
    // A mirroring transform turns the winding around: corners taken in the
    // other order, so culling (one-sided glTF materials) culls back faces.
    let m = instances[instance_index].model;
    let mirrored = determinant(mat3x3<f32>(m[0].xyz, m[1].xyz, m[2].xyz)) < 0.0;
    let corner = select(vertex % 3u, (3u - vertex % 3u) % 3u, mirrored);
    let v = triangle_vertex(instance_index, vertex / 3u, corner, view_right(camera.view), view_up(camera.view));
    let world = instances[instance_index].model * vec4<f32>(v.position_u.xyz, 1.0);
    var out: VertexOut;
    out.clip = camera.view_projection * world;
    out.normal = (instances[instance_index].normal_matrix * vec4<f32>(v.normal_v.xyz, 0.0)).xyz;
    out.color = instances[instance_index].color;
    out.distance = -(camera.view * world).z;
    out.uv = vec2<f32>(v.position_u.w, v.normal_v.w);
    out.second_uv = out.uv;
    out.material = instances[instance_index].info.z;
    out.world = world.xyz;
    out.tangent = vec4<f32>((m * vec4<f32>(v.tangent.xyz, 0.0)).xyz, v.tangent.w);
    out.object_normal = v.normal_v.xyz;
#ifdef VERTEX_EXTRAS
    let extra = corner_extra(instance_index, vertex / 3u, corner, v);
    out.second_uv = extra.second_uv;
    // glTF: base colour = factor x texture x COLOR_0 (alpha too).
    out.color *= vertex_color(extra);
#endif
    return out;
}

struct Accumulated {
    @location(0) accumulation: vec4<f32>,
    @location(1) revealage: vec4<f32>,
}

fn weight(z: f32, alpha: f32) -> f32 {
    let d = max(z, 0.0);
    let w = 10.0 / (1e-5 + pow(d / 5.0, 2.0) + pow(min(d / 200.0, 1e5), 6.0));
    return alpha * clamp(w, 1e-2, 3e3) / 3e3;
}

// `n` bent by a tangent-space normal-map texel (-1..1) along `tangent`.
fn perturb(n: vec3<f32>, tangent: vec4<f32>, texel: vec3<f32>) -> vec3<f32> {
    let t = safe_normalize(tangent.xyz - n * dot(n, tangent.xyz), vec3<f32>(1.0, 0.0, 0.0));
    let b = cross(n, t) * select(-1.0, 1.0, tangent.w >= 0.0);
    return safe_normalize(t * texel.x + b * texel.y + n * texel.z, n);
}

@fragment
fn fs(in: VertexOut, @builtin(front_facing) front: bool) -> Accumulated {
    var base = in.color;
    var n = safe_normalize(in.normal, vec3<f32>(0.0, 1.0, 0.0));
    // What a clearcoat normal map bends (glTF: not the base normal map's normal).
    let geometric = n;
    // Textures first, in uniform control flow (implicit derivatives).
#ifdef TEXCOORDS
    let uv = in.uv;
#else
#ifdef TRIPLANAR
    // Planar projection on the axis the surface faces most, as the G-buffer resolve does.
    let face = abs(in.object_normal);
    var uv = fract(in.world.xy);
    if (face.x >= face.y && face.x >= face.z) {
        uv = fract(in.world.zy);
    } else if (face.y >= face.z) {
        uv = fract(in.world.xz);
    }
#else
    let uv = vec2<f32>(0.0);
#endif
#endif
#ifdef COLOR_MAP
    base = vec4<f32>(base.rgb * max(textureSample(color_map, color_sampler, uv).rgb, vec3<f32>(0.0)), base.a);
#endif
#ifdef NORMAL_MAP
    n = perturb(n, in.tangent, textureSample(normal_map, normal_sampler, uv).xyz * 2.0 - 1.0);
#endif
    var roughness = params.surface.x;
    var metallic = params.surface.y;
    var reflectance = 0.04;
    var emission = vec3<f32>(0.0);
    var occlusion = 1.0;
    // What scales the transmission's thickness (KHR_materials_volume's map).
    var thickness_scale = 1.0;
#ifdef MATERIALS
    let ct = feature_param(in.material, FEATURE_COOK_TORRANCE, 0u, vec4<f32>(roughness, metallic, reflectance, 0.0));
    roughness = ct.x;
    metallic = ct.y;
    reflectance = ct.z;
    let em = feature_param(in.material, FEATURE_EMISSION, 0u, vec4<f32>(0.0));
    emission = max(em.rgb, vec3<f32>(0.0)) * max(em.a, 0.0);
#endif
#ifdef MATERIAL_MAPS
    var coords: MapCoords;
    coords.uv = in.uv;
    coords.dx = dpdx(in.uv);
    coords.dy = dpdy(in.uv);
    coords.second_uv = in.second_uv;
    coords.second_dx = dpdx(in.second_uv);
    coords.second_dy = dpdy(in.second_uv);
    base *= max(sample_map(in.material, MAP_BASE_COLOR, coords, vec4<f32>(1.0)), vec4<f32>(0.0));
    let settings = map_settings(in.material);
    if (has_map(in.material, MAP_NORMAL)) {
        var texel = sample_map(in.material, MAP_NORMAL, coords, vec4<f32>(0.5, 0.5, 1.0, 1.0)).xyz * 2.0 - 1.0;
        texel = vec3<f32>(texel.xy * settings.z, texel.z);
        n = perturb(n, in.tangent, texel);
    }
    let metal_rough = sample_map(in.material, MAP_METALLIC_ROUGHNESS, coords, vec4<f32>(1.0));
    roughness *= metal_rough.g;
    metallic *= metal_rough.b;
    occlusion = clamp(1.0 + settings.w * (sample_map(in.material, MAP_OCCLUSION, coords, vec4<f32>(1.0)).r - 1.0), 0.0, 1.0);
    emission *= max(sample_map(in.material, MAP_EMISSIVE, coords, vec4<f32>(1.0)).rgb, vec3<f32>(0.0));
#ifdef EXTENSION_MAPS
    reflectance = mapped_reflectance(in.material, coords, reflectance);
    thickness_scale = max(sample_map(in.material, MAP_THICKNESS, coords, vec4<f32>(1.0)).g, 0.0);
#endif
#endif
#ifdef ANISOTROPY
    // The anisotropy direction in the geometric normal's tangent frame,
    // turned by the rotation and the map, as the G-buffer resolve makes it
    // (world space here); the light function makes it orthogonal to the
    // shaded normal, and draws a fragment with none isotropic.
    var aniso_direction = vec3<f32>(0.0);
    var aniso_strength = 0.0;
#ifdef MATERIAL_MAPS
    if (has_feature(in.material, FEATURE_ANISOTROPY)) {
        let a = mapped_anisotropy(in.material, coords, feature_param(in.material, FEATURE_ANISOTROPY, 0u, vec4<f32>(0.0)).xy);
        let t = safe_normalize(in.tangent.xyz, vec3<f32>(1.0, 0.0, 0.0));
        let bt = cross(geometric, t) * select(-1.0, 1.0, in.tangent.w >= 0.0);
        aniso_direction = t * a.x + bt * a.y;
        aniso_strength = a.z;
    }
#endif
#endif
#ifdef CLEARCOAT
    // The coat's (factor, roughness) and its normal, before facing: its
    // normal map's on the geometric normal, else the surface's (normal
    // mapped) one, as CookTorrance shares it on opaque surfaces.
    var coat = vec2<f32>(0.0);
    var coat_n = n;
#ifdef MATERIALS
    let coat_params = feature_param(in.material, FEATURE_CLEARCOAT, 0u, vec4<f32>(0.0)).xy;
    coat = clamp(sanitize(vec4<f32>(coat_params, 0.0, 0.0)).xy, vec2<f32>(0.0), vec2<f32>(1.0));
#ifdef EXTENSION_MAPS
    coat = mapped_clearcoat(in.material, coords, coat);
    if (has_map(in.material, MAP_CLEARCOAT_NORMAL)) {
        coat_n = perturb(geometric, in.tangent, clearcoat_normal_texel(in.material, coords));
    }
#endif
#endif
#endif
    // Behind the opaque surface (reversed-Z: a smaller depth is further): hidden.
    let opaque_z = textureLoad(opaque_depth, vec2<i32>(in.clip.xy), 0).r;
    let alpha = clamp(sanitize(base).a, 0.0, 1.0);
    // What shows through is refracted in this share (transmission: the
    // fragment covers it with what it refracts); coverage is what the
    // weight and the revealage see, alpha what the surface's own diffuse
    // colour is scaled by. Without transmission the two are one.
    let transmission = transmission_of(in.material);
    let share = transmission.x * (1.0 - alpha);
    let coverage = alpha + share;
    if (in.clip.z < opaque_z || coverage < 1e-4) {
        discard;
    }
    let albedo = max(sanitize(base).rgb, vec3<f32>(0.0));
    let w = weight(in.distance, coverage);
    var out: Accumulated;
#ifdef SHEEN
    // The sheen's colour (black: none) and roughness, the light pass's and
    // the record's (the compute entry points, which share this module, have
    // no material world: none).
    var sheen = vec4<f32>(0.0);
#ifdef MATERIALS
    sheen = clamp(sanitize(feature_param(in.material, FEATURE_SHEEN, 0u, vec4<f32>(0.0))), vec4<f32>(0.0), vec4<f32>(1.0));
#ifdef EXTENSION_MAPS
    sheen = mapped_sheen(in.material, coords, sheen);
#endif
#endif
#endif
#ifdef LIGHT_PASS
    // A back face (a shell's inside, seen through its front) is lit on the side it shows.
    let facing = select(-n, n, front);
    let v = safe_normalize(camera.position.xyz - in.world, facing);
    let s = brdf_surface(facing, v, albedo, roughness, metallic, reflectance);
#ifdef ANISOTROPY
    aniso = anisotropic_surface(s, aniso_direction, aniso_strength);
#endif
#ifdef CLEARCOAT
    coat_factor = coat.x;
    coat_surface = brdf_surface(select(-coat_n, coat_n, front), v, vec3<f32>(0.0), coat.y, 0.0, DIELECTRIC_F0);
    coat_sum = vec3<f32>(0.0);
#endif
#ifdef SHEEN
    sheen_color = sheen.rgb;
    sheen_roughness = sheen.a;
    sheen_sum = vec3<f32>(0.0);
#endif
#ifdef SHEEN
    // The fragment's film (its maps' factor and thickness with
    // EXTENSION_MAPS), its Fresnel made once for all its lights.
#ifdef EXTENSION_MAPS
    let film_params = feature_param(in.material, FEATURE_IRIDESCENCE, 0u, vec4<f32>(0.0));
    let film = film_of(in.material, mapped_film(in.material, coords, film_params.x));
#else
    let film = iridescence_at(in.material, vec2<u32>(0u));
#endif
    film_factor = film.x;
    film_fresnel = vec3<f32>(0.0);
    film_lit = vec3<f32>(0.0);
    if (film_factor > 0.0) {
        film_fresnel = iridescence_fresnel(reflectance, albedo, metallic, s.n_dot_v, film.y, film.z);
    }
#endif
    let sums = light_sums(in.clip.xy, in.world, s, in.distance);
    var lit = light_sums_brdf(s, sums);
#ifdef SHEEN
    lit = filmed_light(s, sums, lit);
#endif
    var specular = lit.specular;
    var lit_diffuse = lit.diffuse;
    if (params.surface.z > 0.5) {
        specular *= surface_energy_compensation(s);
    }
#ifdef SHEEN
    let sheened = sheened_specular(s, specular);
    specular = sheened.xyz;
    lit_diffuse *= sheened.w;
#endif
#ifdef CLEARCOAT
    let over = coated_specular(specular);
    specular = over.xyz;
    lit_diffuse *= over.w;
#endif
    // Held at 600 before sanitizing: a light that overflows to infinity
    // saturates the pixel instead of blacking it out; NaN becomes 0.
    let diffuse = max(sanitize(vec4<f32>(min(lit_diffuse, vec3<f32>(600.0)), 0.0)).rgb, vec3<f32>(0.0));
    let glossy = max(sanitize(vec4<f32>(min(specular, vec3<f32>(600.0)), 0.0)).rgb, vec3<f32>(0.0));
    // The colour alone: alpha and the revealage are the base pass's (the
    // pipeline masks them). Transmission takes the diffuse's place in what
    // it covers (glTF's model), the specular reflects off all of it.
    out.accumulation = vec4<f32>((diffuse * alpha + glossy * coverage) * w, 0.0);
    out.revealage = vec4<f32>(0.0);
#else
    // Two-sided: a thin glass-like shell is lit from either side.
    let lambert = abs(dot(n, params.light_direction.xyz));
    let radiance = params.ambient.rgb * occlusion + params.light_color.rgb * lambert;
    // The diffuse, scaled by alpha; the rest (emission, reflections, the
    // refracted light) by coverage.
    let diffuse = albedo * radiance;
    var unlit = emission;
#ifdef ENVIRONMENT
    // Layers without a material world reflect fully; with one, as much as
    // their material's Reflection feature says (none without it), as
    // Reflection does for the opaque surfaces.
    var reflective = 1.0;
#ifdef MATERIALS
    reflective = feature_param(in.material, FEATURE_REFLECTION, 0u, vec4<f32>(0.0)).x;
#endif
    let facing = select(-n, n, front);
    let v = safe_normalize(camera.position.xyz - in.world, facing);
    var environment = environment_light(facing, v, albedo, roughness, metallic, reflectance, reflective);
#ifdef CLEARCOAT
    environment = coated_environment(environment, select(-coat_n, coat_n, front), v, coat, reflective);
#endif
    unlit += environment * occlusion;
#endif
#ifdef MATCAP
    unlit += matcap_light(in.material, select(-n, n, front), in.world, albedo);
#endif
#ifdef FROXEL_MARKS
    mark_froxels(in.clip.xy, in.distance);
#endif
#ifdef FRAGMENT_RECORDS
#ifdef CLEARCOAT
    record_coat = coat;
    record_coat_normal = select(-coat_n, coat_n, front);
#endif
#ifdef SHEEN
    record_sheen = sheen;
#endif
#ifdef ANISOTROPY
    record_anisotropy = vec4<f32>(aniso_direction, aniso_strength);
#endif
    record_fragment(in.clip.xy, in.world, select(-n, n, front), albedo, roughness, metallic, reflectance, alpha, coverage);
#endif
    var through = vec3<f32>(0.0);
#ifdef TRANSMISSION
    if (share > 0.0) {
        // rgb: the absorption coefficients; w: the dispersion (layers
        // without a Transmission material: none).
        var absorption = vec4<f32>(params.absorption.rgb, 0.0);
#ifdef MATERIALS
        absorption = feature_param(in.material, FEATURE_TRANSMISSION, 1u, absorption);
#endif
        let sigma = absorption.rgb;
        let n_t = select(-n, n, front);
        let v_t = safe_normalize(camera.position.xyz - in.world, n_t);
        // Tinted by the base colour (glTF: the transmitted light is).
        through = albedo * transmitted(in.world, n_t, v_t, transmission.y, transmission.z * thickness_scale, roughness, sigma, in.clip.xy, absorption.w);
    }
#endif
    let surface = max(sanitize(vec4<f32>(min(diffuse, vec3<f32>(600.0)), 0.0)).rgb, vec3<f32>(0.0));
    let color = max(sanitize(vec4<f32>(min(unlit, vec3<f32>(600.0)), 0.0)).rgb, vec3<f32>(0.0));
    let refracted = min(through, vec3<f32>(600.0));
    out.accumulation = vec4<f32>(surface * alpha + color * coverage + refracted * share, coverage) * w;
    out.revealage = vec4<f32>(coverage);
#endif
    return out;
}

#ifdef COMPUTE_SHADE
// A recorded fragment, unpacked (FRAGMENT_RECORDS' `record_fragment`).
struct Recorded {
    world: vec3<f32>,
    view_depth: f32,
    surface: BrdfSurface,
    alpha: f32,
    coverage: f32,
#ifdef CLEARCOAT
    coat: f32,
    coat_lobe: BrdfSurface,
#endif
#ifdef SHEEN
    // rgb the colour, a the roughness.
    sheen: vec4<f32>,
#endif
#ifdef ANISOTROPY
    // xyz the unit direction (world), w the strength.
    anisotropy: vec4<f32>,
#endif
}

fn recorded(at: u32) -> Recorded {
    let world = bitcast<vec3<f32>>(vec3<u32>(fragment_records[at], fragment_records[at + 1u], fragment_records[at + 2u]));
    let n = unoctahedral(unpack2x16snorm(fragment_records[at + 3u]));
    let colour = bitcast<vec4<f32>>(vec4<u32>(fragment_records[at + 4u], fragment_records[at + 5u], fragment_records[at + 6u], fragment_records[at + 7u]));
    let rough_metal = unpack2x16unorm(fragment_records[at + 8u]);
    // x alpha, y coverage
    let cover = unpack2x16unorm(fragment_records[at + 9u]);
    let v = safe_normalize(camera.position.xyz - world, n);
    var f: Recorded;
    f.world = world;
    f.view_depth = -(camera.view * vec4<f32>(world, 1.0)).z;
    f.surface = brdf_surface(n, v, colour.rgb, rough_metal.x, rough_metal.y, colour.w);
    f.alpha = cover.x;
    f.coverage = cover.y;
#ifdef CLEARCOAT
    let coat_at = 2u * (at / RECORD_WORDS);
    let coat = unpack2x16unorm(coat_records[coat_at + 1u]);
    f.coat = coat.x;
    f.coat_lobe = brdf_surface(unoctahedral(unpack2x16snorm(coat_records[coat_at])), v, vec3<f32>(0.0), coat.y, 0.0, DIELECTRIC_F0);
#endif
#ifdef SHEEN
    let sheen_at = 2u * (at / RECORD_WORDS);
    f.sheen = vec4<f32>(unpack2x16unorm(sheen_records[sheen_at]), unpack2x16unorm(sheen_records[sheen_at + 1u]));
#endif
#ifdef ANISOTROPY
    let aniso_at = 2u * (at / RECORD_WORDS);
    f.anisotropy = vec4<f32>(unoctahedral(unpack2x16snorm(anisotropy_records[aniso_at])), unpack2x16unorm(anisotropy_records[aniso_at + 1u]).x);
#endif
    return f;
}

#ifdef CLEARCOAT
// Sets the private coat state to fragment `f`'s, with `sum` its coat's
// light so far.
fn begin_coat(f: Recorded, sum: vec3<f32>) {
    coat_factor = f.coat;
    coat_surface = f.coat_lobe;
    coat_sum = sum;
}
#endif

#ifdef SHEEN
// Sets the private sheen state to fragment `f`'s, with `sum` its sheen's
// light so far.
fn begin_sheen(f: Recorded, sum: vec3<f32>) {
    sheen_color = f.sheen.rgb;
    sheen_roughness = f.sheen.a;
    sheen_sum = sum;
}
#endif

#ifdef ANISOTROPY
// Sets the private anisotropic lobe to fragment `f`'s (strength 0: the
// isotropic lobe), as the forward light pass sets it from the same inputs.
fn begin_anisotropy(f: Recorded) {
    aniso = anisotropic_surface(f.surface, f.anisotropy.xyz, f.anisotropy.w);
}
#endif

// What fragment `f` lit by `sums` adds to the accumulation's colour: the
// forward light pass's output for it.
// With CLEARCOAT and SHEEN, the private coat and sheen states are the
// fragment's, summed over the same lights (begin_coat, begin_sheen, then
// the walk).
fn recorded_light(f: Recorded, sums: LightSums) -> vec3<f32> {
    let lit = light_sums_brdf(f.surface, sums);
    var specular = lit.specular;
    var lit_diffuse = lit.diffuse;
    if (params.surface.z > 0.5) {
        specular *= surface_energy_compensation(f.surface);
    }
#ifdef SHEEN
    let sheened = sheened_specular(f.surface, specular);
    specular = sheened.xyz;
    lit_diffuse *= sheened.w;
#endif
#ifdef CLEARCOAT
    let over = coated_specular(specular);
    specular = over.xyz;
    lit_diffuse *= over.w;
#endif
    let diffuse = max(sanitize(vec4<f32>(min(lit_diffuse, vec3<f32>(600.0)), 0.0)).rgb, vec3<f32>(0.0));
    let glossy = max(sanitize(vec4<f32>(min(specular, vec3<f32>(600.0)), 0.0)).rgb, vec3<f32>(0.0));
    return (diffuse * f.alpha + glossy * f.coverage) * weight(f.view_depth, f.coverage);
}

// Adds `sum`, the light of a pixel's `kept` recorded fragments of `count`
// (`kept_weight`: their share of the accumulation's alpha), to the pixel's
// light sum. Fragments past the pixel's slots were not recorded: their
// weight is in the accumulation's alpha, and they are lit as the recorded
// ones are on average per weight (the sum scaled by all the weight over the
// recorded weight), so an overfull pixel is approximate, never dark or NaN.
fn add_shaded(id: vec2<u32>, pixel: u32, count: u32, kept: u32, sum_in: vec3<f32>, kept_weight: f32) {
    var sum = sum_in;
    if (count > kept) {
        let all_weight = sanitize(textureLoad(shade_accumulation, vec2<i32>(id), 0)).a;
        if (kept_weight > 0.0 && all_weight > kept_weight) {
            sum *= min(all_weight / kept_weight, HALF_MAX);
        }
    }
    let before = shaded_light[pixel].rgb;
    shaded_light[pixel] = vec4<f32>(min(before + sanitize(vec4<f32>(sum, 0.0)).rgb, vec3<f32>(HALF_MAX)), 0.0);
}

// One light buffer's light on every fragment recorded at a pixel, added to
// the pixel's light sum: per fragment exactly what the forward light pass
// adds to the accumulation's colour (the same walk from the same froxel:
// `frag` is the pixel's centre, as a fragment's position is), but summed
// in f32.
@compute @workgroup_size(8, 8)
fn shade(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(shade_accumulation);
    if (id.x >= size.x || id.y >= size.y) {
        return;
    }
    let pixels = size.x * size.y;
    let pixel = id.y * size.x + id.x;
    let count = fragment_counts[pixel];
    if (count == 0u) {
        return;
    }
    let slots = arrayLength(&fragment_records) / (RECORD_WORDS * pixels);
    let kept = min(count, slots);
    let frag = vec2<f32>(id.xy) + 0.5;
    var sum = vec3<f32>(0.0);
    var kept_weight = 0.0;
    for (var k = 0u; k < kept; k++) {
        let f = recorded(RECORD_WORDS * (pixel * slots + k));
#ifdef CLEARCOAT
        begin_coat(f, vec3<f32>(0.0));
#endif
#ifdef SHEEN
        begin_sheen(f, vec3<f32>(0.0));
#endif
#ifdef ANISOTROPY
        begin_anisotropy(f);
#endif
        sum += recorded_light(f, light_sums(frag, f.world, f.surface, f.view_depth));
        // What the base pass added to the accumulation's alpha for it.
        kept_weight += f.coverage * weight(f.view_depth, f.coverage);
    }
    add_shaded(id.xy, pixel, count, kept, sum, kept_weight);
}

#ifdef SHADE_TILED
// Shading with the lights shared by each 8x8 tile, as CookTorrance's
// clustered walk shares a block's: the tile's pixels lie in one 32-pixel
// tile of the forward grid (ClusterGrid::FORWARD_TILE is a multiple of 8),
// so its froxels differ only in the slice. The tile marks the slices its
// recorded fragments lie in; then for each marked slice, batch by batch,
// the 64 lanes load that froxel's next 64 lights into workgroup memory,
// and each lane adds them to those of its fragments that lie in the slice.
// Each fragment gets exactly its froxel's list, in its order: the sums are
// `shade`'s.
const SLICE_WORDS: u32 = 4u;
// SLOTS (compute.rs): per-lane sums for at most this many fragments.
const MAX_SLOTS: u32 = 8u;
const BATCH: u32 = 64u;
var<workgroup> tile_slices: array<atomic<u32>, SLICE_WORDS>;
var<workgroup> slice_words: array<u32, SLICE_WORDS>;
var<workgroup> batch_lights: array<Light, BATCH>;
var<workgroup> batch_index: array<u32, BATCH>;

@compute @workgroup_size(8, 8)
fn shade_tiled(@builtin(global_invocation_id) id: vec3<u32>, @builtin(local_invocation_index) lane: u32, @builtin(workgroup_id) group: vec3<u32>) {
    let size = textureDimensions(shade_accumulation);
    // Lanes past the image's edge take part in the barriers with nothing recorded.
    let inside = id.x < size.x && id.y < size.y;
    let pixels = size.x * size.y;
    let pixel = select(0u, id.y * size.x + id.x, inside);
    let count = select(0u, fragment_counts[pixel], inside);
    let slots = arrayLength(&fragment_records) / (RECORD_WORDS * pixels);
    let kept = min(min(count, slots), MAX_SLOTS);
    let first_at = RECORD_WORDS * pixel * slots;
    if (lane < SLICE_WORDS) {
        atomicStore(&tile_slices[lane], 0u);
    }
    workgroupBarrier();
    var sums: array<LightSums, MAX_SLOTS>;
#ifdef CLEARCOAT
    // Each fragment's coat light, as `sums`.
    var coat_sums: array<vec3<f32>, MAX_SLOTS>;
#endif
#ifdef SHEEN
    // Each fragment's sheen light, as `sums`.
    var sheen_sums: array<vec3<f32>, MAX_SLOTS>;
#endif
    for (var k = 0u; k < kept; k++) {
        let s = slice_of(recorded(first_at + RECORD_WORDS * k).view_depth);
        atomicOr(&tile_slices[s / 32u], 1u << (s % 32u));
        sums[k] = no_light_sums();
    }
    workgroupBarrier();
    if (lane < SLICE_WORDS) {
        slice_words[lane] = atomicLoad(&tile_slices[lane]);
    }
    // The tile's column and row of the forward grid: every lane's.
    let corner = vec2<f32>(group.xy * 8u) + 0.5;
    let tile = vec2<u32>(clamp(floor(corner / grid.depth.w), vec2<f32>(0.0), vec2<f32>(grid.dims.xy - 1u)));
    // Loaded whole, once: uniform across the tile (the loops below hold barriers).
    let words = workgroupUniformLoad(&slice_words);
    for (var word = 0u; word < SLICE_WORDS; word++) {
        var bits = words[word];
        while (bits != 0u) {
            let slice = word * 32u + firstTrailingBit(bits);
            bits &= bits - 1u;
            let froxel = (slice * grid.dims.y + tile.y) * grid.dims.x + tile.x;
            let first = light_offsets[froxel];
            // Never past the list's end (an overfull frame's lists are cut: clusters.rs).
            let end = min(first + light_counts[froxel], arrayLength(&light_indices));
            for (var start = first; start < end; start += BATCH) {
                let n = min(BATCH, end - start);
                if (lane < n) {
                    let i = light_indices[start + lane];
                    batch_index[lane] = i;
                    batch_lights[lane] = lights[i];
                }
                workgroupBarrier();
                for (var k = 0u; k < kept; k++) {
                    let f = recorded(first_at + RECORD_WORDS * k);
                    if (slice_of(f.view_depth) == slice) {
                        // A whole local, not a pointer into the array: naga's SPIR-V
                        // output fails on a dynamically indexed element passed by pointer.
                        var acc = sums[k];
#ifdef CLEARCOAT
                        begin_coat(f, coat_sums[k]);
#endif
#ifdef SHEEN
                        begin_sheen(f, sheen_sums[k]);
#endif
#ifdef ANISOTROPY
                        begin_anisotropy(f);
#endif
                        for (var j = 0u; j < n; j++) {
                            add_light_record(batch_lights[j], batch_index[j], f.world, f.surface, f.view_depth, &acc);
                        }
                        sums[k] = acc;
#ifdef CLEARCOAT
                        coat_sums[k] = coat_sum;
#endif
#ifdef SHEEN
                        sheen_sums[k] = sheen_sum;
#endif
                    }
                }
                workgroupBarrier();
            }
        }
    }
    if (!inside || count == 0u) {
        return;
    }
    var sum = vec3<f32>(0.0);
    var kept_weight = 0.0;
    for (var k = 0u; k < kept; k++) {
        let f = recorded(first_at + RECORD_WORDS * k);
#ifdef CLEARCOAT
        begin_coat(f, coat_sums[k]);
#endif
#ifdef SHEEN
        begin_sheen(f, sheen_sums[k]);
#endif
        sum += recorded_light(f, sums[k]);
        kept_weight += f.coverage * weight(f.view_depth, f.coverage);
    }
    add_shaded(id.xy, pixel, count, kept, sum, kept_weight);
}
#endif
#endif

@compute @workgroup_size(8, 8)
fn resolve(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(output);
    if (id.x >= size.x || id.y >= size.y) {
        return;
    }
    let p = vec2<i32>(id.xy);
    let base = sanitize(textureLoad(opaque, p, 0));
    var accumulated = textureLoad(accumulation, p, 0);
#ifdef LIGHT_SUMS
    // The lights shaded in compute (finite, held at HALF_MAX by `shade`).
    accumulated = vec4<f32>(accumulated.rgb + shaded_light[id.y * size.x + id.x].rgb, accumulated.a);
#endif
    // An overflowed sum reads as infinity: held at the top of the range, never NaN.
    let sum = sanitize(min(accumulated, vec4<f32>(HALF_MAX)));
    let r = clamp(sanitize(textureLoad(revealage, p, 0)).r, 0.0, 1.0);
    if (r >= 1.0 || sum.a <= 0.0) {
        textureStore(output, id.xy, base);
        return;
    }
    let average = sum.rgb / clamp(sum.a, 1e-7, HALF_MAX);
    let color = base.rgb * r + average * (1.0 - r);
    textureStore(output, id.xy, vec4<f32>(clamp(color, vec3<f32>(0.0), vec3<f32>(HALF_MAX)), base.a));
}

// The targets' starting values (nothing accumulated, everything revealed),
// written in compute before the accumulation loads them: a render pass's
// clear costs raster output bandwidth.
@compute @workgroup_size(8, 8)
fn clear(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(clear_accumulation);
    if (id.x >= size.x || id.y >= size.y) {
        return;
    }
    textureStore(clear_accumulation, id.xy, vec4<f32>(0.0));
    textureStore(clear_revealage, id.xy, vec4<f32>(1.0));
}

// Rough refraction's mip chain (REFRACTION_MIPS reads it; refraction_mips.rs
// builds it only in frames where a layer refracts): level 0 the opaque image
// in half float (NaN as 0, held in range), each further level the box average
// of the texels under it, a dispatch a level in one compute pass.
@group(0) @binding(34) var mips_image: texture_2d<f32>;
@group(0) @binding(35) var mips_source: texture_2d<f32>;
@group(0) @binding(36) var mips_out: texture_storage_2d<rgba16float, write>;
// The level after mips_out's (refraction_mips_first).
@group(0) @binding(37) var mips_out_next: texture_storage_2d<rgba16float, write>;

// Along one axis: the first and last texel of the level above (`src` wide)
// under texel `k` of a level `out` wide: its two, and at the last texel the
// rest of an odd level (so every texel above counts somewhere).
fn mip_footprint(k: u32, out: u32, src: u32) -> vec2<u32> {
    let lo = min(k * 2u, src - 1u);
    var hi = min(lo + 1u, src - 1u);
    if (k + 1u == out) {
        hi = src - 1u;
    }
    return vec2<u32>(lo, hi);
}

fn mip_texel(c: vec4<f32>) -> vec4<f32> {
    return clamp(sanitize(c), vec4<f32>(0.0), vec4<f32>(HALF_MAX));
}

// A 1x1 image: level 0 alone.
@compute @workgroup_size(8, 8)
fn refraction_mips_copy(@builtin(global_invocation_id) id: vec3<u32>) {
    if (any(id.xy >= textureDimensions(mips_out))) {
        return;
    }
    textureStore(mips_out, id.xy, mip_texel(textureLoad(mips_image, id.xy, 0)));
}

// Levels 0 and 1: a thread per level-1 texel copies the image's texels under
// it into level 0 (the footprints tile it, so each is written once) and
// stores their average.
@compute @workgroup_size(8, 8)
fn refraction_mips_first(@builtin(global_invocation_id) id: vec3<u32>) {
    let out_size = textureDimensions(mips_out_next);
    if (any(id.xy >= out_size)) {
        return;
    }
    let src = textureDimensions(mips_image);
    let fx = mip_footprint(id.x, out_size.x, src.x);
    let fy = mip_footprint(id.y, out_size.y, src.y);
    var sum = vec4<f32>(0.0);
    for (var y = fy.x; y <= fy.y; y++) {
        for (var x = fx.x; x <= fx.y; x++) {
            let c = mip_texel(textureLoad(mips_image, vec2<u32>(x, y), 0));
            textureStore(mips_out, vec2<u32>(x, y), c);
            sum += c;
        }
    }
    let count = f32((fx.y - fx.x + 1u) * (fy.y - fy.x + 1u));
    textureStore(mips_out_next, id.xy, sum / count);
}

// One level from the one above it.
@compute @workgroup_size(8, 8)
fn refraction_mips_down(@builtin(global_invocation_id) id: vec3<u32>) {
    let out_size = textureDimensions(mips_out);
    if (any(id.xy >= out_size)) {
        return;
    }
    let src = textureDimensions(mips_source);
    let fx = mip_footprint(id.x, out_size.x, src.x);
    let fy = mip_footprint(id.y, out_size.y, src.y);
    var sum = vec4<f32>(0.0);
    for (var y = fy.x; y <= fy.y; y++) {
        for (var x = fx.x; x <= fx.y; x++) {
            sum += textureLoad(mips_source, vec2<u32>(x, y), 0);
        }
    }
    let count = f32((fx.y - fx.x + 1u) * (fy.y - fy.x + 1u));
    textureStore(mips_out, id.xy, sum / count);
}
