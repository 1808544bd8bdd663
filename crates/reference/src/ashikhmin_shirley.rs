//! Ashikhmin-Shirley's anisotropic Phong BRDF on the CPU (M. Ashikhmin,
//! P. Shirley, "An Anisotropic Phong BRDF Model", 2000): what
//! `shaders/nodes/ashikhmin_shirley.wgsl`, the shipped light shader node,
//! returns for one light, and the sum over lights the light loop makes of it.

use std::f32::consts::PI;

use glam::Vec3;

pub use super::lights::ShaderLight;

/// The node's pins.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AshikhminShirleyParams {
    /// Phong exponent along the tangent (U).
    pub exponent_u: f32,
    /// Phong exponent along the bitangent (V).
    pub exponent_v: f32,
    /// Rs: the specular reflectance head on, 0..1.
    pub specular: f32,
}

fn pow5(x: f32) -> f32 {
    let x2 = x * x;
    x2 * x2 * x
}

/// The surface's U direction at unit normal `n`: the first vector of
/// Frisvad's orthonormal basis ("Building an Orthonormal Basis from a 3D
/// Unit Vector Without Normalization", 2012), continuous over every normal
/// but the one facing -Z (held at -Y there); V is `n x U`. On a floor
/// (`n` = +Y) U is +X, V is -Z.
pub fn tangent_of(n: Vec3) -> Vec3 {
    if n.z < -0.999_999_9 {
        return Vec3::NEG_Y;
    }
    let a = 1.0 / (1.0 + n.z);
    Vec3::new(1.0 - n.x * n.x * a, -n.x * n.y * a, -n.x)
}

/// (diffuse BRDF without the albedo, specular BRDF) for unit normal `n`,
/// unit vectors `l` to the light and `v` to the eye; zero when either is
/// below the surface.
pub fn ashikhmin_shirley_brdf(
    n: Vec3,
    l: Vec3,
    v: Vec3,
    params: &AshikhminShirleyParams,
) -> (f32, f32) {
    let n_dot_l = n.dot(l);
    let n_dot_v = n.dot(v);
    if n_dot_l <= 0.0 || n_dot_v <= 0.0 {
        return (0.0, 0.0);
    }
    let rs = params.specular;
    let diffuse = 28.0 / (23.0 * PI)
        * (1.0 - rs)
        * (1.0 - pow5(1.0 - 0.5 * n_dot_l))
        * (1.0 - pow5(1.0 - 0.5 * n_dot_v));
    let h = (l + v).try_normalize().unwrap_or(n);
    let t = tangent_of(n);
    let b = n.cross(t);
    let (hu, hv) = (h.dot(t), h.dot(b));
    let (nu, nv) = (params.exponent_u, params.exponent_v);
    let exponent = (nu * hu * hu + nv * hv * hv) / (hu * hu + hv * hv).max(1e-12);
    let n_dot_h = n.dot(h).clamp(0.0, 1.0);
    let h_dot_l = h.dot(l).max(1e-4);
    let fresnel = rs + (1.0 - rs) * pow5(1.0 - h_dot_l);
    let specular = ((nu + 1.0) * (nv + 1.0)).sqrt() / (8.0 * PI) * n_dot_h.powf(exponent)
        / (h_dot_l * n_dot_l.max(n_dot_v))
        * fresnel;
    (diffuse, specular)
}

/// (diffuse, specular) radiance of one light at a surface with unit normal
/// `n`, unit view vector `v` and `albedo`: the BRDF times the irradiance,
/// radiance x attenuation x shadow x N.L.
pub fn ashikhmin_shirley_light(
    n: Vec3,
    v: Vec3,
    albedo: Vec3,
    light: &ShaderLight,
    params: &AshikhminShirleyParams,
) -> (Vec3, Vec3) {
    let (diffuse, specular) = ashikhmin_shirley_brdf(n, light.direction, v, params);
    let irradiance =
        light.radiance * (light.attenuation * light.shadow * n.dot(light.direction).max(0.0));
    (albedo * irradiance * diffuse, irradiance * specular)
}

