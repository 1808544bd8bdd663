// Reflection: image-based light from a prefiltered environment over the
// G-buffer (crates/render/src/environment/reflection.rs), in `main` and
// `diffuse`, or `both` in one pass when a frame reads both outputs:
// `main`, for each pixel whose material has the Reflection feature:
//   specular = prefiltered(R, roughness) * (F0 A + B)   (split-sum)
// `diffuse`, for every pixel with geometry (diffuse light does not depend
// on a material reflecting):
//   diffuse  = irradiance(N)                            (E / pi, albedo NOT applied)
// with roughness, metallic and reflectance from the material's
// CookTorrance feature and F0 = mix(reflectance, albedo, metallic).
// mode 1 (refraction): specular is the environment seen through the
// surface along the refracted direction (IOR ior, air outside) times
// 1 - (F0 A + B), what Fresnel lets through; total internal reflection
// falls back to the reflected direction. Empty depth, materials without
// the feature: zero. Clamped below half-float overflow.
// PARALLAX (an EnvironmentProbe with an influence volume): the specular
// ray from the shaded point is intersected with the volume (a box or a
// sphere) and the cube read towards that hit from the probe's position
// (Lagarde & Zanuttini 2012); outside the volume, or for a ray that does
// not leave it, the direction stays as it is.
// CLEARCOAT (some material of the world has a Clearcoat): a coated pixel's
// specular adds the coat's own reflection of the environment, along the
// coat's normal (its map's, where the G-buffer resolved one) at the coat's
// roughness with f0 0.04, times the coat's factor, and dims the base's by
// 1 - factor x F(N.V), as CookTorrance's light walk does for each light
// (Khronos' sample viewer's clear coat IBL). Reflect mode only: refraction
// shows what the surface lets through, base and coat alike. The diffuse
// output (irradiance, for every surface) is dimmed by the same
// 1 - factor x F(N.V), as the light walk dims the base's diffuse: what the
// coat reflects never reaches the base.
// ANISOTROPY (the G-buffer has an anisotropy target: some material has
// KHR_materials_anisotropy): for such a material's pixels the environment is
// read along the reflection about the bent normal of the extension and the
// Khronos sample viewer (lib/anisotropy.wgsl's anisotropic_bent_normal,
// bent more the stronger the anisotropy and the smoother the surface), at
// the material's roughness; the split sum keeps the pixel's own N.V.
// IRIDESCENCE (some material has the Iridescence feature): a film's
// Fresnel at N.V (lib/iridescence.wgsl) replaces the split sum's Schlick
// term, mixed by its factor: (1 - k) (F0 A + B) + k F_film (A + B), the
// Khronos sample viewer's image-based iridescence.
// SHEEN (some material has the Sheen feature, glTF's KHR_materials_sheen):
// for a sheen material, the specular is dimmed by the sheen's albedo
// scaling, 1 - max(colour) E(N.V) (lib/sheen.wgsl), and the sheen's own
// image-based light is added as colour x E(N.V) x irradiance(N): the lobe's
// albedo times the environment's cosine-weighted mean radiance about the
// normal, in place of a cube prefiltered with the Charlie lobe (exact for a
// uniform environment; a sharp environment's sheen comes out as soft as
// its diffuse light). The diffuse output is dimmed by the same scaling.
#import spreadlight::camera::{Camera, pixel_to_ndc}
#import spreadlight::packing::{channel_to_id, safe_normalize}
#import spreadlight::ibl::{split_sum, facing_normal}
#import spreadlight::material::{feature_param_at, has_feature, FEATURE_COOK_TORRANCE, FEATURE_REFLECTION}
#ifdef CLEARCOAT
#import spreadlight::material::{clearcoat_at, clearcoat_normal_at}
#import spreadlight::brdf::{schlick_weight, DIELECTRIC_F0}
#endif
#ifdef ANISOTROPY
#import spreadlight::material::FEATURE_ANISOTROPY
#import spreadlight::anisotropy::anisotropic_bent_normal
#endif
#ifdef IRIDESCENCE
#import spreadlight::sheen_film::film_at
#import spreadlight::iridescence::iridescence_fresnel
#ifndef SHEEN
// The G-buffer's sheen and film target (lib/sheen_film.wgsl), or a 1x1
// stand-in of one unwritten texel where it has none (factors only).
@group(0) @binding(12) var sheen_film_target: texture_2d<u32>;
fn sheen_film_texel(pixel: vec2<u32>) -> vec4<u32> {
    return textureLoad(sheen_film_target, min(pixel, textureDimensions(sheen_film_target) - vec2<u32>(1u)), 0);
}
#endif
#endif
#ifdef SHEEN
#import spreadlight::sheen_film::sheen_at
#import spreadlight::sheen::{sheen_albedo, sheen_scaling}
// The G-buffer's sheen and film target (lib/sheen_film.wgsl), or a 1x1
// stand-in of one unwritten texel where it has none (factors only).
@group(0) @binding(12) var sheen_film_target: texture_2d<u32>;
fn sheen_film_texel(pixel: vec2<u32>) -> vec4<u32> {
    return textureLoad(sheen_film_target, min(pixel, textureDimensions(sheen_film_target) - vec2<u32>(1u)), 0);
}

