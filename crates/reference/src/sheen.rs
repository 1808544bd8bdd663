//! The sheen lobe on the CPU (glTF's `KHR_materials_sheen`, as the Khronos
//! specification and sample viewer shade it): the "Charlie" distribution
//! (Estevez & Kulla 2017, "Production Friendly Microfacet Sheen BRDF") with
//! Neubelt's visibility term, tinted by the sheen colour, over a base layer
//! that it dims by 1 - max(sheen colour) x E(N.V), E being the lobe's
//! directional albedo. `shaders/lib/sheen.wgsl` (`spreadlight::sheen`) has
//! the same functions under the same names.
//!
//! E is an analytic fit ([`sheen_albedo`]) rather than a lookup texture, so
//! every pass that draws sheen (CookTorrance, Reflection, lit transparency)
//! computes it without another binding: ln(E + 0.02) is a polynomial of
//! degree 4 in sqrt(N.V) and sqrt(roughness), within 0.0125 of the
//! numerically integrated albedo ([`sheen_albedo_integrated`]) for roughness
//! 0.1..1 and N.V 0.01..1 (the tests hold it to that). Below roughness 0.1
//! the fit reads roughness 0.1, below N.V 0.01 it reads 0.01.

use std::f32::consts::PI;

use glam::Vec3;

use crate::brdf::MIN_COS;

/// Smallest Charlie width (alpha = roughness^2): roughness 0 stays finite.
pub const MIN_SHEEN_ALPHA: f32 = 1e-3;
/// The roughness below which [`sheen_albedo`] reads its fit at this value.
pub const SHEEN_ALBEDO_MIN_ROUGHNESS: f32 = 0.1;
/// The cosine below which [`sheen_albedo`] reads its fit at this value.
pub const SHEEN_ALBEDO_MIN_COS: f32 = 0.01;
/// The largest error of [`sheen_albedo`] against the integrated albedo over
/// roughness 0.1..1 and N.V 0.01..1.
pub const SHEEN_ALBEDO_FIT_ERROR: f32 = 0.0125;

/// The Charlie distribution D(h): (2 + 1/a) sin(h)^(1/a) / (2 pi), a = roughness^2.
pub fn d_charlie(n_dot_h: f32, roughness: f32) -> f32 {
    let r = roughness.clamp(0.0, 1.0);
    let inverse = 1.0 / (r * r).max(MIN_SHEEN_ALPHA);
    let sin2 = (1.0 - n_dot_h * n_dot_h).max(0.0);
    (2.0 + inverse) * sin2.powf(inverse * 0.5) / (2.0 * PI)
}

/// Neubelt's sheen visibility, 1 / (4 (N.L + N.V - N.L N.V)), capped at 1
/// as the sample viewer caps it (it exceeds 1 only where both cosines are small).
pub fn v_neubelt(n_dot_v: f32, n_dot_l: f32) -> f32 {
    let nv = n_dot_v.clamp(MIN_COS, 1.0);
    let nl = n_dot_l.clamp(MIN_COS, 1.0);
    (1.0 / (4.0 * (nl + nv - nl * nv))).min(1.0)
}

/// `SHEEN_ALBEDO_FIT[i][j]` multiplies sqrt(N.V)^i sqrt(roughness)^j in the
/// fit of ln(E + 0.02). Fitted (least squares, Lawson's reweighting towards
/// the smallest largest error) to the albedo integrated on a 128 x 64 grid
/// of light directions at N.V in {0.01, 0.02, 0.035, 0.05, 0.075, 0.1,
/// 0.15, ..., 1} x roughness in {0.1, 0.15, ..., 1}: largest error 0.0122,
/// RMS 0.0067.
const SHEEN_ALBEDO_FIT: [[f32; 5]; 5] = [
    [-1.713953, 19.76195, -54.17829, 54.55947, -19.04794],
    [31.6313, -240.4802, 602.4391, -615.9817, 222.8554],
    [-164.1458, 1255.803, -3229.161, 3396.535, -1262.074],
    [79.84902, -1225.455, 3942.208, -4637.071, 1842.924],
    [78.02134, 17.17138, -893.0577, 1481.041, -684.1884],
];

fn poly4(x: f32, c: [f32; 5]) -> f32 {
    (((c[4] * x + c[3]) * x + c[2]) * x + c[1]) * x + c[0]
}

/// E(N.V, roughness): the fraction of light the sheen lobe (white) reflects
/// towards `v`, integrated over light directions; the analytic fit (see the
/// module's docs for its domain and error). Never negative.
pub fn sheen_albedo(n_dot_v: f32, roughness: f32) -> f32 {
    let q = roughness.clamp(SHEEN_ALBEDO_MIN_ROUGHNESS, 1.0).sqrt();
    let s = n_dot_v.clamp(SHEEN_ALBEDO_MIN_COS, 1.0).sqrt();
    let c = SHEEN_ALBEDO_FIT;
    let ln_e = poly4(
        s,
        [
            poly4(q, c[0]),
            poly4(q, c[1]),
            poly4(q, c[2]),
            poly4(q, c[3]),
            poly4(q, c[4]),
        ],
    );
    (ln_e.exp() - 0.02).max(0.0)
}

