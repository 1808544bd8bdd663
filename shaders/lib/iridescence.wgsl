// Thin-film iridescence (glTF's KHR_materials_iridescence): the Fresnel
// reflectance of a dielectric film over the base, after Belcour & Barla
// 2017, as the Khronos glTF Sample Viewer evaluates it (iridescence.glsl:
// the Airy sum to the second order, the phase shifts turned into colour
// through the CIE XYZ sensitivity's Gaussian fit in Fourier space, then
// XYZ to linear Rec. 709). The CPU reference, with the same names, is
// crates/reference/src/iridescence.rs. Its F, at N.V, takes the place of
// Schlick's in the specular lobes (CookTorrance's IRIDESCENCE, Reflection's),
// mixed by the material's iridescence factor.
#define_import_path spreadlight::iridescence

const IRIDESCENCE_PI: f32 = 3.14159265358979;

// CIE XYZ to linear Rec. 709 (D65), by columns.
const XYZ_TO_REC709: mat3x3<f32> = mat3x3<f32>(
    vec3<f32>(3.2404542, -0.9692660, 0.0556434),
    vec3<f32>(-1.5371385, 1.8760108, -0.2040259),
    vec3<f32>(-0.4985314, 0.0415560, 1.0572252),
);

fn ior_to_fresnel(transmitted: vec3<f32>, incident: f32) -> vec3<f32> {
    let r = (transmitted - vec3<f32>(incident)) / (transmitted + vec3<f32>(incident));
    return r * r;
}

fn fresnel_to_ior(f: vec3<f32>) -> vec3<f32> {
    let s = sqrt(f);
    return (vec3<f32>(1.0) + s) / (vec3<f32>(1.0) - s);
}

fn film_schlick(f: vec3<f32>, cos_theta: f32) -> vec3<f32> {
    let x = 1.0 - clamp(cos_theta, 0.0, 1.0);
    let x2 = x * x;
    return f + (vec3<f32>(1.0) - f) * (x2 * x2 * x);
}

// The XYZ sensitivity's Fourier transform at optical path difference
// `opd` (nm) and phase `shift`, as linear Rec. 709.
fn eval_sensitivity(opd: f32, shift: vec3<f32>) -> vec3<f32> {
    let phase = 2.0 * IRIDESCENCE_PI * opd * 1.0e-9;
    let val = vec3<f32>(5.4856e-13, 4.4201e-13, 5.2481e-13);
    let pos = vec3<f32>(1.6810e+06, 1.7953e+06, 2.2084e+06);
    let spread = vec3<f32>(4.3278e+09, 9.3046e+09, 6.6121e+09);
    var xyz = val * sqrt(2.0 * IRIDESCENCE_PI * spread) * cos(pos * phase + shift) * exp(-(phase * phase) * spread);
    xyz.x += 9.7470e-14 * sqrt(2.0 * IRIDESCENCE_PI * 4.5282e+09) * cos(2.2399e+06 * phase + shift.x) * exp(-4.5282e+09 * phase * phase);
    return XYZ_TO_REC709 * (xyz / 1.0685e-7);
}

// The reflectance of a film of index `film_ior`, `thickness` nm thick,
// between a medium of index `outside_ior` and a base of normal-incidence
// reflectance `base_f` (per channel), seen at `cos_theta1`: 1 under total
// internal reflection, never negative.
fn eval_iridescence(outside_ior: f32, film_ior: f32, cos_theta1: f32, thickness: f32, base_f: vec3<f32>) -> vec3<f32> {
    // A film fading to nothing takes the outside's index.
    let iridescence_ior = mix(outside_ior, film_ior, smoothstep(0.0, 0.03, thickness));
    let ratio = outside_ior / iridescence_ior;
    let sin_theta2_sq = ratio * ratio * (1.0 - cos_theta1 * cos_theta1);
    let cos_theta2_sq = 1.0 - sin_theta2_sq;
    if (cos_theta2_sq < 0.0) {
        return vec3<f32>(1.0);
    }
    let cos_theta2 = sqrt(cos_theta2_sq);
    // The first interface (outside to film).
    let r_zero = ior_to_fresnel(vec3<f32>(iridescence_ior), outside_ior).x;
    let r12 = film_schlick(vec3<f32>(r_zero), cos_theta1).x;
    let t121 = 1.0 - r12;
    let phi12 = select(0.0, IRIDESCENCE_PI, iridescence_ior < outside_ior);
    let phi21 = IRIDESCENCE_PI - phi12;
    // The second interface (film to base).
    let base_ior = fresnel_to_ior(clamp(base_f, vec3<f32>(0.0), vec3<f32>(0.9999)));
    let r23 = film_schlick(ior_to_fresnel(base_ior, iridescence_ior), cos_theta2);
    let phi23 = select(vec3<f32>(0.0), vec3<f32>(IRIDESCENCE_PI), base_ior < vec3<f32>(iridescence_ior));
    // The phase shift.
    let opd = 2.0 * iridescence_ior * thickness * cos_theta2;
    let phi = vec3<f32>(phi21) + phi23;
    // The compound terms.
    let r123 = clamp(r12 * r23, vec3<f32>(1e-5), vec3<f32>(0.9999));
    let r123_root = sqrt(r123);
    let rs = t121 * t121 * r23 / (vec3<f32>(1.0) - r123);
    var i = vec3<f32>(r12) + rs;
    var cm = rs - vec3<f32>(t121);
    for (var m = 1; m <= 2; m++) {
        cm *= r123_root;
        let sm = 2.0 * eval_sensitivity(f32(m) * opd, f32(m) * phi);
        i += cm * sm;
    }
    return max(i, vec3<f32>(0.0));
}

// The film's reflectance at N.V over a metal-rough surface: over the
// dielectric base (f0 `reflectance`) and over the metal (f0 the albedo),
// mixed by metallic; kept within 0..1.
fn iridescence_fresnel(reflectance: f32, albedo: vec3<f32>, metallic: f32, n_dot_v: f32, film_ior: f32, thickness: f32) -> vec3<f32> {
    let c = clamp(n_dot_v, 1e-4, 1.0);
    let m = clamp(metallic, 0.0, 1.0);
    var f = vec3<f32>(0.0);
    if (m < 1.0) {
        f += (1.0 - m) * eval_iridescence(1.0, film_ior, c, thickness, vec3<f32>(clamp(reflectance, 0.0, 1.0)));
    }
    if (m > 0.0) {
        f += m * eval_iridescence(1.0, film_ior, c, thickness, max(albedo, vec3<f32>(0.0)));
    }
    return clamp(f, vec3<f32>(0.0), vec3<f32>(1.0));
}
