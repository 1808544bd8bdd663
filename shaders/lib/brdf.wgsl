// The Cook-Torrance BRDF: GGX distribution, height-correlated Smith
// visibility, Schlick Fresnel, Lambert diffuse and the multiple-scattering
// energy compensation. The CPU reference, with the same names and the
// reasoning, is crates/render/src/reference/brdf.rs; tests run both.
//
// Roughness is perceptual (0..1), alpha = roughness^2 >= MIN_ALPHA; N.L <= 0
// gives no light, a back-facing view is clamped to grazing. Never NaN.
#define_import_path spreadlight::brdf

#import spreadlight::packing::safe_normalize

const PI: f32 = 3.14159265358979;
const MIN_ALPHA: f32 = 1e-3;
const MIN_COS: f32 = 1e-4;
const DIELECTRIC_F0: f32 = 0.04;

// What one light contributes, as factors of its incoming radiance (N.L included).
struct Brdf {
    diffuse: vec3<f32>,
    specular: vec3<f32>,
}

fn roughness_to_alpha(roughness: f32) -> f32 {
    let r = clamp(roughness, 0.0, 1.0);
    return max(r * r, MIN_ALPHA);
}

fn d_ggx(n_dot_h: f32, roughness: f32) -> f32 {
    let a = roughness_to_alpha(roughness);
    let a2 = a * a;
    return a2 / ggx_denominator(n_dot_h, a2);
}

// PI ((1 - nh^2) + nh^2 a^2)^2: D is alpha^2 over it. Apart, so the light
// loop divides once for D and V together.
fn ggx_denominator(n_dot_h: f32, a2: f32) -> f32 {
    let nh = clamp(n_dot_h, 0.0, 1.0);
    // 1 - nh^2 as (1 - nh)(1 + nh): keeps its digits next to a sharp peak.
    let f = (1.0 - nh) * (1.0 + nh) + nh * nh * a2;
    return PI * f * f;
}

// sqrt(cos^2 (1 - a^2) + a^2), with cos clamped to MIN_COS..1: one
// direction's half of the height-correlated Smith term.
fn smith_lambda(cos_theta: f32, a2: f32) -> f32 {
    let c = clamp(cos_theta, MIN_COS, 1.0);
    return sqrt(c * c * (1.0 - a2) + a2);
}

// G2 / (4 N.L N.V), so the specular lobe is D * V * F.
fn v_smith_ggx_correlated(n_dot_v: f32, n_dot_l: f32, roughness: f32) -> f32 {
    let a = roughness_to_alpha(roughness);
    let a2 = a * a;
    return 1.0 / smith_denominator(n_dot_v, n_dot_l, smith_lambda(n_dot_v, a2), smith_lambda(n_dot_l, a2));
}

// 2 (N.L lambda(V) + N.V lambda(L)), cosines clamped to MIN_COS..1: V is
// one over it, from the two directions' `smith_lambda`.
fn smith_denominator(n_dot_v: f32, n_dot_l: f32, lambda_of_v: f32, lambda_of_l: f32) -> f32 {
    let nv = clamp(n_dot_v, MIN_COS, 1.0);
    let nl = clamp(n_dot_l, MIN_COS, 1.0);
    return 2.0 * (nl * lambda_of_v + nv * lambda_of_l);
}

fn f_schlick(f0: vec3<f32>, v_dot_h: f32) -> vec3<f32> {
    return f0 + (vec3<f32>(1.0) - f0) * schlick_weight(v_dot_h);
}

// (1 - V.H)^5, V.H clamped to 0..1: Schlick's F is F0 + (1 - F0) times it.
fn schlick_weight(v_dot_h: f32) -> f32 {
    let x = 1.0 - clamp(v_dot_h, 0.0, 1.0);
    let x2 = x * x;
    return x2 * x2 * x;
}

fn diffuse_lambert() -> f32 {
    return 1.0 / PI;
}

fn poly4(x: f32, c0: f32, c1: f32, c2: f32, c3: f32, c4: f32) -> f32 {
    return (((c4 * x + c3) * x + c2) * x + c1) * x + c0;
}

