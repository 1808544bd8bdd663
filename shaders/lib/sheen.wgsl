// The sheen lobe (glTF's KHR_materials_sheen, as the Khronos specification
// and sample viewer shade it): the "Charlie" distribution (Estevez & Kulla
// 2017) with Neubelt's visibility term, tinted by the sheen colour, over a
// base layer it dims by 1 - max(colour) x E(N.V), E the lobe's directional
// albedo as an analytic fit (within 0.0125 of the integral for roughness
// 0.1..1, N.V 0.01..1; below those it reads its fit at them). The CPU
// reference, with the same names and the reasoning, is
// crates/reference/src/sheen.rs. Never NaN: roughness 0 keeps a floor width.
#define_import_path spreadlight::sheen

const SHEEN_PI: f32 = 3.14159265358979;
const MIN_SHEEN_ALPHA: f32 = 1e-3;
const SHEEN_MIN_COS: f32 = 1e-4;

// D(h) = (2 + 1/a) sin(h)^(1/a) / (2 pi), a = roughness^2.
fn d_charlie(n_dot_h: f32, roughness: f32) -> f32 {
    let r = clamp(roughness, 0.0, 1.0);
    let inverse = 1.0 / max(r * r, MIN_SHEEN_ALPHA);
    let sin2 = max(1.0 - n_dot_h * n_dot_h, 0.0);
    // pow(0, y) for y > 0 is 0; a sine of exactly 0 is kept off it anyway.
    return (2.0 + inverse) * pow(max(sin2, 1e-30), inverse * 0.5) / (2.0 * SHEEN_PI);
}

// 1 / (4 (N.L + N.V - N.L N.V)), capped at 1 (the sample viewer's cap).
fn v_neubelt(n_dot_v: f32, n_dot_l: f32) -> f32 {
    let nv = clamp(n_dot_v, SHEEN_MIN_COS, 1.0);
    let nl = clamp(n_dot_l, SHEEN_MIN_COS, 1.0);
    return min(1.0 / (4.0 * (nl + nv - nl * nv)), 1.0);
}

fn sheen_poly4(x: f32, c: vec4<f32>, c4: f32) -> f32 {
    return (((c4 * x + c.w) * x + c.z) * x + c.y) * x + c.x;
}

// E(N.V, roughness): ln(E + 0.02) is a polynomial of degree 4 in sqrt(N.V)
// and sqrt(roughness) (SHEEN_ALBEDO_FIT in the reference; rows by the power of sqrt(N.V)).
fn sheen_albedo(n_dot_v: f32, roughness: f32) -> f32 {
    let q = sqrt(clamp(roughness, 0.1, 1.0));
    let s = sqrt(clamp(n_dot_v, 0.01, 1.0));
    let c0 = sheen_poly4(q, vec4<f32>(-1.713953, 19.76195, -54.17829, 54.55947), -19.04794);
    let c1 = sheen_poly4(q, vec4<f32>(31.6313, -240.4802, 602.4391, -615.9817), 222.8554);
    let c2 = sheen_poly4(q, vec4<f32>(-164.1458, 1255.803, -3229.161, 3396.535), -1262.074);
    let c3 = sheen_poly4(q, vec4<f32>(79.84902, -1225.455, 3942.208, -4637.071), 1842.924);
    let c4 = sheen_poly4(q, vec4<f32>(78.02134, 17.17138, -893.0577, 1481.041), -684.1884);
    let ln_e = sheen_poly4(s, vec4<f32>(c0, c1, c2, c3), c4);
    return max(exp(ln_e) - 0.02, 0.0);
}

// What multiplies the base layer's light: 1 - max(colour) x E(N.V), in 0..1.
fn sheen_scaling(color: vec3<f32>, n_dot_v: f32, roughness: f32) -> f32 {
    let c = min(max(max(color.r, color.g), max(color.b, 0.0)), 1.0);
    return clamp(1.0 - c * sheen_albedo(n_dot_v, roughness), 0.0, 1.0);
}

// The white lobe's D V N.L from a light's cosines (N.L unclamped: <= 0 is
// no light; N.H of the half vector), times `scale` (the light's attenuation).
fn sheen_weight(n_dot_v: f32, n_dot_l_raw: f32, n_dot_h: f32, roughness: f32, scale: f32) -> f32 {
    if (!(n_dot_l_raw > 0.0)) {
        return 0.0;
    }
    let n_dot_l = min(n_dot_l_raw, 1.0);
    return d_charlie(n_dot_h, roughness) * v_neubelt(n_dot_v, n_dot_l) * n_dot_l * scale;
}