// A material's sheen at a pixel: colour (0..1) and roughness, its maps'
// where the G-buffer resolved them; black without one.
fn sheen_of(material: u32, pixel: vec2<u32>) -> vec4<f32> {
    return sheen_at(material, sheen_film_texel(pixel));
}
#endif

struct Params {
    // 0: reflect, 1: refract
    mode: u32,
    // Prefiltered levels: roughness r reads level r * (levels - 1).
    levels: u32,
    ior: f32,
    pad: f32,
}

@group(0) @binding(0) var<uniform> camera: Camera;
@group(0) @binding(1) var<uniform> params: Params;
@group(0) @binding(2) var color: texture_2d<f32>;
@group(0) @binding(3) var normals: texture_2d<f32>;
@group(0) @binding(4) var depth: texture_2d<f32>;
@group(0) @binding(5) var prefiltered: texture_cube<f32>;
@group(0) @binding(6) var irradiance: texture_cube<f32>;
@group(0) @binding(7) var lut: texture_2d<f32>;
@group(0) @binding(8) var cube_sampler: sampler;
@group(0) @binding(9) var out_specular: texture_storage_2d<rgba16float, write>;
@group(0) @binding(10) var out_diffuse: texture_storage_2d<rgba16float, write>;
#ifdef ANISOTROPY
// View-space anisotropy direction (rgb) and strength (a), written by the
// G-buffer resolve for pixels of Anisotropy materials only.
@group(0) @binding(13) var anisotropy_target: texture_2d<f32>;
#endif
#ifdef CLEARCOAT
// The coat's own normal at `pixel` (its map's, else `n`), facing the viewer.
fn coat_normal(pixel: vec2<u32>, n: vec3<f32>, v: vec3<f32>) -> vec3<f32> {
    return facing_normal(safe_normalize(clearcoat_normal_at(pixel, n), n), v);
}

// 1 - factor x F(N_c.V), F Schlick's at f0 0.04: what a coat of `factor`
// lets reach the base and leave it (CookTorrance's dimming under a light).
fn coat_dim(factor: f32, coat_n: vec3<f32>, v: vec3<f32>) -> f32 {
    let n_dot_v = clamp(dot(coat_n, v), 1e-4, 1.0);
    return 1.0 - factor * (DIELECTRIC_F0 + (1.0 - DIELECTRIC_F0) * schlick_weight(n_dot_v));
}
#endif
#ifdef PARALLAX
// Matches `GpuProbeVolume` in crates/render/src/environment/probe/mod.rs.
struct ProbeVolume {
    position: vec3<f32>,
    // 0: none, 1: box (low..high), 2: sphere (low.xyz, radius low.w)
    shape: u32,
    low: vec4<f32>,
    high: vec4<f32>,
}
@group(0) @binding(11) var<uniform> volume: ProbeVolume;

// The distance along unit `r` from `p` to where it leaves the volume, or
// -1 where `p` is outside it.
fn leaving_distance(p: vec3<f32>, r: vec3<f32>) -> f32 {
    if (volume.shape == 1u) {
        if (any(p < volume.low.xyz) || any(p > volume.high.xyz)) {
            return -1.0;
        }
        // Lagarde's box: the nearest of the far planes along each axis
        // (an axis the ray runs parallel to never limits it).
        let safe = select(r, vec3<f32>(1e-6), abs(r) < vec3<f32>(1e-6));
        let far = max((volume.high.xyz - p) / safe, (volume.low.xyz - p) / safe);
        return max(min(min(far.x, far.y), far.z), 0.0);
    }
    let o = p - volume.low.xyz;
    let c = dot(o, o) - volume.low.w * volume.low.w;
    if (c > 0.0) {
        return -1.0;
    }
    let b = dot(o, r);
    return -b + sqrt(max(b * b - c, 0.0));
}