/// E(N.V, roughness) by numerical integration over the hemisphere of light
/// directions (`steps` x `steps / 2` cells, midpoint rule in cos(theta) and
/// phi): what [`sheen_albedo`] is fitted to. For tests and `accuracy`.
pub fn sheen_albedo_integrated(n_dot_v: f32, roughness: f32, steps: u32) -> f32 {
    let mu = n_dot_v.clamp(MIN_COS, 1.0);
    let v = Vec3::new((1.0 - mu * mu).sqrt(), 0.0, mu);
    let (rows, columns) = (steps.max(2), (steps / 2).max(1));
    let mut sum = 0.0f64;
    for i in 0..rows {
        let c = (i as f32 + 0.5) / rows as f32;
        let s = (1.0 - c * c).sqrt();
        for j in 0..columns {
            // phi over 0..pi: the lobe is symmetric about the plane of n and v.
            let phi = (j as f32 + 0.5) / columns as f32 * PI;
            let l = Vec3::new(s * phi.cos(), s * phi.sin(), c);
            sum += f64::from(sheen_lobe(Vec3::Z, v, l, roughness));
        }
    }
    // d omega = d cos d phi; the half of phi counted twice.
    (sum * 2.0 * f64::from(PI) / f64::from(rows * columns)) as f32
}

/// The white sheen lobe's D V N.L for unit `n`, `v`, `l` (0 for N.L <= 0).
pub fn sheen_lobe(n: Vec3, v: Vec3, l: Vec3, roughness: f32) -> f32 {
    let n_dot_l = n.dot(l);
    if n_dot_l <= 0.0 {
        return 0.0;
    }
    let n_dot_l = n_dot_l.min(1.0);
    let h = v + l;
    let len2 = h.dot(h);
    let n_dot_h = if len2 > 1e-20 {
        n.dot(h) / len2.sqrt()
    } else {
        1.0
    };
    d_charlie(n_dot_h, roughness) * v_neubelt(n.dot(v), n_dot_l) * n_dot_l
}

/// What multiplies the base layer's light (diffuse and specular) under a
/// sheen of `color`: 1 - max(color) x E(N.V), kept within 0..1 (E exceeds 1
/// at grazing views of smooth sheens, where Neubelt's term is not energy conserving).
pub fn sheen_scaling(color: Vec3, n_dot_v: f32, roughness: f32) -> f32 {
    let c = color.max(Vec3::ZERO).max_element().min(1.0);
    (1.0 - c * sheen_albedo(n_dot_v, roughness)).clamp(0.0, 1.0)
}

/// A sheen over a surface (`shaders/lighting/cook_torrance.wgsl`, SHEEN):
/// returns (scaling, lobe); the shaded result per unit of a light's
/// radiance is base x scaling + lobe. Colour components are taken within
/// 0..1, roughness within 0..1.
pub fn sheen(n: Vec3, v: Vec3, l: Vec3, color: Vec3, roughness: f32) -> (f32, Vec3) {
    let color = color.clamp(Vec3::ZERO, Vec3::ONE);
    let roughness = roughness.clamp(0.0, 1.0);
    let scaling = sheen_scaling(color, n.dot(v), roughness);
    (scaling, color * sheen_lobe(n, v, l, roughness))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_albedo_fit_is_within_its_stated_error_of_the_integral() {
        let mut worst = 0.0f32;
        for r in [0.1, 0.25, 0.4, 0.55, 0.7, 0.85, 1.0] {
            for mu in [0.01, 0.03, 0.08, 0.2, 0.35, 0.5, 0.7, 0.9, 1.0] {
                let integrated = sheen_albedo_integrated(mu, r, 128);
                let fitted = sheen_albedo(mu, r);
                worst = worst.max((integrated - fitted).abs());
            }
        }
        assert!(worst <= SHEEN_ALBEDO_FIT_ERROR, "largest error {worst}");
        // Not a flat fit: rough sheens reflect more at grazing views than head on.
        assert!(sheen_albedo(0.05, 0.8) > 3.0 * sheen_albedo(1.0, 0.8));
    }

    #[test]
    fn the_lobe_is_a_sheen_bright_at_grazing_angles_and_finite_everywhere() {
        let n = Vec3::Z;
        // Charlie's microfibres stand along the normal: they reflect most
        // where the half vector lies flat (grazing light seen from near
        // where it comes), hardly at all seen head on.
        let oblique = Vec3::new(1.0, 0.0, 1.0).normalize();
        let head_on = sheen_lobe(n, n, oblique, 0.5);
        let grazing_v = Vec3::new(0.995, 0.0, 0.1).normalize();
        let grazing_l = Vec3::new(-0.995, 0.0, 0.1).normalize();
        assert!(sheen_lobe(n, grazing_v, grazing_v, 0.5) > 10.0 * head_on);
        assert!(head_on > 0.0);
        for r in [0.0, 1e-6, 0.5, 1.0, f32::NAN] {
            for l in [n, grazing_l, -n, Vec3::new(1.0, 0.0, 0.0)] {
                let (scaling, lobe) = sheen(n, grazing_v, l, Vec3::ONE, r);
                assert!(lobe.is_finite() && (0.0..=1.0).contains(&scaling));
            }
        }
        // No light from behind; a black sheen leaves the base alone.
        assert_eq!(sheen_lobe(n, n, -n, 0.5), 0.0);
        assert_eq!(sheen(n, n, n, Vec3::ZERO, 0.5), (1.0, Vec3::ZERO));
    }
}
