//! The Cook-Torrance BRDF on the CPU: the GGX distribution, height-correlated
//! Smith visibility, Schlick Fresnel, Lambert diffuse, and the
//! multiple-scattering energy compensation with its fitted specular albedo.
//! `shaders/lib/brdf.wgsl` (`spreadlight::brdf`) has the same functions under
//! the same names; `tests/shader_reference.rs` runs both on the same inputs.
//!
//! Roughness is perceptual roughness `r` in 0..1; the GGX width is
//! `alpha = r * r`, never below [`MIN_ALPHA`], so a perfect mirror
//! (roughness 0) stays finite. Cosines are clamped: N.L <= 0 gives no light,
//! a back-facing view (N.V <= 0, common with normal maps) is treated as
//! grazing ([`MIN_COS`]), never NaN.

use std::f32::consts::PI;

use glam::Vec3;

/// Smallest GGX alpha (= roughness^2): roughness 0 must not divide by zero.
pub const MIN_ALPHA: f32 = 1e-3;
/// Smallest N.V and N.L the visibility term sees, so grazing angles stay finite.
pub const MIN_COS: f32 = 1e-4;
/// The reflectance of dielectrics at normal incidence (4%, IOR 1.5).
pub const DIELECTRIC_F0: f32 = 0.04;

/// What one light contributes, as factors of its incoming radiance (N.L included).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Brdf {
    pub diffuse: Vec3,
    pub specular: Vec3,
}

/// GGX alpha from perceptual roughness, clamped to [`MIN_ALPHA`].
pub fn roughness_to_alpha(roughness: f32) -> f32 {
    let r = roughness.clamp(0.0, 1.0);
    (r * r).max(MIN_ALPHA)
}

/// The GGX (Trowbridge-Reitz) normal distribution D(h).
pub fn d_ggx(n_dot_h: f32, roughness: f32) -> f32 {
    let a = roughness_to_alpha(roughness);
    let a2 = a * a;
    let nh = n_dot_h.clamp(0.0, 1.0);
    // 1 - nh^2 as (1 - nh)(1 + nh): next to the peak of a sharp lobe, where
    // nh^2 (a2 - 1) + 1 would cancel catastrophically, it keeps its digits.
    let f = (1.0 - nh) * (1.0 + nh) + nh * nh * a2;
    a2 / (PI * f * f)
}

/// Height-correlated Smith visibility (Heitz 2014, in Filament's form):
/// G2 / (4 N.L N.V), so the specular lobe is `D * V * F`.
pub fn v_smith_ggx_correlated(n_dot_v: f32, n_dot_l: f32, roughness: f32) -> f32 {
    let a = roughness_to_alpha(roughness);
    let a2 = a * a;
    let nv = n_dot_v.clamp(MIN_COS, 1.0);
    let nl = n_dot_l.clamp(MIN_COS, 1.0);
    let lambda_v = nl * (nv * nv * (1.0 - a2) + a2).sqrt();
    let lambda_l = nv * (nl * nl * (1.0 - a2) + a2).sqrt();
    0.5 / (lambda_v + lambda_l)
}

/// Schlick's Fresnel approximation, reflectance `f0` at normal incidence.
pub fn f_schlick(f0: Vec3, v_dot_h: f32) -> Vec3 {
    let x = 1.0 - v_dot_h.clamp(0.0, 1.0);
    let x2 = x * x;
    f0 + (Vec3::ONE - f0) * (x2 * x2 * x)
}

/// Lambert's diffuse BRDF for white albedo: 1 / pi.
pub fn diffuse_lambert() -> f32 {
    1.0 / PI
}

/// `SPECULAR_ALBEDO_FIT[i]` are the coefficients of r^0..r^4 that multiply
/// s^i in the fit of ln E_ss (see [`specular_albedo`]). Fitted (minimax
/// relative error, Lawson's iteratively reweighted least squares) to the
/// directional albedo of this module's GGX lobe with F = 1, integrated
/// numerically on N.V in {0.002, 0.005, 0.01, 0.015, 0.02, 0.025, 0.05, ..., 1}
/// x roughness in {0, 0.025, ..., 1} with 2048 visible-normal samples each.
/// Maximum relative error of E_ss on that grid: 1.03%.
const SPECULAR_ALBEDO_FIT: [[f32; 5]; 5] = [
    [0.1079475, -0.639055, 1.637571, -1.833237, 0.7098608],
    [-1.615846, 7.462202, -21.4432, 26.51882, -13.93525],
    [5.613205, -28.53082, 93.49193, -131.1957, 65.84242],
    [-8.25543, 39.95344, -142.8702, 215.3067, -109.894],
    [4.162487, -18.68436, 72.00439, -114.627, 59.542],
];

