//! Thin-film iridescence (glTF's `KHR_materials_iridescence`): the Fresnel
//! reflectance of a dielectric film over the base surface, after Belcour &
//! Barla 2017 ("A Practical Extension to Microfacet Theory for the Modeling
//! of Varying Iridescence"), as the Khronos glTF Sample Viewer evaluates it
//! (`iridescence.glsl`: the two interfaces' Airy summation to the second
//! order, the phase shifts turned into colour through the CIE XYZ
//! sensitivity's Gaussian fit in Fourier space, then XYZ to linear Rec. 709).
//! A straight port, function by function; `shaders/lib/iridescence.wgsl`
//! (`spreadlight::iridescence`) has the same functions under the same names.
//!
//! The lobe: the film's reflectance at N.V, [`iridescence_fresnel`], takes
//! the place of Schlick's F in both the specular and the diffuse weight,
//! mixed by the iridescence factor ([`cook_torrance_iridescent`]).
//! `tools/iridescence_reference.py` runs the sample viewer's GLSL by hand
//! in double precision; its numbers are this module's tests.

use std::f32::consts::PI;

use glam::{Mat3, Vec3};

use crate::brdf::{Brdf, MIN_COS, cook_torrance_fresnel, f_schlick};

/// CIE XYZ to linear Rec. 709 (sRGB primaries, D65), by columns.
const XYZ_TO_REC709: Mat3 = Mat3::from_cols(
    Vec3::new(3.240_454_2, -0.969_266, 0.055_643_4),
    Vec3::new(-1.537_138_5, 1.876_010_8, -0.204_025_9),
    Vec3::new(-0.498_531_4, 0.041_556, 1.057_225_2),
);

/// The default index of refraction of the film (the extension's).
pub const DEFAULT_FILM_IOR: f32 = 1.3;

/// The reflectance at normal incidence of an interface from `incident` into `transmitted`.
pub fn ior_to_fresnel0(transmitted: f32, incident: f32) -> f32 {
    let r = (transmitted - incident) / (transmitted + incident);
    r * r
}

/// The index of refraction (from air) that reflects `f0` at normal incidence.
pub fn fresnel0_to_ior(f0: f32) -> f32 {
    let s = f0.sqrt();
    (1.0 + s) / (1.0 - s)
}

/// The XYZ sensitivity's Fourier transform at optical path difference
/// `opd` (nm) and phase `shift`, as linear Rec. 709: the colour of a
/// reflection whose two waves are `opd` apart.
pub fn eval_sensitivity(opd: f32, shift: Vec3) -> Vec3 {
    let phase = 2.0 * PI * opd * 1.0e-9;
    let val = Vec3::new(5.4856e-13, 4.4201e-13, 5.2481e-13);
    let pos = Vec3::new(1.6810e6, 1.7953e6, 2.2084e6);
    let var = Vec3::new(4.3278e9, 9.3046e9, 6.6121e9);
    let cosine = map(pos * phase + shift, f32::cos);
    let gauss = map(-(phase * phase) * var, f32::exp);
    let mut xyz = val * map(2.0 * PI * var, f32::sqrt) * cosine * gauss;
    xyz.x += 9.7470e-14
        * (2.0 * PI * 4.5282e9f32).sqrt()
        * (2.2399e6 * phase + shift.x).cos()
        * (-4.5282e9 * phase * phase).exp();
    XYZ_TO_REC709 * (xyz / 1.0685e-7)
}

