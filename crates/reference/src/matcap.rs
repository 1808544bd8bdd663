//! The CPU twin of `shaders/lib/matcap.wgsl`: where a surface looks up a
//! matcap image, and the built-in neutral matcap. Same names and maths as
//! the WGSL, so tests can say what CompositeLight's MATCAP code should show.

use glam::{Vec2, Vec3};

/// Where on the matcap image a surface looks up, from its view-space unit
/// normal `n` and the unit view vector `v` from the eye to the surface (view
/// space: +x right, +y up, the eye looking down -z). Image v grows downwards.
/// `reflected`: the view vector reflected about the normal, sphere-mapped
/// (OpenGL's `GL_SPHERE_MAP`), instead of the normal itself.
pub fn matcap_uv(n: Vec3, v: Vec3, reflected: bool) -> Vec2 {
    let mut d = n;
    if reflected {
        let r = v - 2.0 * n.dot(v) * n;
        let m = 2.0
            * (r.x * r.x + r.y * r.y + (r.z + 1.0) * (r.z + 1.0))
                .max(1e-12)
                .sqrt();
        d = Vec3::new(r.x / m * 2.0, r.y / m * 2.0, 0.0);
    }
    let x = d.x.clamp(-1.0, 1.0);
    let y = d.y.clamp(-1.0, 1.0);
    Vec2::new(0.5 + 0.5 * x, 0.5 - 0.5 * y)
}

/// The built-in matcap when a material names no image: neutral clay.
pub fn default_matcap(uv: Vec2) -> Vec3 {
    let x = uv.x * 2.0 - 1.0;
    let y = 1.0 - uv.y * 2.0;
    let n = Vec3::new(x, y, (1.0 - x * x - y * y).max(0.0).sqrt());
    let key = n.dot(Vec3::new(-0.48, 0.64, 0.6)).max(0.0);
    Vec3::splat(0.1 + 0.8 * key)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_normal_facing_the_eye_looks_up_the_centre_either_way() {
        let n = Vec3::Z;
        let v = -Vec3::Z;
        assert!((matcap_uv(n, v, false) - Vec2::splat(0.5)).length() < 1e-6);
        assert!((matcap_uv(n, v, true) - Vec2::splat(0.5)).length() < 1e-6);
    }

    #[test]
    fn normals_map_across_the_image_right_and_up() {
        let v = -Vec3::Z;
        assert!((matcap_uv(Vec3::X, v, false) - Vec2::new(1.0, 0.5)).length() < 1e-6);
        assert!((matcap_uv(Vec3::Y, v, false) - Vec2::new(0.5, 0.0)).length() < 1e-6);
        // Reflection doubles the angle: a normal 45 degrees right reflects the
        // view vector to grazing (+x), which the sphere map puts at radius
        // 1/sqrt(2) of the image's half width.
        let n = Vec3::new(1.0, 0.0, 1.0).normalize();
        let expected = Vec2::new(0.5 + 0.5 * std::f32::consts::FRAC_1_SQRT_2, 0.5);
        assert!((matcap_uv(n, v, true) - expected).length() < 1e-5);
        // Off-centre eye rays change the reflected lookup, not the normal one.
        let slanted = Vec3::new(0.3, 0.0, -1.0).normalize();
        assert_eq!(matcap_uv(Vec3::Z, slanted, false), Vec2::splat(0.5));
        assert!(matcap_uv(Vec3::Z, slanted, true).x > 0.55);
    }

    #[test]
    fn the_built_in_matcap_is_lit_from_the_upper_left() {
        let upper_left = default_matcap(Vec2::new(0.25, 0.25));
        let lower_right = default_matcap(Vec2::new(0.75, 0.75));
        assert!(upper_left.x > lower_right.x);
        assert!(default_matcap(Vec2::new(0.0, 0.0)).is_finite());
        assert!(lower_right.x >= 0.1);
    }
}