/// c0 + c1 x + c2 x^2 + c3 x^3 + c4 x^4, by Horner's rule.
fn poly4(x: f32, c: [f32; 5]) -> f32 {
    (((c[4] * x + c[3]) * x + c[2]) * x + c[1]) * x + c[0]
}

/// E_ss: the directional albedo of the single-scattering specular lobe with
/// F = 1 (the fraction of light a white metal reflects in one bounce), as an
/// analytic fit: ln E_ss is a polynomial of degree 4 in roughness and in
/// s = N.V / sqrt(N.V^2 (1 - a^2) + a^2) (a = alpha), the term of the
/// visibility function, which puts the dip of E_ss at grazing angles for
/// smooth surfaces where a polynomial in N.V could not follow it.
pub fn specular_albedo(n_dot_v: f32, roughness: f32) -> f32 {
    let r = roughness.clamp(0.0, 1.0);
    let a = roughness_to_alpha(r);
    let a2 = a * a;
    let nv = n_dot_v.clamp(MIN_COS, 1.0);
    let s = nv / (nv * nv * (1.0 - a2) + a2).sqrt();
    let c = SPECULAR_ALBEDO_FIT;
    let ln_e = poly4(
        s,
        [
            poly4(r, c[0]),
            poly4(r, c[1]),
            poly4(r, c[2]),
            poly4(r, c[3]),
            poly4(r, c[4]),
        ],
    );
    ln_e.exp().min(1.0)
}

/// Multiple-scattering compensation (Kulla & Conty 2017, in Filament's
/// form): the single-scattering lobe loses 1 - E_ss of the energy, which
/// further bounces would have reflected, tinted by `f0`. Multiply the
/// specular term by this.
pub fn energy_compensation(f0: Vec3, n_dot_v: f32, roughness: f32) -> Vec3 {
    Vec3::ONE + f0 * (1.0 / specular_albedo(n_dot_v, roughness) - 1.0)
}

/// `v` normalised, or `fallback` where it has no direction (like `safe_normalize` in `spreadlight::packing`).
pub fn safe_normalize(v: Vec3, fallback: Vec3) -> Vec3 {
    let len2 = v.dot(v);
    if len2 > 1e-20 {
        v / len2.sqrt()
    } else {
        fallback
    }
}

/// The Cook-Torrance BRDF for unit vectors `n` (normal), `v` (to the eye) and
/// `l` (to the light), times N.L: multiply both terms by the light's
/// radiance. Metalness workflow: F0 = mix(0.04, albedo, metallic), diffuse
/// (1 - F)(1 - metallic) albedo / pi. `compensate` adds the
/// multiple-scattering energy that the single-scattering lobe loses at high
/// roughness ([`energy_compensation`]).
pub fn cook_torrance(
    n: Vec3,
    v: Vec3,
    l: Vec3,
    albedo: Vec3,
    roughness: f32,
    metallic: f32,
    compensate: bool,
) -> Brdf {
    cook_torrance_f0(
        n,
        v,
        l,
        albedo,
        roughness,
        metallic,
        DIELECTRIC_F0,
        compensate,
    )
}

/// [`cook_torrance`] with the dielectric part's F0 given (a material's
/// Reflectance, 0..1): F0 = mix(reflectance, albedo, metallic).
#[allow(clippy::too_many_arguments)]
pub fn cook_torrance_f0(
    n: Vec3,
    v: Vec3,
    l: Vec3,
    albedo: Vec3,
    roughness: f32,
    metallic: f32,
    reflectance: f32,
    compensate: bool,
) -> Brdf {
    cook_torrance_fresnel(
        n,
        v,
        l,
        albedo,
        roughness,
        metallic,
        reflectance,
        compensate,
        |f0, v_dot_h, _| f_schlick(f0, v_dot_h),
    )
}