/// The reflectance of a thin film of index `film_ior` and `thickness`
/// (nanometres) between a medium of index `outside_ior` and a base whose
/// reflectance at normal incidence is `base_f0` (per channel), seen at
/// `cos_theta1` (N.V), per Rec. 709 channel. 1 under total internal
/// reflection; a thickness near 0 fades the film's index into the
/// outside's (no film). Never negative (colours out of gamut are clamped,
/// as the sample viewer does).
pub fn eval_iridescence(
    outside_ior: f32,
    film_ior: f32,
    cos_theta1: f32,
    thickness: f32,
    base_f0: Vec3,
) -> Vec3 {
    let t = ((thickness - 0.0) / 0.03).clamp(0.0, 1.0);
    let iridescence_ior = outside_ior + (film_ior - outside_ior) * (t * t * (3.0 - 2.0 * t));
    // Snell's law into the film.
    let sin_theta2_sq = (outside_ior / iridescence_ior).powi(2) * (1.0 - cos_theta1 * cos_theta1);
    let cos_theta2_sq = 1.0 - sin_theta2_sq;
    if cos_theta2_sq < 0.0 {
        return Vec3::ONE;
    }
    let cos_theta2 = cos_theta2_sq.sqrt();
    // The first interface (outside to film).
    let r0 = ior_to_fresnel0(iridescence_ior, outside_ior);
    let r12 = schlick(r0, cos_theta1);
    let t121 = 1.0 - r12;
    let phi12 = if iridescence_ior < outside_ior {
        PI
    } else {
        0.0
    };
    let phi21 = PI - phi12;
    // The second interface (film to base).
    let base_ior = base_f0
        .clamp(Vec3::ZERO, Vec3::splat(0.9999))
        .to_array()
        .map(fresnel0_to_ior);
    let r23 =
        Vec3::from(base_ior.map(|b| schlick(ior_to_fresnel0(b, iridescence_ior), cos_theta2)));
    let phi23 = Vec3::from(base_ior.map(|b| if b < iridescence_ior { PI } else { 0.0 }));
    // The phase shift.
    let opd = 2.0 * iridescence_ior * thickness * cos_theta2;
    let phi = Vec3::splat(phi21) + phi23;
    // The compound terms.
    let r123 = (r12 * r23).clamp(Vec3::splat(1e-5), Vec3::splat(0.9999));
    let r123_root = map(r123, f32::sqrt);
    let rs = t121 * t121 * r23 / (Vec3::ONE - r123);
    // m = 0: the mean reflectance; m = 1, 2: the interference's first terms.
    let mut i = r12 + rs;
    let mut cm = rs - t121;
    for m in 1..=2 {
        cm *= r123_root;
        let m = m as f32;
        let sm = 2.0 * eval_sensitivity(m * opd, m * phi);
        i += cm * sm;
    }
    i.max(Vec3::ZERO)
}

/// `f` of each component.
fn map(v: Vec3, f: fn(f32) -> f32) -> Vec3 {
    Vec3::from(v.to_array().map(f))
}

/// Schlick's approximation with f90 1 for a scalar f0.
fn schlick(f0: f32, cos_theta: f32) -> f32 {
    f_schlick(Vec3::splat(f0), cos_theta).x
}

/// A material's film, made finite and physical: the factor 0..1, the
/// film's index at least 1 (a non-finite one: [`DEFAULT_FILM_IOR`]), the
/// thickness >= 0 nm (a non-finite one: 0, no film). A film of thickness
/// 0 has no factor (as the sample viewer has it).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Film {
    pub factor: f32,
    pub ior: f32,
    pub thickness: f32,
}

impl Film {
    pub fn new(factor: f32, ior: f32, thickness: f32) -> Self {
        let thickness = if thickness.is_finite() {
            thickness.max(0.0)
        } else {
            0.0
        };
        let factor = if factor.is_finite() && thickness > 0.0 {
            factor.clamp(0.0, 1.0)
        } else {
            0.0
        };
        let ior = if ior.is_finite() {
            ior.max(1.0)
        } else {
            DEFAULT_FILM_IOR
        };
        Film {
            factor,
            ior,
            thickness,
        }
    }
}

/// The film's Fresnel reflectance at N.V over a metal-rough surface: the
/// film over the dielectric base (f0 `reflectance`) and over the metal
/// (f0 the albedo), mixed by metallic as the base's F0 is; kept within 0..1.
pub fn iridescence_fresnel(
    reflectance: f32,
    albedo: Vec3,
    metallic: f32,
    n_dot_v: f32,
    film_ior: f32,
    thickness: f32,
) -> Vec3 {
    let cos = n_dot_v.clamp(MIN_COS, 1.0);
    let dielectric = eval_iridescence(
        1.0,
        film_ior,
        cos,
        thickness,
        Vec3::splat(reflectance.clamp(0.0, 1.0)),
    );
    let metal = eval_iridescence(1.0, film_ior, cos, thickness, albedo.max(Vec3::ZERO));
    dielectric
        .lerp(metal, metallic.clamp(0.0, 1.0))
        .clamp(Vec3::ZERO, Vec3::ONE)
}