/// The light loop's sum of [`ashikhmin_shirley_light`] over `lights`.
pub fn ashikhmin_shirley_sum(
    n: Vec3,
    v: Vec3,
    albedo: Vec3,
    lights: &[ShaderLight],
    params: &AshikhminShirleyParams,
) -> (Vec3, Vec3) {
    lights.iter().fold((Vec3::ZERO, Vec3::ZERO), |(d, s), l| {
        let (dl, sl) = ashikhmin_shirley_light(n, v, albedo, l, params);
        (d + dl, s + sl)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    const ROUND: AshikhminShirleyParams = AshikhminShirleyParams {
        exponent_u: 100.0,
        exponent_v: 100.0,
        specular: 0.05,
    };
    const BRUSHED: AshikhminShirleyParams = AshikhminShirleyParams {
        exponent_u: 400.0,
        exponent_v: 10.0,
        specular: 0.05,
    };

    fn dir(x: f32, y: f32, z: f32) -> Vec3 {
        Vec3::new(x, y, z).normalize()
    }

    #[test]
    fn the_tangent_frame_is_orthonormal_and_fixed_on_a_floor() {
        assert!((tangent_of(Vec3::Y) - Vec3::X).length() < 1e-6);
        assert!((Vec3::Y.cross(tangent_of(Vec3::Y)) - Vec3::NEG_Z).length() < 1e-6);
        for n in [
            dir(0.3, -0.5, 0.8),
            dir(-0.2, 0.1, -0.97),
            Vec3::NEG_Z,
            Vec3::Z,
        ] {
            let t = tangent_of(n);
            assert!(
                (t.length() - 1.0).abs() < 1e-5 && t.dot(n).abs() < 1e-5,
                "{n} {t}"
            );
        }
    }

    #[test]
    fn the_brdf_is_reciprocal_and_finite_at_the_mirror_direction() {
        let n = Vec3::Y;
        for params in [ROUND, BRUSHED] {
            for (l, v) in [
                (dir(0.3, 1.0, 0.1), dir(-0.5, 0.7, 0.2)),
                (dir(0.9, 0.2, -0.3), dir(-0.1, 1.0, 0.4)),
            ] {
                let (d1, s1) = ashikhmin_shirley_brdf(n, l, v, &params);
                let (d2, s2) = ashikhmin_shirley_brdf(n, v, l, &params);
                assert!((d1 - d2).abs() < 1e-6 && (s1 - s2).abs() <= 1e-5 * s1.max(1e-3));
            }
            // Head on (h = n, hu = hv = 0): the peak, finite.
            let (d, s) = ashikhmin_shirley_brdf(n, n, n, &params);
            assert!(d.is_finite() && s.is_finite() && s > 0.0);
            // Peak: sqrt((nu+1)(nv+1)) / 8pi x Rs (Fresnel head on is Rs).
            let peak = ((params.exponent_u + 1.0) * (params.exponent_v + 1.0)).sqrt() / (8.0 * PI)
                * params.specular;
            assert!((s - peak).abs() < 1e-4 * peak, "{s} vs {peak}");
        }
        assert_eq!(
            ashikhmin_shirley_brdf(n, Vec3::NEG_Y, n, &ROUND),
            (0.0, 0.0)
        );
        assert_eq!(
            ashikhmin_shirley_brdf(n, n, dir(1.0, -0.1, 0.0), &ROUND),
            (0.0, 0.0)
        );
    }

    #[test]
    fn unequal_exponents_stretch_the_highlight_across_the_sharper_axis() {
        // The half vector tilted by the same angle towards U and towards V:
        // with nu >> nv the lobe is narrow along U, wide along V.
        let v = Vec3::Y;
        let tilt = 0.15f32;
        let towards_u = dir(2.0 * tilt.sin(), 1.0, 0.0);
        let towards_v = dir(0.0, 1.0, -2.0 * tilt.sin());
        let (_, along_u) = ashikhmin_shirley_brdf(Vec3::Y, towards_u, v, &BRUSHED);
        let (_, along_v) = ashikhmin_shirley_brdf(Vec3::Y, towards_v, v, &BRUSHED);
        assert!(along_v > 10.0 * along_u, "{along_u} {along_v}");
        let (_, round_u) = ashikhmin_shirley_brdf(Vec3::Y, towards_u, v, &ROUND);
        let (_, round_v) = ashikhmin_shirley_brdf(Vec3::Y, towards_v, v, &ROUND);
        assert!((round_u - round_v).abs() < 1e-5 * round_u.max(1e-6));
    }

    #[test]
    fn lights_sum_and_shadows_take_their_light_away() {
        let n = Vec3::Y;
        let v = dir(0.2, 1.0, 0.1);
        let light = |direction: Vec3, shadow: f32| ShaderLight {
            direction,
            radiance: Vec3::new(2.0, 1.0, 0.5),
            attenuation: 0.5,
            shadow,
        };
        let a = light(dir(-0.3, 1.0, 0.0), 1.0);
        let b = light(dir(0.5, 0.6, -0.2), 1.0);
        let albedo = Vec3::splat(0.8);
        let (da, sa) = ashikhmin_shirley_light(n, v, albedo, &a, &ROUND);
        let (db, sb) = ashikhmin_shirley_light(n, v, albedo, &b, &ROUND);
        let (d, s) = ashikhmin_shirley_sum(n, v, albedo, &[a, b], &ROUND);
        assert!((d - (da + db)).length() < 1e-6 && (s - (sa + sb)).length() < 1e-6);
        let (d0, s0) = ashikhmin_shirley_light(n, v, albedo, &light(a.direction, 0.0), &ROUND);
        assert_eq!((d0, s0), (Vec3::ZERO, Vec3::ZERO));
        // The diffuse lobe never gives more than Lambert's 28/23 (its maximum).
        assert!(da.x <= albedo.x * 2.0 * 0.5 * 28.0 / 23.0 / PI);
    }
}