// E_ss, the single-scattering specular albedo with F = 1: ln E_ss is a
// degree-4 polynomial in roughness and in s = N.V / sqrt(N.V^2 (1 - a^2) + a^2),
// fitted to a numerical integration (max relative error 1.03%; see the
// reference for how).
fn specular_albedo(n_dot_v: f32, roughness: f32) -> f32 {
    let r = clamp(roughness, 0.0, 1.0);
    let a = roughness_to_alpha(r);
    let a2 = a * a;
    let nv = clamp(n_dot_v, MIN_COS, 1.0);
    let s = nv / sqrt(nv * nv * (1.0 - a2) + a2);
    let ln_e = poly4(
        s,
        poly4(r, 0.1079475, -0.639055, 1.637571, -1.833237, 0.7098608),
        poly4(r, -1.615846, 7.462202, -21.4432, 26.51882, -13.93525),
        poly4(r, 5.613205, -28.53082, 93.49193, -131.1957, 65.84242),
        poly4(r, -8.25543, 39.95344, -142.8702, 215.3067, -109.894),
        poly4(r, 4.162487, -18.68436, 72.00439, -114.627, 59.542),
    );
    return min(exp(ln_e), 1.0);
}

// Multiply the specular term by this to restore the energy of the bounces
// the single-scattering lobe leaves out (Kulla & Conty 2017, Filament's form).
fn energy_compensation(f0: vec3<f32>, n_dot_v: f32, roughness: f32) -> vec3<f32> {
    return vec3<f32>(1.0) + f0 * (1.0 / specular_albedo(n_dot_v, roughness) - 1.0);
}

// Unit n (normal), v (to the eye), l (to the light); metalness workflow
// with the common dielectric F0 of 0.04.
fn cook_torrance(
    n: vec3<f32>,
    v: vec3<f32>,
    l: vec3<f32>,
    albedo_in: vec3<f32>,
    roughness_in: f32,
    metallic_in: f32,
    compensate: bool,
) -> Brdf {
    return cook_torrance_f0(n, v, l, albedo_in, roughness_in, metallic_in, DIELECTRIC_F0, compensate);
}

// `cook_torrance` with the dielectric part's F0 given (a material's
// Reflectance, 0..1): F0 = mix(reflectance, albedo, metallic).
fn cook_torrance_f0(
    n: vec3<f32>,
    v: vec3<f32>,
    l: vec3<f32>,
    albedo_in: vec3<f32>,
    roughness_in: f32,
    metallic_in: f32,
    reflectance_in: f32,
    compensate: bool,
) -> Brdf {
    let surface = brdf_surface(n, v, albedo_in, roughness_in, metallic_in, reflectance_in);
    var brdf = cook_torrance_light(surface, l);
    if (compensate) {
        brdf.specular *= surface_energy_compensation(surface);
    }
    return brdf;
}

// What `cook_torrance_f0` needs of a surface point that no light changes.
// A light loop makes it once per pixel and calls `cook_torrance_light` per
// light: at hundreds of lights a pixel, this part was most of the work.
struct BrdfSurface {
    n: vec3<f32>,
    v: vec3<f32>,
    // N.V clamped to MIN_COS..1.
    n_dot_v: f32,
    // N.V as it is (half_vector_cosines).
    view_cosine: f32,
    roughness: f32,
    // alpha^2.
    alpha_squared: f32,
    // smith_lambda(N.V, alpha^2).
    lambda_of_v: f32,
    // F0, the Fresnel reflectance at normal incidence (`f0` would break
    // naga_oil's names: an identifier may not end in a digit).
    normal_fresnel: vec3<f32>,
    // (1 - metallic) albedo / PI: Lambert before (1 - F) and N.L.
    diffuse: vec3<f32>,
}

fn brdf_surface(
    n: vec3<f32>,
    v: vec3<f32>,
    albedo_in: vec3<f32>,
    roughness_in: f32,
    metallic_in: f32,
    reflectance_in: f32,
) -> BrdfSurface {
    let view_cosine = dot(n, v);
    let n_dot_v = clamp(view_cosine, MIN_COS, 1.0);
    let roughness = clamp(roughness_in, 0.0, 1.0);
    let metallic = clamp(metallic_in, 0.0, 1.0);
    let albedo = max(albedo_in, vec3<f32>(0.0));
    let a = roughness_to_alpha(roughness);
    let a2 = a * a;
    return BrdfSurface(
        n,
        v,
        n_dot_v,
        view_cosine,
        roughness,
        a2,
        smith_lambda(n_dot_v, a2),
        mix(vec3<f32>(clamp(reflectance_in, 0.0, 1.0)), albedo, metallic),
        (1.0 - metallic) * albedo * diffuse_lambert(),
    );
}

// The energy compensation depends on the surface alone: a light loop
// multiplies its summed specular by it once.
fn surface_energy_compensation(s: BrdfSurface) -> vec3<f32> {
    return energy_compensation(s.normal_fresnel, s.n_dot_v, s.roughness);
}

// One light's share for a prepared surface, without the energy compensation.
fn cook_torrance_light(s: BrdfSurface, l: vec3<f32>) -> Brdf {
    let n_dot_l = dot(s.n, l);
    let h = safe_normalize(s.v + l, s.n);
    let w = cook_torrance_weights(s, n_dot_l, dot(s.n, h), dot(s.v, h));
    return light_sums_brdf(s, LightSums(vec3<f32>(w.x), vec3<f32>(w.y), vec3<f32>(w.z)));
}