/// `brdf::cook_torrance_f0` with a film: F = mix(Schlick's F at V.H,
/// the film's reflectance at N.V, factor) in the specular lobe and in the
/// diffuse's (1 - F). The energy compensation keeps the base's F0.
#[allow(clippy::too_many_arguments)]
pub fn cook_torrance_iridescent(
    n: Vec3,
    v: Vec3,
    l: Vec3,
    albedo: Vec3,
    roughness: f32,
    metallic: f32,
    reflectance: f32,
    film: Film,
    compensate: bool,
) -> Brdf {
    // Clamped here as the lobe clamps them (idempotent), for the film's F.
    let metallic = metallic.clamp(0.0, 1.0);
    let albedo = albedo.max(Vec3::ZERO);
    cook_torrance_fresnel(
        n,
        v,
        l,
        albedo,
        roughness,
        metallic,
        reflectance,
        compensate,
        |f0, v_dot_h, n_dot_v| {
            let film_f = iridescence_fresnel(
                reflectance,
                albedo,
                metallic,
                n_dot_v,
                film.ior,
                film.thickness,
            );
            f_schlick(f0, v_dot_h).lerp(film_f, film.factor)
        },
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::brdf::cook_torrance_f0;

    /// (film ior, cos theta1, thickness nm, base f0, reflectance).
    type Case = (f32, f32, f32, [f32; 3], [f32; 3]);

    /// `tools/iridescence_reference.py` (the sample viewer's GLSL run by
    /// hand in double precision): (film ior, cos theta1, thickness nm,
    /// base f0) -> reflectance, pasted from its output.
    const PYTHON: [Case; 8] = [
        (
            1.3,
            1.0,
            400.0,
            [0.04; 3],
            [0.0074565, 0.0383517, 0.0160382],
        ),
        (
            1.3,
            0.5,
            400.0,
            [0.04; 3],
            [0.0608344, 0.0228908, 0.0505085],
        ),
        (
            1.3,
            1.0,
            250.0,
            [0.04; 3],
            [0.0479931, 0.0268589, 0.0049179],
        ),
        (
            1.33,
            0.8,
            100.0,
            [0.02; 3],
            [0.0255891, 0.0258561, 0.0259334],
        ),
        (
            1.5,
            0.3,
            600.0,
            [0.9, 0.6, 0.3],
            [0.851982, 0.3115119, 0.463056],
        ),
        (
            1.3,
            0.05,
            400.0,
            [0.04; 3],
            [0.8326797, 0.7849511, 0.7358476],
        ),
        (1.3, 1.0, 10.0, [0.04; 3], [0.0430404, 0.0383185, 0.0372864]),
        (
            1.8,
            0.7,
            1200.0,
            [0.04, 0.5, 0.99],
            [0.0940726, 0.319958, 0.9821176],
        ),
    ];

    #[test]
    fn the_film_matches_the_sample_viewer_run_by_hand() {
        for (ior, cos, thickness, f0, want) in PYTHON {
            let got = eval_iridescence(1.0, ior, cos, thickness, Vec3::from(f0));
            for c in 0..3 {
                // f32 against f64: the phase (about 2e-2 rad per nm of
                // thickness) loses a few ulps, well inside 1e-4.
                assert!(
                    (got[c] - want[c]).abs() <= 1e-4 + 1e-4 * want[c],
                    "ior {ior}, cos {cos}, {thickness} nm, f0 {f0:?}: {got} against {want:?}"
                );
            }
        }
    }

    #[test]
    fn a_thick_film_is_grey_and_a_thin_one_colours() {
        // A thick film (20 um) has no colour: the sensitivity's Gaussians
        // vanish and what is left is the incoherent sum of the two
        // interfaces' reflections, R12 + T121^2 R23 / (1 - R12 R23), grey.
        for cos in [1.0f32, 0.6, 0.2] {
            let got = eval_iridescence(1.0, 1.3, cos, 20_000.0, Vec3::splat(0.04));
            let r12 = schlick(ior_to_fresnel0(1.3, 1.0), cos);
            let cos2 = (1.0 - (1.0 - cos * cos) / (1.3 * 1.3)).sqrt();
            let r23 = schlick(ior_to_fresnel0(fresnel0_to_ior(0.04), 1.3), cos2);
            let want = r12 + (1.0 - r12).powi(2) * r23 / (1.0 - r12 * r23);
            assert!(
                (got - Vec3::splat(want)).abs().max_element() < 1e-5,
                "{got} {want}"
            );
        }
        // A soap film at 400 nm is green at normal incidence (the sample
        // viewer's): green above red and blue.
        let soap = eval_iridescence(1.0, 1.3, 1.0, 400.0, Vec3::splat(0.04));
        assert!(soap.y > soap.x && soap.y > soap.z, "{soap}");
        // Total internal reflection (a film below the outside's index at a
        // grazing angle) reflects all.
        assert_eq!(
            eval_iridescence(1.5, 1.0, 0.1, 300.0, Vec3::splat(0.04)),
            Vec3::ONE
        );
    }

    #[test]
    fn hard_films_stay_finite() {
        for thickness in [0.0, 1e-6, 1e6, 1e30, f32::MAX] {
            for ior in [1.0, 1.3, 3.0, 1e30] {
                for cos in [0.0, MIN_COS, 0.5, 1.0] {
                    for f0 in [0.0, 0.04, 1.0] {
                        let r = eval_iridescence(1.0, ior, cos, thickness, Vec3::splat(f0));
                        assert!(
                            r.is_finite() && r.min_element() >= 0.0,
                            "{thickness} {ior} {cos} {f0}: {r}"
                        );
                    }
                }
            }
        }
        let film = Film::new(f32::NAN, f32::INFINITY, f32::NAN);
        assert_eq!(
            film,
            Film {
                factor: 0.0,
                ior: DEFAULT_FILM_IOR,
                thickness: 0.0
            }
        );
        assert_eq!(
            Film::new(2.0, 0.5, 300.0),
            Film {
                factor: 1.0,
                ior: 1.0,
                thickness: 300.0
            }
        );
        assert_eq!(Film::new(1.0, 1.3, 0.0).factor, 0.0);
    }

    #[test]
    fn factor_zero_is_cook_torrance_and_factor_one_replaces_f() {
        let n = Vec3::Z;
        let v = Vec3::new(0.3, 0.0, 1.0).normalize();
        let l = Vec3::new(-0.5, 0.2, 1.0).normalize();
        let albedo = Vec3::new(0.8, 0.5, 0.2);
        for metallic in [0.0, 0.5, 1.0] {
            let plain = cook_torrance_f0(n, v, l, albedo, 0.4, metallic, 0.04, true);
            let off = cook_torrance_iridescent(
                n,
                v,
                l,
                albedo,
                0.4,
                metallic,
                0.04,
                Film::new(0.0, 1.3, 400.0),
                true,
            );
            assert!((plain.specular - off.specular).abs().max_element() < 1e-7);
            assert!((plain.diffuse - off.diffuse).abs().max_element() < 1e-7);
            let on = cook_torrance_iridescent(
                n,
                v,
                l,
                albedo,
                0.4,
                metallic,
                0.04,
                Film::new(1.0, 1.3, 400.0),
                false,
            );
            let film = iridescence_fresnel(0.04, albedo, metallic, n.dot(v), 1.3, 400.0);
            let bare = cook_torrance_f0(n, v, l, Vec3::ZERO, 0.4, 0.0, 1.0, false);
            // F = 1 gives the lobe alone: the film's lobe is it times the film's F.
            assert!(
                (on.specular - film * bare.specular).abs().max_element() < 1e-6,
                "{metallic}"
            );
        }
    }
}