/// [`cook_torrance_f0`] with its Fresnel term given: `fresnel(f0, V.H,
/// N.V)` (Schlick's for the plain lobe; a thin film's mixed in for
/// `iridescence::cook_torrance_iridescent`), in the specular lobe and the
/// diffuse's (1 - F). The energy compensation keeps the base's F0.
#[allow(clippy::too_many_arguments)]
pub(crate) fn cook_torrance_fresnel(
    n: Vec3,
    v: Vec3,
    l: Vec3,
    albedo: Vec3,
    roughness: f32,
    metallic: f32,
    reflectance: f32,
    compensate: bool,
    fresnel: impl Fn(Vec3, f32, f32) -> Vec3,
) -> Brdf {
    let n_dot_l = n.dot(l);
    if n_dot_l <= 0.0 {
        return Brdf::default();
    }
    let n_dot_l = n_dot_l.min(1.0);
    let n_dot_v = n.dot(v).clamp(MIN_COS, 1.0);
    let h = safe_normalize(v + l, n);
    let roughness = roughness.clamp(0.0, 1.0);
    let metallic = metallic.clamp(0.0, 1.0);
    let albedo = albedo.max(Vec3::ZERO);
    let f0 = Vec3::splat(reflectance.clamp(0.0, 1.0)).lerp(albedo, metallic);
    let f = fresnel(f0, v.dot(h), n_dot_v);
    let lobe = d_ggx(n.dot(h), roughness) * v_smith_ggx_correlated(n_dot_v, n_dot_l, roughness);
    let mut specular = f * (lobe * n_dot_l);
    if compensate {
        specular *= energy_compensation(f0, n_dot_v, roughness);
    }
    let diffuse = (Vec3::ONE - f) * (1.0 - metallic) * albedo * (diffuse_lambert() * n_dot_l);
    Brdf { diffuse, specular }
}