// The direction to read the probe's cube along for a ray from `p` along `r`.
fn parallax_corrected(p: vec3<f32>, r: vec3<f32>) -> vec3<f32> {
    let t = leaving_distance(p, r);
    if (t < 0.0) {
        return r;
    }
    return safe_normalize(p + r * t - volume.position, r);
}
#endif

const HALF_MAX: f32 = 65000.0;

fn clean(v: vec3<f32>) -> vec4<f32> {
    // max/min drop NaN on most drivers; select makes sure.
    let c = min(max(v, vec3<f32>(0.0)), vec3<f32>(HALF_MAX));
    return vec4<f32>(select(vec3<f32>(0.0), c, c == c), 1.0);
}

// The reflected (or refracted) environment at `pixel`, times the split-sum
// factor; zero where depth is empty or the material does not reflect.
fn specular_at(pixel: vec2<u32>) -> vec4<f32> {
    let d = textureLoad(depth, pixel, 0).r;
    let texel = textureLoad(color, pixel, 0);
    let material = channel_to_id(texel.a);
    if (d <= 0.0 || !has_feature(material, FEATURE_REFLECTION)) {
        return vec4<f32>(0.0, 0.0, 0.0, 1.0);
    }
    let h = camera.projection_inverse * vec4<f32>(pixel_to_ndc(pixel, camera.size), d, 1.0);
    let p = h.xyz / h.w;
    let v = safe_normalize(-p, vec3<f32>(0.0, 0.0, 1.0));
    let n = facing_normal(safe_normalize(textureLoad(normals, pixel, 0).xyz, v), v);
    let ct = clamp(feature_param_at(material, FEATURE_COOK_TORRANCE, 0u, vec4<f32>(0.5, 0.0, 0.04, 0.0), pixel), vec4<f32>(0.0), vec4<f32>(1.0));
    let roughness = ct.x;
    let albedo = max(texel.rgb, vec3<f32>(0.0));
    let f0 = mix(vec3<f32>(ct.z), albedo, ct.y);
    let n_dot_v = clamp(dot(n, v), 1e-4, 1.0);
    var factor = split_sum(lut, cube_sampler, f0, n_dot_v, roughness);
#ifdef IRIDESCENCE
    let film = film_at(material, pixel, sheen_film_texel(pixel));
    if (film.x > 0.0) {
        let film_f = iridescence_fresnel(ct.z, albedo, ct.y, n_dot_v, film.y, film.z);
        factor = mix(factor, film_f * split_sum(lut, cube_sampler, vec3<f32>(1.0), n_dot_v, roughness), film.x);
    }
#endif
    // The normal the reflection is mirrored about: the pixel's, or the
    // anisotropic lobe's bent normal.
    var mirror_n = n;
#ifdef ANISOTROPY
    if (has_feature(material, FEATURE_ANISOTROPY)) {
        let aniso = textureLoad(anisotropy_target, pixel, 0);
        mirror_n = anisotropic_bent_normal(n, v, aniso.xyz, roughness, aniso.w);
    }
#endif
    var dir = reflect(-v, mirror_n);
    var weight = factor;
    if (params.mode == 1u) {
        let t = refract(-v, n, 1.0 / max(params.ior, 1e-3));
        if (dot(t, t) > 1e-8) {
            dir = t;
            weight = max(vec3<f32>(1.0) - factor, vec3<f32>(0.0));
        }
    }
    var specular = environment_along(p, dir, roughness) * weight;
#ifdef SHEEN
    // The sheen lies over the base (and under a coat): the base's light is
    // dimmed by its albedo scaling and the sheen adds its own, lit by the
    // environment's irradiance at the normal (exact for a uniform one).
    let sheen = sheen_of(material, pixel);
    if (params.mode == 0u && any(sheen.rgb > vec3<f32>(0.0))) {
        let world_n = safe_normalize((camera.view_inverse * vec4<f32>(n, 0.0)).xyz, vec3<f32>(0.0, 1.0, 0.0));
        let around = textureSampleLevel(irradiance, cube_sampler, world_n, 0.0).rgb;
        specular = specular * sheen_scaling(sheen.rgb, n_dot_v, sheen.a) + sheen.rgb * sheen_albedo(n_dot_v, sheen.a) * around;
    }
#endif
#ifdef CLEARCOAT
    if (params.mode == 0u) {
        // Scaled by its maps where the G-buffer resolved them.
        let coat = clamp(clearcoat_at(material, pixel), vec2<f32>(0.0), vec2<f32>(1.0));
        if (coat.x > 0.0) {
            let coat_n = coat_normal(pixel, n, v);
            let coat_n_dot_v = clamp(dot(coat_n, v), 1e-4, 1.0);
            // What the coat reflects does not reach the base, nor leave it.
            let dim = coat_dim(coat.x, coat_n, v);
            let coat_weight = split_sum(lut, cube_sampler, vec3<f32>(DIELECTRIC_F0), coat_n_dot_v, coat.y);
            let coat_light = environment_along(p, reflect(-v, coat_n), coat.y) * coat_weight;
            specular = specular * dim + coat.x * coat_light;
        }
    }
#endif
    return clean(specular);
}

