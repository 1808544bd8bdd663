//! A surface point's material shaded on the CPU: what the G-buffer
//! resolve's Cook-Torrance gives a surface lit by the sun. The material's
//! inputs at the point are sampled by the renderer's own point sampler of
//! glTF materials (`spreadlight_render::material::point_sample`), which
//! knows the imported material's types; this half is pure maths.
//! `spreadlight accuracy gltf` uses both as the reference of the GPU's image.

use glam::Vec3;

/// A material's inputs to shading at one surface point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceSample {
    /// Linear RGB albedo (base colour).
    pub albedo: Vec3,
    pub alpha: f32,
    pub roughness: f32,
    pub metallic: f32,
}

/// The radiance towards `view` (unit, surface to eye) of `surface` with
/// normal `normal`, lit by a sun travelling along `travel` with radiance
/// `radiance` (colour x illuminance): Cook-Torrance (diffuse + specular),
/// dielectric F0 0.04, with the multiple-scattering compensation when
/// `compensate` (CookTorrance's Energy Compensation).
pub fn shade_sun(
    surface: &SurfaceSample,
    normal: Vec3,
    view: Vec3,
    travel: Vec3,
    radiance: Vec3,
    compensate: bool,
) -> Vec3 {
    let brdf = crate::brdf::cook_torrance(
        normal,
        view,
        -travel.normalize_or(Vec3::NEG_Y),
        surface.albedo,
        surface.roughness,
        surface.metallic,
        compensate,
    );
    (brdf.diffuse + brdf.specular) * radiance
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_sun_behind_the_surface_gives_nothing_and_one_in_front_light() {
        let s = SurfaceSample {
            albedo: Vec3::splat(0.5),
            alpha: 1.0,
            roughness: 0.5,
            metallic: 0.0,
        };
        let lit = shade_sun(&s, Vec3::Y, Vec3::Y, Vec3::NEG_Y, Vec3::ONE, true);
        assert!(lit.x > 0.1 && lit.is_finite(), "{lit}");
        let dark = shade_sun(&s, Vec3::Y, Vec3::Y, Vec3::Y, Vec3::ONE, true);
        assert_eq!(dark, Vec3::ZERO);
    }
}
