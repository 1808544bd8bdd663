// The anisotropic GGX lobe of glTF's KHR_materials_anisotropy, as the
// extension and the Khronos sample viewer write it: along the anisotropy
// direction t the GGX width is alpha_t = mix(alpha, 1, strength^2), across
// it (b = n x t) alpha_b = alpha; the anisotropic height-correlated Smith
// visibility and distribution. The CPU reference, with the same names and
// the reasoning, is crates/reference/src/anisotropy.rs. Strength 0 is
// brdf.wgsl's isotropic lobe; cosines are clamped as there, so a strength
// of 1 over roughness 0 with the tangent along the view stays finite.
#define_import_path spreadlight::anisotropy

#import spreadlight::brdf::{BrdfSurface, roughness_to_alpha, schlick_weight, MIN_ALPHA, MIN_COS, PI}
#import spreadlight::packing::safe_normalize

// What the lobe needs of a surface point that no light changes.
struct AnisotropicSurface {
    // The anisotropy direction, unit and orthogonal to the normal, and n x t.
    t: vec3<f32>,
    b: vec3<f32>,
    // The widths along t and b.
    alpha_t: f32,
    alpha_b: f32,
    // smith_lambda_anisotropic of the view.
    lambda_of_v: f32,
    // 0..1; 0: the pixel is drawn with the isotropic lobe.
    strength: f32,
}

// (alpha_t, alpha_b) for perceptual roughness and strength (both 0..1).
fn anisotropic_alphas(roughness: f32, strength_in: f32) -> vec2<f32> {
    let alpha = roughness_to_alpha(roughness);
    let s = clamp(strength_in, 0.0, 1.0);
    return vec2<f32>(max(alpha + (1.0 - alpha) * s * s, MIN_ALPHA), alpha);
}

fn d_ggx_anisotropic(n_dot_h: f32, t_dot_h: f32, b_dot_h: f32, at: f32, ab: f32) -> f32 {
    let a2 = at * ab;
    let f = vec3<f32>(ab * t_dot_h, at * b_dot_h, a2 * clamp(n_dot_h, 0.0, 1.0));
    let w2 = a2 / max(dot(f, f), 1e-30);
    return a2 * w2 * w2 / PI;
}

// |(alpha_t T.x, alpha_b B.x, N.x)|, N.x clamped to MIN_COS..1.
fn smith_lambda_anisotropic(n_dot_x: f32, t_dot_x: f32, b_dot_x: f32, at: f32, ab: f32) -> f32 {
    return length(vec3<f32>(at * t_dot_x, ab * b_dot_x, clamp(n_dot_x, MIN_COS, 1.0)));
}

// The pixel's lobe from the G-buffer's direction (any length, view space)
// and strength: the direction is made orthogonal to the shaded normal (a
// normal map bends it); one with no direction left, or no strength, is
// strength 0.
fn anisotropic_surface(s: BrdfSurface, direction: vec3<f32>, strength_in: f32) -> AnisotropicSurface {
    let along = direction - s.n * dot(s.n, direction);
    let length2 = dot(along, along);
    var strength = select(0.0, min(strength_in, 1.0), strength_in > 0.0);
    if (!(length2 > 1e-12)) {
        strength = 0.0;
    }
    let t = safe_normalize(along, vec3<f32>(1.0, 0.0, 0.0));
    let b = cross(s.n, t);
    let alphas = anisotropic_alphas(s.roughness, strength);
    let lambda_of_v = smith_lambda_anisotropic(s.view_cosine, dot(t, s.v), dot(b, s.v), alphas.x, alphas.y);
    return AnisotropicSurface(t, b, alphas.x, alphas.y, lambda_of_v, strength);
}

// One light's weights (D V N.L, D V N.L w, N.L (1 - w)) times `scale`, as
// brdf.wgsl's cook_torrance_weights_scaled, with the anisotropic D and V:
// `l` the unit direction to the light, N.L unclamped (<= 0: no light).
fn anisotropic_weights_scaled(s: BrdfSurface, a: AnisotropicSurface, l: vec3<f32>, n_dot_l_raw: f32, scale: f32) -> vec3<f32> {
    if (n_dot_l_raw <= 0.0) {
        return vec3<f32>(0.0);
    }
    let n_dot_l = min(n_dot_l_raw, 1.0);
    let h = safe_normalize(s.v + l, s.n);
    let d = d_ggx_anisotropic(dot(s.n, h), dot(a.t, h), dot(a.b, h), a.alpha_t, a.alpha_b);
    let lambda_of_l = smith_lambda_anisotropic(n_dot_l, dot(a.t, l), dot(a.b, l), a.alpha_t, a.alpha_b);
    let visibility = 0.5 / (clamp(n_dot_l, MIN_COS, 1.0) * a.lambda_of_v + s.n_dot_v * lambda_of_l);
    let w = schlick_weight(dot(s.v, h));
    let scaled = n_dot_l * scale;
    let specular = d * visibility * scaled;
    return vec3<f32>(specular, specular * w, scaled - scaled * w);
}

// The normal image-based light mirrors the view about on an anisotropic
// surface (the extension's and the Khronos sample viewer's bent normal):
// the view projected onto the plane of the normal and the anisotropy
// direction t (the stretched lobe's reflections lie about it), mixed with
// the normal by (1 - strength (1 - roughness))^4, so a smooth, strongly
// anisotropic surface bends all the way and a rough or weak one hardly.
// `direction` any length, view space as `n` and `v`; no direction left
// after removing its normal part, or no strength (NaN too): `n`.
fn anisotropic_bent_normal(n: vec3<f32>, v: vec3<f32>, direction: vec3<f32>, roughness: f32, strength_in: f32) -> vec3<f32> {
    let along = direction - n * dot(n, direction);
    let strength = select(0.0, min(strength_in, 1.0), strength_in > 0.0);
    if (!(dot(along, along) > 1e-12) || strength <= 0.0) {
        return n;
    }
    let t = normalize(along);
    let b = cross(n, t);
    let anisotropic_normal = cross(cross(b, v), b);
    let bend = 1.0 - strength * (1.0 - clamp(roughness, 0.0, 1.0));
    let bend2 = bend * bend;
    return safe_normalize(mix(anisotropic_normal, n, bend2 * bend2), n);
}
