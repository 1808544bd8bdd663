// One light of a buffer at a world point, Cook-Torrance weighted, for the
// forward passes that shade surfaces outside the G-buffer: lit transparency
// (post/transparency.wgsl) and EnvironmentProbe's faces
// (environment/environment_probe.wgsl). CookTorrance's `shade` in world
// space: the attenuation, cone and shadow functions are the libraries' it
// calls, so a light lights a glass pane, and what a probe sees, exactly as
// it lights the wall behind them. The light type is compiled in as
// CookTorrance compiles it: point by default, LIGHT_SPOT, LIGHT_SUN;
// SHADOWS (and its filter) reads the buffer's shadow maps; CLEARCOAT adds
// the coat's lobe on the coat's own normal (lit transparency's coated layers);
// ANISOTROPY stretches the specular lobe along the fragment's anisotropy
// direction (lib/anisotropy.wgsl; lit transparency's anisotropic layers);
// SHEEN the sheen's Charlie lobe (lib/sheen.wgsl) and its dimming of the base,
// and sums what a thin film's diffuse takes (`filmed_light`: lit
// transparency compiles its extension lobes under one switch).
#define_import_path spreadlight::forward_light
#import spreadlight::brdf::{BrdfSurface, LightSums, add_light, cook_torrance_weights, half_vector_cosines}
#import spreadlight::lights::{range_window, inverse_square}
#import spreadlight::packing::safe_normalize
#ifdef LIGHT_SPOT
#import spreadlight::spot::spot_mask
#endif
#ifdef SHADOWS
#import spreadlight::shadow_sampling::light_shadow
#endif
#ifdef CLEARCOAT
#import spreadlight::brdf::{cook_torrance_weights_scaled, schlick_weight, DIELECTRIC_F0}
#endif
#ifdef SHEEN
#import spreadlight::brdf::Brdf
#endif
#ifdef ANISOTROPY
#import spreadlight::anisotropy::{AnisotropicSurface, anisotropic_weights_scaled}
// The shaded fragment's anisotropic lobe, set by the importer before its
// lights (strength 0: the isotropic lobe).
var<private> aniso: AnisotropicSurface;
#endif
#ifdef SHEEN
#import spreadlight::sheen::{sheen_weight, sheen_scaling}
#endif

// Matches `GpuLight` in crates/render/src/lighting/mod.rs.
struct Light {
    position_range: vec4<f32>,
    intensity: vec4<f32>,
    direction: vec4<f32>,
    cone: vec4<f32>,
}

@group(0) @binding(13) var<storage, read> lights: array<Light>;

#ifdef CLEARCOAT
// The shaded fragment's coat, set by the importer before its lights: its
// coverage (0: none), its lobe's surface (the coat's normal and roughness,
// f0 0.04) and the coat's specular summed over the lights.
var<private> coat_factor: f32;
var<private> coat_surface: BrdfSurface;
var<private> coat_sum: vec3<f32>;
#endif
#ifdef SHEEN
// The shaded fragment's thin film, set by the importer before its lights:
// its factor (0: none), its Fresnel at N.V (lib/iridescence.wgsl), and the
// summed radiance N.L its diffuse takes, as CookTorrance keeps them.
var<private> film_factor: f32;
var<private> film_fresnel: vec3<f32>;
var<private> film_lit: vec3<f32>;
#endif
#ifdef SHEEN
// The shaded fragment's sheen, set by the importer before its lights: its
// colour (black: none), its roughness and its lobe summed over the lights.
var<private> sheen_color: vec3<f32>;
var<private> sheen_roughness: f32;
var<private> sheen_sum: vec3<f32>;
#endif

// Light `i`'s radiance at world point `pw` times its Cook-Torrance weights,
// added to `sums`. `view_depth` (the camera's depth of the point) picks a
// sun's cascade (LIGHT_SUN with SHADOWS); point and spot lights ignore it.
fn add_forward_light(i: u32, pw: vec3<f32>, s: BrdfSurface, view_depth: f32, sums: ptr<function, LightSums>) {
    add_light_record(lights[i], i, pw, s, view_depth, sums);
}