// What a light loop sums: each light's radiance times its three
// `cook_torrance_weights`. F = F0 + (1 - F0) w (w: Schlick's weight), so a
// light's specular is D V N.L (F0 + (1 - F0) w) and its diffuse
// (1 - F0) (1 - w) N.L times the surface's Lambert term: F0 and the surface
// are applied once to the sums (`light_sums_brdf`), not per light and
// channel. At hundreds of lights a pixel that halves the per-light
// arithmetic after the BRDF's scalars.
struct LightSums {
    // Sum of radiance D V N.L.
    specular: vec3<f32>,
    // Sum of radiance D V N.L w.
    grazing: vec3<f32>,
    // Sum of radiance N.L (1 - w).
    diffuse: vec3<f32>,
}

fn no_light_sums() -> LightSums {
    return LightSums(vec3<f32>(0.0), vec3<f32>(0.0), vec3<f32>(0.0));
}

// Adds one light: `radiance` (rgb), `weights` from `cook_torrance_weights`.
fn add_light(sums: ptr<function, LightSums>, radiance: vec3<f32>, weights: vec3<f32>) {
    (*sums).specular += radiance * weights.x;
    (*sums).grazing += radiance * weights.y;
    (*sums).diffuse += radiance * weights.z;
}

// The diffuse and specular radiance of summed lights, without the energy
// compensation.
fn light_sums_brdf(s: BrdfSurface, sums: LightSums) -> Brdf {
    let f0 = s.normal_fresnel;
    let specular = f0 * sums.specular + (vec3<f32>(1.0) - f0) * sums.grazing;
    let diffuse = (vec3<f32>(1.0) - f0) * s.diffuse * sums.diffuse;
    return Brdf(diffuse, specular);
}

// One light's scalar weights (D V N.L, D V N.L w, N.L (1 - w)) from its
// cosines: N.L unclamped (<= 0: no light), N.H and V.H of the half vector.
fn cook_torrance_weights(s: BrdfSurface, n_dot_l_raw: f32, n_dot_h: f32, v_dot_h: f32) -> vec3<f32> {
    return cook_torrance_weights_scaled(s, n_dot_l_raw, n_dot_h, v_dot_h, 1.0);
}

// `cook_torrance_weights` times `scale` (a light's attenuation): the scale
// enters through N.L, the one factor all three weights share, so a light
// loop pays one multiplication for it, not three.
fn cook_torrance_weights_scaled(s: BrdfSurface, n_dot_l_raw: f32, n_dot_h: f32, v_dot_h: f32, scale: f32) -> vec3<f32> {
    if (n_dot_l_raw <= 0.0) {
        return vec3<f32>(0.0);
    }
    let n_dot_l = min(n_dot_l_raw, 1.0);
    let w = schlick_weight(v_dot_h);
    // D * V over one reciprocal: at hundreds of lights a pixel, reciprocals
    // (a quarter of the rate of other arithmetic) were a good part of the
    // light loop. The reciprocal as a squared reciprocal square root: one
    // special-function op and a multiplication, where a division may
    // compile to a refined reciprocal with a slow path. Within a few ulps:
    // the denominator lies in about 1e-18..13 (f >= alpha^2 >= 1e-6, the
    // cosines >= MIN_COS), far inside f32's normal range.
    let a2 = s.alpha_squared;
    let v_denominator = smith_denominator(s.n_dot_v, n_dot_l, s.lambda_of_v, smith_lambda(n_dot_l, a2));
    let scaled = n_dot_l * scale;
    let root = inverseSqrt(ggx_denominator(n_dot_h, a2) * v_denominator);
    let specular = a2 * root * root * scaled;
    return vec3<f32>(specular, specular * w, scaled - scaled * w);
}

// N.H and V.H for unit `v` and `l` from N.L and V.L, without the half vector:
// |v + l|^2 = 2 + 2 V.L (Karis). Where v + l has no direction the half vector
// is the normal, as `safe_normalize` makes it.
fn half_vector_cosines(s: BrdfSurface, n_dot_l: f32, v_dot_l: f32) -> vec2<f32> {
    let length2 = 2.0 + 2.0 * v_dot_l;
    if (length2 <= 1e-20) {
        return vec2<f32>(1.0, s.view_cosine);
    }
    let inverse_length = inverseSqrt(length2);
    return vec2<f32>((s.view_cosine + n_dot_l) * inverse_length, (1.0 + v_dot_l) * inverse_length);
}