// The prefiltered environment along view-space direction `dir` from
// view-space point `p` (corrected for a probe's volume with PARALLAX), at
// `roughness`'s level.
fn environment_along(p: vec3<f32>, dir: vec3<f32>, roughness: f32) -> vec3<f32> {
    var world_dir = safe_normalize((camera.view_inverse * vec4<f32>(dir, 0.0)).xyz, vec3<f32>(0.0, 1.0, 0.0));
#ifdef PARALLAX
    let world = camera.view_inverse * vec4<f32>(p, 1.0);
    world_dir = parallax_corrected(world.xyz / world.w, world_dir);
#endif
    let lod = roughness * f32(max(params.levels, 1u) - 1u);
    return textureSampleLevel(prefiltered, cube_sampler, world_dir, lod).rgb;
}

// The environment's diffuse light at `pixel` (zero where depth is empty).
fn diffuse_at(pixel: vec2<u32>) -> vec4<f32> {
    let d = textureLoad(depth, pixel, 0).r;
    if (d <= 0.0) {
        return vec4<f32>(0.0, 0.0, 0.0, 1.0);
    }
    let h = camera.projection_inverse * vec4<f32>(pixel_to_ndc(pixel, camera.size), d, 1.0);
    let v = safe_normalize(-h.xyz / h.w, vec3<f32>(0.0, 0.0, 1.0));
    let n = facing_normal(safe_normalize(textureLoad(normals, pixel, 0).xyz, v), v);
    let world_n = safe_normalize((camera.view_inverse * vec4<f32>(n, 0.0)).xyz, vec3<f32>(0.0, 1.0, 0.0));
    var light = textureSampleLevel(irradiance, cube_sampler, world_n, 0.0).rgb;
#ifdef SHEEN
    // Under a sheen the base receives what the sheen does not reflect.
    let sheen = sheen_of(channel_to_id(textureLoad(color, pixel, 0).a), pixel);
    if (any(sheen.rgb > vec3<f32>(0.0))) {
        light *= sheen_scaling(sheen.rgb, clamp(dot(n, v), 1e-4, 1.0), sheen.a);
    }
#endif
#ifdef CLEARCOAT
    // Nor what a coat reflects (it lies over the sheen too).
    let coat = clamp(clearcoat_at(channel_to_id(textureLoad(color, pixel, 0).a), pixel), vec2<f32>(0.0), vec2<f32>(1.0));
    if (coat.x > 0.0) {
        light *= coat_dim(coat.x, coat_normal(pixel, n, v), v);
    }
#endif
    return clean(light);
}

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = vec2<u32>(camera.size.xy);
    if (id.x >= size.x || id.y >= size.y) {
        return;
    }
    textureStore(out_specular, id.xy, specular_at(id.xy));
}

// The environment's diffuse light on every surface.
@compute @workgroup_size(8, 8)
fn diffuse(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = vec2<u32>(camera.size.xy);
    if (id.x >= size.x || id.y >= size.y) {
        return;
    }
    textureStore(out_diffuse, id.xy, diffuse_at(id.xy));
}

// Both outputs in one pass, when the frame reads both: one full-screen
// pass less than `main` and `diffuse` apart.
@compute @workgroup_size(8, 8)
fn both(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = vec2<u32>(camera.size.xy);
    if (id.x >= size.x || id.y >= size.y) {
        return;
    }
    textureStore(out_diffuse, id.xy, diffuse_at(id.xy));
    textureStore(out_specular, id.xy, specular_at(id.xy));
}

// No material reflects: the specular output is zero.
@compute @workgroup_size(8, 8)
fn clear(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = vec2<u32>(camera.size.xy);
    if (id.x >= size.x || id.y >= size.y) {
        return;
    }
    textureStore(out_specular, id.xy, vec4<f32>(0.0, 0.0, 0.0, 1.0));
}