/// A clear coat over a surface (glTF's `KHR_materials_clearcoat`, as the
/// Khronos sample viewer shades it; `shaders/lighting/cook_torrance.wgsl`,
/// CLEARCOAT): the coat's GGX lobe (f0 0.04, Schlick Fresnel at V.H) times
/// N.L, and the factor the base's diffuse and specular are multiplied by,
/// 1 - factor x F_coat(N.V). Returns (dim, lobe); the shaded result is
/// base x dim + factor x lobe, per unit of the light's radiance.
pub fn clearcoat(n: Vec3, v: Vec3, l: Vec3, factor: f32, roughness: f32) -> (f32, f32) {
    let factor = factor.clamp(0.0, 1.0);
    let n_dot_v = n.dot(v).clamp(MIN_COS, 1.0);
    let dim = 1.0 - factor * f_schlick(Vec3::splat(DIELECTRIC_F0), n_dot_v).x;
    let n_dot_l = n.dot(l);
    if n_dot_l <= 0.0 {
        return (dim, 0.0);
    }
    let n_dot_l = n_dot_l.min(1.0);
    let h = safe_normalize(v + l, n);
    let roughness = roughness.clamp(0.0, 1.0);
    let f = f_schlick(Vec3::splat(DIELECTRIC_F0), v.dot(h)).x;
    let lobe = d_ggx(n.dot(h), roughness) * v_smith_ggx_correlated(n_dot_v, n_dot_l, roughness);
    (dim, f * lobe * n_dot_l)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Point `i` of an `n`-point Hammersley set: deterministic, well spread.
    fn hammersley(i: u32, n: u32) -> (f32, f32) {
        (
            (i as f32 + 0.5) / n as f32,
            i.reverse_bits() as f32 * (1.0 / 4_294_967_296.0),
        )
    }

    /// A GGX microfacet normal visible from `v` (normal +Z): Heitz 2018,
    /// "Sampling the GGX Distribution of Visible Normals".
    fn sample_vndf(v: Vec3, alpha: f32, (u1, u2): (f32, f32)) -> Vec3 {
        let vh = Vec3::new(alpha * v.x, alpha * v.y, v.z).normalize();
        let len2 = vh.x * vh.x + vh.y * vh.y;
        let t1 = if len2 > 0.0 {
            Vec3::new(-vh.y, vh.x, 0.0) / len2.sqrt()
        } else {
            Vec3::X
        };
        let t2 = vh.cross(t1);
        let r = u1.sqrt();
        let phi = 2.0 * PI * u2;
        let p1 = r * phi.cos();
        let s = 0.5 * (1.0 + vh.z);
        let p2 = (1.0 - s) * (1.0 - p1 * p1).sqrt() + s * r * phi.sin();
        let nh = p1 * t1 + p2 * t2 + (1.0 - p1 * p1 - p2 * p2).max(0.0).sqrt() * vh;
        Vec3::new(alpha * nh.x, alpha * nh.y, nh.z.max(0.0)).normalize()
    }

    /// Smith's masking G1(v) for GGX.
    fn g1(n_dot_v: f32, alpha: f32) -> f32 {
        let a2 = alpha * alpha;
        2.0 * n_dot_v / (n_dot_v + (n_dot_v * n_dot_v * (1.0 - a2) + a2).sqrt())
    }

    /// The directional albedo of `cook_torrance`'s specular term for a white
    /// metal (F0 = 1, so F = 1): the integral of specular over the
    /// hemisphere of light directions, importance-sampled with visible
    /// normals (pdf of l = G1(v) D(h) / (4 N.V)).
    fn directional_albedo(n_dot_v: f32, roughness: f32, compensate: bool, samples: u32) -> f32 {
        let n = Vec3::Z;
        let v = Vec3::new((1.0 - n_dot_v * n_dot_v).sqrt(), 0.0, n_dot_v);
        let alpha = roughness_to_alpha(roughness);
        let mut sum = 0.0f64;
        for i in 0..samples {
            let h = sample_vndf(v, alpha, hammersley(i, samples));
            let l = 2.0 * v.dot(h) * h - v;
            if l.z <= 0.0 {
                continue;
            }
            let brdf = cook_torrance(n, v, l, Vec3::ONE, roughness, 1.0, compensate);
            // D from the half vector exactly as cook_torrance rebuilds it, so
            // that D cancels bit for bit even where it is very sharp.
            let h_used = (v + l) / (v + l).dot(v + l).sqrt();
            let pdf = g1(n_dot_v, alpha) * d_ggx(h_used.z, roughness) / (4.0 * n_dot_v);
            sum += f64::from(brdf.specular.x / pdf);
        }
        (sum / f64::from(samples)) as f32
    }

    /// (min E without compensation, max |E - 1| with it, max |fit / E - 1|)
    /// over roughness and N.V in 0.05..=1 in steps of 0.05.
    fn furnace(samples: u32) -> (f32, f32, f32) {
        let (mut min_plain, mut max_residual, mut max_fit_error) = (f32::MAX, 0.0f32, 0.0f32);
        for ri in 1..=20 {
            let roughness = ri as f32 * 0.05;
            for vi in 1..=20 {
                let n_dot_v = vi as f32 * 0.05;
                let plain = directional_albedo(n_dot_v, roughness, false, samples);
                let compensated = directional_albedo(n_dot_v, roughness, true, samples);
                assert!(
                    plain <= 1.0 + 1e-3,
                    "roughness {roughness}, N.V {n_dot_v}: albedo {plain} > 1"
                );
                min_plain = min_plain.min(plain);
                max_residual = max_residual.max((compensated - 1.0).abs());
                let fit = specular_albedo(n_dot_v, roughness);
                max_fit_error = max_fit_error.max((fit / plain - 1.0).abs());
            }
        }
        (min_plain, max_residual, max_fit_error)
    }

    /// The white furnace: a white metal under uniform white light reflects at
    /// most all of it. Measured over roughness x N.V in 0.05..=1 (steps of
    /// 0.05, 4096 samples per cell): without compensation the lobe keeps
    /// between 30.7% and 100% of the energy (the largest loss, 69.3%, at
    /// roughness 1 and N.V 1); with compensation every cell is within 1.02%
    /// of 1, which is the error of the E_ss fit (at most 1.03% here).
    #[test]
    fn white_furnace_conserves_and_compensation_restores_energy() {
        let (min_plain, max_residual, max_fit_error) = furnace(4096);
        eprintln!(
            "furnace: max loss without compensation {:.4}, max |E - 1| with it {:.4}, max fit error {:.4}",
            1.0 - min_plain,
            max_residual,
            max_fit_error
        );
        assert!(min_plain > 0.25 && min_plain < 0.35, "{min_plain}");
        assert!(max_fit_error < 0.02, "E_ss fit off by {max_fit_error}");
        assert!(
            max_residual < 0.02,
            "compensated albedo off by {max_residual}"
        );
    }

    /// The visible-normal sampler against a plain grid over the hemisphere
    /// (no importance sampling), where the lobe is wide enough for a grid.
    #[test]
    fn importance_sampling_agrees_with_a_plain_grid() {
        for (n_dot_v, roughness) in [(0.9, 0.5), (0.3, 0.7), (1.0, 1.0), (0.1, 1.0)] {
            let n = Vec3::Z;
            let v = Vec3::new((1.0f32 - n_dot_v * n_dot_v).sqrt(), 0.0, n_dot_v);
            let (rows, cols) = (512, 1024);
            let mut sum = 0.0f64;
            for i in 0..rows {
                let cos_theta = (i as f32 + 0.5) / rows as f32;
                let sin_theta = (1.0 - cos_theta * cos_theta).sqrt();
                for j in 0..cols {
                    let phi = 2.0 * PI * (j as f32 + 0.5) / cols as f32;
                    let l = Vec3::new(sin_theta * phi.cos(), sin_theta * phi.sin(), cos_theta);
                    let brdf = cook_torrance(n, v, l, Vec3::ONE, roughness, 1.0, false);
                    sum += f64::from(brdf.specular.x);
                }
            }
            // Each cell is d(cos theta) d(phi) of solid angle.
            let grid = (sum * 2.0 * std::f64::consts::PI / f64::from(rows * cols)) as f32;
            let sampled = directional_albedo(n_dot_v, roughness, false, 4096);
            assert!(
                (grid - sampled).abs() < 2e-3,
                "N.V {n_dot_v}, roughness {roughness}: grid {grid}, sampled {sampled}"
            );
        }
    }

    #[test]
    fn roughness_zero_and_one_stay_finite() {
        for roughness in [0.0, 1e-4, 1.0] {
            for n_dot_v in [0.0, 1e-6, 0.05, 1.0] {
                let e = specular_albedo(n_dot_v, roughness);
                assert!(e.is_finite() && e > 0.0 && e <= 1.0, "{e}");
                let c = energy_compensation(Vec3::ONE, n_dot_v, roughness);
                assert!(c.is_finite() && c.min_element() >= 1.0, "{c}");
            }
            for cos in [0.0, 1e-6, 0.5, 1.0] {
                assert!(d_ggx(cos, roughness).is_finite());
                assert!(v_smith_ggx_correlated(cos, cos, roughness).is_finite());
                assert!(v_smith_ggx_correlated(cos, 1.0, roughness).is_finite());
            }
        }
        // The mirror's peak is tall but finite: 1 / (pi alpha^2).
        assert!((d_ggx(1.0, 0.0) - 1.0 / (PI * MIN_ALPHA * MIN_ALPHA)).abs() < 1.0);
    }

    #[test]
    fn cook_torrance_is_finite_and_non_negative_everywhere() {
        let n = Vec3::Z;
        let dirs = [
            Vec3::Z,
            Vec3::new(0.6, 0.0, 0.8),
            Vec3::new(-0.6, 0.0, 0.8),
            Vec3::new(1.0, 0.0, 1e-6).normalize(),
            Vec3::X,
            Vec3::new(0.0, 0.6, -0.8),
            -Vec3::Z,
        ];
        for &v in &dirs {
            for &l in &dirs {
                for roughness in [0.0, 0.05, 0.5, 1.0] {
                    for metallic in [0.0, 0.5, 1.0] {
                        for albedo in [Vec3::ZERO, Vec3::new(0.9, 0.5, 0.1), Vec3::ONE] {
                            for compensate in [false, true] {
                                let b =
                                    cook_torrance(n, v, l, albedo, roughness, metallic, compensate);
                                for x in b
                                    .diffuse
                                    .to_array()
                                    .into_iter()
                                    .chain(b.specular.to_array())
                                {
                                    assert!(
                                        x.is_finite() && x >= 0.0,
                                        "v {v} l {l} r {roughness} m {metallic}: {b:?}"
                                    );
                                }
                                if n.dot(l) <= 0.0 {
                                    assert_eq!(b, Brdf::default());
                                }
                            }
                        }
                    }
                }
            }
        }
        // l = -v: the half vector has no direction and falls back to n.
        let v = Vec3::new(0.6, 0.0, -0.8);
        let b = cook_torrance(n, v, -v, Vec3::ONE, 0.0, 1.0, true);
        assert!(b.specular.is_finite());
    }

    #[test]
    fn metals_have_no_diffuse_and_dielectrics_reflect_four_percent() {
        let n = Vec3::Z;
        let metal = cook_torrance(n, n, n, Vec3::ONE, 0.5, 1.0, false);
        assert_eq!(metal.diffuse, Vec3::ZERO);
        assert!((f_schlick(Vec3::splat(DIELECTRIC_F0), 1.0) - Vec3::splat(0.04)).length() < 1e-7);
        assert!((f_schlick(Vec3::splat(0.04), 0.0) - Vec3::ONE).length() < 1e-6);
        let plastic = cook_torrance(n, n, n, Vec3::ONE, 0.5, 0.0, false);
        assert!((plastic.diffuse.x - 0.96 / PI).abs() < 1e-6);
        assert!((diffuse_lambert() * PI - 1.0).abs() < 1e-7);
    }
}
