//! Refraction on the CPU: the ground truth lit transparency's screen-space
//! transmission (`post/transparency.wgsl`, TRANSMISSION) is measured
//! against (`crates/render/tests/transparency.rs`, `spreadlight accuracy
//! transmission`). A ray through a glass slab: bent by Snell's law at the
//! entry face, `thickness` deep, leaving parallel to where it came from
//! (the slab's faces are parallel), absorbed by Beer-Lambert over the path
//! inside; then traced to the opaque scene behind. Exact where the screen-
//! space pass approximates (it finds the scene behind through the depth
//! buffer and sees only what is on screen).

use glam::Vec3;

/// `incident` (unit, towards the surface) refracted through a surface of
/// unit normal `n` (facing the incident ray's origin) from index 1 into
/// index `ior`: Snell's law, n1 sin θ1 = n2 sin θ2. `None` for total
/// internal reflection (only below 1). An ior that is not a positive
/// finite number is 1 (the ray goes straight on), as the shader takes it.
pub fn refract(incident: Vec3, n: Vec3, ior: f32) -> Option<Vec3> {
    let ior = if ior.is_finite() && ior > 0.0 {
        ior
    } else {
        1.0
    };
    let eta = 1.0 / ior;
    let cos_i = -incident.dot(n);
    let k = 1.0 - eta * eta * (1.0 - cos_i * cos_i);
    (k >= 0.0).then(|| incident * eta + n * (eta * cos_i - k.sqrt()))
}

/// Where a ray that meets a slab `thickness` deep at `entry` (unit normal
/// `n` facing the ray's origin, index `ior`) leaves it, and the path it
/// travelled inside: along the refracted ray, thickness / cos θ2 (held at
/// thickness / 0.05 at grazing, as the shader holds it). It then goes on
/// along `incident`. Total internal reflection goes straight through.
pub fn slab_exit(entry: Vec3, incident: Vec3, n: Vec3, ior: f32, thickness: f32) -> (Vec3, f32) {
    let thickness = if thickness.is_finite() {
        thickness.max(0.0)
    } else {
        0.0
    };
    let r = refract(incident, n, ior).unwrap_or(incident);
    let path = thickness / (-n.dot(r)).max(0.05);
    (entry + r * path, path)
}

/// How much of each channel is left after `path` through a medium of
/// absorption coefficients `sigma` (1 / length): exp(-σ path), in 0..=1.
pub fn beer_lambert(sigma: Vec3, path: f32) -> Vec3 {
    let f = |s: f32| {
        let x = s.max(0.0) * path.max(0.0);
        if x.is_finite() { (-x).exp() } else { 0.0 }
    };
    Vec3::new(f(sigma.x), f(sigma.y), f(sigma.z))
}

/// Where the ray from `origin` along `dir` meets the plane through `point`
/// with normal `normal`; `None` when it runs parallel or away from it.
pub fn hit_plane(origin: Vec3, dir: Vec3, point: Vec3, normal: Vec3) -> Option<Vec3> {
    let denom = dir.dot(normal);
    if denom.abs() < 1e-9 {
        return None;
    }
    let t = (point - origin).dot(normal) / denom;
    (t > 0.0).then(|| origin + dir * t)
}

/// The point on the opaque plane (`back`, `back_normal`) that a ray seen
/// through a slab at `entry` (normal `n`, `ior`, `thickness`) reaches, and
/// the path inside: `slab_exit`, then on along `incident`.
pub fn through_slab(
    entry: Vec3,
    incident: Vec3,
    n: Vec3,
    ior: f32,
    thickness: f32,
    back: Vec3,
    back_normal: Vec3,
) -> Option<(Vec3, f32)> {
    let (exit, path) = slab_exit(entry, incident, n, ior, thickness);
    hit_plane(exit, incident, back, back_normal).map(|p| (p, path))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn snell_holds_and_ior_one_goes_straight() {
        let n = Vec3::Z;
        let theta = 0.6f32;
        let incident = Vec3::new(theta.sin(), 0.0, -theta.cos());
        let r = refract(incident, n, 1.5).expect("no total internal reflection into glass");
        let sin_t = r.x / r.length();
        assert!((theta.sin() - 1.5 * sin_t).abs() < 1e-6, "{sin_t}");
        assert!((r.length() - 1.0).abs() < 1e-6);
        for ior in [1.0, 0.0, -2.0, f32::NAN, f32::INFINITY] {
            let r = refract(incident, n, ior).expect("straight");
            assert!((r - incident).length() < 1e-6, "ior {ior}: {r}");
        }
        // Out of glass into air past the critical angle (asin(1 / 1.5) = 0.73): reflected.
        let steep = Vec3::new(0.9f32.sin(), 0.0, -0.9f32.cos());
        assert_eq!(refract(steep, n, 1.0 / 1.5), None);
        assert!(refract(incident, n, 1.0 / 1.5).is_some());
    }

    #[test]
    fn a_slab_shifts_the_ray_by_its_thickness_and_absorbs_exponentially() {
        let n = Vec3::Z;
        let theta = 0.5f32;
        let incident = Vec3::new(theta.sin(), 0.0, -theta.cos());
        let (exit, path) = slab_exit(Vec3::ZERO, incident, n, 1.5, 2.0);
        // The exit is on the slab's far face, thickness / cos θ2 along the refracted ray.
        assert!((exit.z + 2.0).abs() < 1e-5, "{exit}");
        let cos_t = (1.0 - (theta.sin() / 1.5).powi(2)).sqrt();
        assert!((path - 2.0 / cos_t).abs() < 1e-5);
        // Lateral shift against the straight ray: t (tan θ1 - tan θ2).
        let straight = incident * (2.0 / theta.cos());
        let tan_t = (theta.sin() / 1.5) / cos_t;
        assert!(((straight.x - exit.x) - 2.0 * (theta.tan() - tan_t)).abs() < 1e-5);
        let t = beer_lambert(Vec3::new(2.0f32.ln(), 0.0, 1e6), 1.0);
        assert!(
            (t - Vec3::new(0.5, 1.0, 0.0)).abs().max_element() < 1e-6,
            "{t}"
        );
        assert_eq!(beer_lambert(Vec3::ONE, f32::INFINITY), Vec3::ZERO);
        // An infinite or NaN thickness is thin-walled: no shift.
        for t in [f32::INFINITY, f32::NAN] {
            assert_eq!(slab_exit(Vec3::ONE, incident, n, 1.5, t), (Vec3::ONE, 0.0));
        }
    }
}