// `add_forward_light` with light `i`'s record already loaded (SHADE_TILED
// shares a batch of records through workgroup memory).
fn add_light_record(record: Light, i: u32, pw: vec3<f32>, s: BrdfSurface, view_depth: f32, sums: ptr<function, LightSums>) {
#ifdef LIGHT_SUN
    let l = safe_normalize(-record.direction.xyz, vec3<f32>(0.0, 1.0, 0.0));
    let n_dot_l = dot(s.n, l);
    let v_dot_l = dot(s.v, l);
#ifdef CLEARCOAT
    let coat_n_dot_l = dot(coat_surface.n, l);
#endif
    var radiance = record.intensity.rgb;
    let attenuation = 1.0;
#ifdef SHADOWS
    if (record.cone.z >= 0.0) {
        radiance *= light_shadow(u32(record.cone.z), pw, s.n, record.direction.xyz, view_depth, n_dot_l);
    }
#endif
#else
    let range = record.position_range.w;
    // A light without a range lights nothing.
    if (!(range > 0.0)) {
        return;
    }
    let to_light = record.position_range.xyz - pw;
    let distance2 = dot(to_light, to_light);
    // (distance / range)^2; the floor keeps a range whose square underflows finite.
    let ratio2 = distance2 / max(range * range, 1e-30);
    if (!(ratio2 < 1.0)) {
        return;
    }
    let inverse_distance = inverseSqrt(max(distance2, 1e-20));
    let attenuation = range_window(ratio2) * inverse_square(inverse_distance);
    var n_dot_l = dot(s.n, to_light) * inverse_distance;
    var v_dot_l = dot(s.v, to_light) * inverse_distance;
#ifdef ANISOTROPY
    var l = to_light * inverse_distance;
#endif
    if (!(distance2 > 1e-20)) {
        // A light at the surface point: from along the normal.
        n_dot_l = 1.0;
        v_dot_l = s.view_cosine;
#ifdef ANISOTROPY
        l = s.n;
#endif
    }
#ifdef CLEARCOAT
    var coat_n_dot_l = dot(coat_surface.n, to_light) * inverse_distance;
    if (!(distance2 > 1e-20)) {
        coat_n_dot_l = 1.0;
    }
#endif
    var radiance = record.intensity.rgb;
#ifdef LIGHT_SPOT
    radiance *= spot_mask(i, record.cone, pw);
#endif
#ifdef SHADOWS
    if (record.cone.z >= 0.0) {
        radiance *= light_shadow(u32(record.cone.z), pw, s.n, pw - record.position_range.xyz, view_depth, n_dot_l);
    }
#endif
#endif
    let cosines = half_vector_cosines(s, n_dot_l, v_dot_l);
#ifdef ANISOTROPY
    if (aniso.strength > 0.0) {
        add_light(sums, radiance, anisotropic_weights_scaled(s, aniso, l, n_dot_l, attenuation));
    } else {
        add_light(sums, radiance, cook_torrance_weights(s, n_dot_l, cosines.x, cosines.y) * attenuation);
    }
#else
    add_light(sums, radiance, cook_torrance_weights(s, n_dot_l, cosines.x, cosines.y) * attenuation);
#endif
#ifdef CLEARCOAT
    if (coat_factor > 0.0) {
        // D V N.L (F0 + (1 - F0) w) on the coat's normal: CookTorrance's coat lobe.
        let coat_cosines = half_vector_cosines(coat_surface, coat_n_dot_l, v_dot_l);
        let coat = cook_torrance_weights_scaled(coat_surface, coat_n_dot_l, coat_cosines.x, coat_cosines.y, attenuation);
        coat_sum += radiance * (coat.x * DIELECTRIC_F0 + coat.y * (1.0 - DIELECTRIC_F0));
    }
#endif
#ifdef SHEEN
    if (film_factor > 0.0 && n_dot_l > 0.0) {
        film_lit += radiance * (min(n_dot_l, 1.0) * attenuation);
    }
#endif
#ifdef SHEEN
    if (any(sheen_color > vec3<f32>(0.0))) {
        sheen_sum += radiance * sheen_weight(s.n_dot_v, n_dot_l, cosines.x, sheen_roughness, attenuation);
    }
#endif
}

#ifdef SHEEN
// The film over a lit fragment of surface `s` (the private film state,
// summed over its lights), as CookTorrance's IRIDESCENCE: F = mix(Schlick's,
// the film's, factor), the film's F one per fragment, so its specular is F
// times the lobes' sum (D V N.L in `sums`), its diffuse (1 - F) times the
// Lambert term's. `lit` is what light_sums_brdf made of `sums`.
fn filmed_light(s: BrdfSurface, sums: LightSums, lit: Brdf) -> Brdf {
    if (!(film_factor > 0.0)) {
        return lit;
    }
    var out = lit;
    out.specular = mix(lit.specular, film_fresnel * sums.specular, film_factor);
    out.diffuse = mix(lit.diffuse, (vec3<f32>(1.0) - film_fresnel) * s.diffuse * film_lit, film_factor);
    return out;
}
#endif

#ifdef CLEARCOAT
// The coat over a lit fragment (the private coat state, summed over its
// lights): what the coat reflects neither reaches the base nor leaves it,
// and the coat's lobe adds to the specular. x: the diffuse's scale; the
// specular is returned whole.
fn coated_specular(specular: vec3<f32>) -> vec4<f32> {
    if (!(coat_factor > 0.0)) {
        return vec4<f32>(specular, 1.0);
    }
    let dim = 1.0 - coat_factor * (DIELECTRIC_F0 + (1.0 - DIELECTRIC_F0) * schlick_weight(coat_surface.n_dot_v));
    return vec4<f32>(specular * dim + coat_factor * coat_sum, dim);
}
#endif

#ifdef SHEEN
// The sheen over a lit fragment of surface `s` (the private sheen state,
// summed over its lights), as CookTorrance's SHEEN: the base is dimmed by
// 1 - max(colour) E(N.V) and the lobe adds to the specular. x: the
// diffuse's scale; the specular is returned whole. Apply before the coat,
// which lies over both.
fn sheened_specular(s: BrdfSurface, specular: vec3<f32>) -> vec4<f32> {
    if (!any(sheen_color > vec3<f32>(0.0))) {
        return vec4<f32>(specular, 1.0);
    }
    let scaling = sheen_scaling(sheen_color, s.n_dot_v, sheen_roughness);
    return vec4<f32>(specular * scaling + sheen_color * sheen_sum, scaling);
}
#endif
