//! Ray-cast ambient occlusion on the CPU: the share of a cosine-weighted
//! hemisphere of rays from a surface point that travel `radius` without
//! hitting a sphere or the floor. The truth the screen-space AO estimators
//! are measured against (`spreadlight accuracy ao`, crates/render/tests/occlusion.rs):
//! it sees what the screen cannot (hidden and off-screen occluders).

use glam::{Mat4, Vec3, Vec4};

use crate::shadows::Sphere;

/// What occludes: balls over an optional square floor of half-width `floor` at y = 0.
#[derive(Clone, Debug, PartialEq)]
pub struct Occluders {
    pub spheres: Vec<Sphere>,
    pub floor: Option<f32>,
}

impl Occluders {
    /// The distance along unit `dir` from `origin` to the first hit, if within `max`.
    pub fn hit(&self, origin: Vec3, dir: Vec3, max: f32) -> Option<f32> {
        let mut nearest: Option<f32> = None;
        let mut keep = |t: f32| {
            if t > 1e-4 && t <= max && nearest.is_none_or(|n| t < n) {
                nearest = Some(t);
            }
        };
        for s in &self.spheres {
            let oc = origin - s.center;
            let b = oc.dot(dir);
            let c = oc.length_squared() - s.radius * s.radius;
            let disc = b * b - c;
            if disc >= 0.0 {
                let root = disc.sqrt();
                keep(-b - root);
                keep(-b + root);
            }
        }
        if let Some(half) = self.floor
            && dir.y.abs() > 1e-9
        {
            let t = -origin.y / dir.y;
            let p = origin + dir * t;
            if p.x.abs() <= half && p.z.abs() <= half {
                keep(t);
            }
        }
        nearest
    }

    /// The ball nearest to `p`, if it is nearer than the floor.
    fn nearest_ball(&self, p: Vec3) -> Option<&Sphere> {
        let (gap, ball) = self
            .spheres
            .iter()
            .map(|s| ((p.distance(s.center) - s.radius).abs(), s))
            .min_by(|a, b| a.0.total_cmp(&b.0))?;
        (self.floor.is_none() || gap < p.y.abs()).then_some(ball)
    }

    /// The surface normal at `p`, a point on a ball or the floor (the nearest surface).
    pub fn normal_at(&self, p: Vec3) -> Vec3 {
        match self.nearest_ball(p) {
            Some(s) => (p - s.center).normalize_or(Vec3::Y),
            None => Vec3::Y,
        }
    }

    /// `p` moved onto the nearest true surface (the mesh's facets lie just
    /// inside the spheres), then just off it along the normal, so rays do not
    /// hit the surface they start on. Returns the point and its normal.
    pub fn on_surface(&self, p: Vec3) -> (Vec3, Vec3) {
        match self.nearest_ball(p) {
            Some(s) => {
                let n = (p - s.center).normalize_or(Vec3::Y);
                (s.center + n * (s.radius + 1e-3), n)
            }
            None => (Vec3::new(p.x, 1e-3, p.z), Vec3::Y),
        }
    }
}

/// Cosine-weighted directions about +Z, stratified (Vogel's spiral on the
/// disk lifted to the hemisphere): deterministic, evenly spread.
pub fn hemisphere_samples(n: u32) -> Vec<Vec3> {
    crate::shadows::disk_samples(n)
        .into_iter()
        .map(|(x, y)| Vec3::new(x, y, (1.0 - x * x - y * y).max(0.0).sqrt()))
        .collect()
}

/// Visibility 0..1 at `point` with unit normal `normal`: the share of
/// `samples` (from [`hemisphere_samples`]) that reach `radius` unblocked.
pub fn visibility(
    point: Vec3,
    normal: Vec3,
    radius: f32,
    occluders: &Occluders,
    samples: &[Vec3],
) -> f32 {
    if samples.is_empty() || radius <= 0.0 {
        return 1.0;
    }
    let (t, b) = normal.any_orthonormal_pair();
    let open = samples
        .iter()
        .filter(|s| {
            let dir = t * s.x + b * s.y + normal * s.z;
            occluders.hit(point, dir, radius).is_none()
        })
        .count();
    open as f32 / samples.len() as f32
}

/// Ray-cast visibility under every pixel of a `size` image whose reversed-Z
/// depths are `depth` (row by row; 0 = no geometry, giving None), seen
/// through `inverse_view_projection`: each pixel's point is put on the true
/// surface and `rays` cosine-weighted rays of `radius` are cast from it.
pub fn visibility_image(
    depth: &[f32],
    size: (u32, u32),
    inverse_view_projection: Mat4,
    occluders: &Occluders,
    radius: f32,
    rays: u32,
) -> Vec<Option<f32>> {
    let samples = hemisphere_samples(rays);
    depth
        .iter()
        .enumerate()
        .map(|(i, &d)| {
            if d <= 0.0 {
                return None;
            }
            let (x, y) = (i as u32 % size.0, i as u32 / size.0);
            let ndc = Vec4::new(
                (x as f32 + 0.5) / size.0 as f32 * 2.0 - 1.0,
                1.0 - (y as f32 + 0.5) / size.1 as f32 * 2.0,
                d,
                1.0,
            );
            let h = inverse_view_projection * ndc;
            let (p, n) = occluders.on_surface(h.truncate() / h.w);
            Some(visibility(p, n, radius, occluders, &samples))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scene() -> Occluders {
        Occluders {
            spheres: vec![Sphere {
                center: Vec3::new(0.0, 1.0, 0.0),
                radius: 1.0,
            }],
            floor: Some(10.0),
        }
    }

    #[test]
    fn open_floor_is_unoccluded_and_the_contact_point_is_dark() {
        let samples = hemisphere_samples(512);
        let s = scene();
        assert_eq!(
            visibility(Vec3::new(6.0, 1e-3, 0.0), Vec3::Y, 1.0, &s, &samples),
            1.0
        );
        let contact = visibility(Vec3::new(0.05, 1e-3, 0.0), Vec3::Y, 1.0, &s, &samples);
        assert!(contact < 0.2, "contact: {contact}");
        // Farther from the ball, more of the sky is seen.
        let near = visibility(Vec3::new(1.0, 1e-3, 0.0), Vec3::Y, 1.0, &s, &samples);
        let far = visibility(Vec3::new(1.6, 1e-3, 0.0), Vec3::Y, 1.0, &s, &samples);
        assert!(
            contact < near && near < far && far < 1.0,
            "{contact} {near} {far}"
        );
    }

    #[test]
    fn radius_limits_what_occludes() {
        let samples = hemisphere_samples(256);
        let s = scene();
        let p = Vec3::new(1.5, 1e-3, 0.0);
        assert_eq!(visibility(p, Vec3::Y, 0.0, &s, &samples), 1.0);
        let small = visibility(p, Vec3::Y, 0.2, &s, &samples);
        let large = visibility(p, Vec3::Y, 5.0, &s, &samples);
        assert!(large < small, "{small} {large}");
    }

    #[test]
    fn the_cosine_weighted_samples_are_unit_and_upward() {
        let samples = hemisphere_samples(64);
        assert!(
            samples
                .iter()
                .all(|s| (s.length() - 1.0).abs() < 1e-4 && s.z >= 0.0)
        );
        // Cosine weighting: the mean of z over the hemisphere is 2/3.
        let mean = samples.iter().map(|s| s.z).sum::<f32>() / 64.0;
        assert!((mean - 2.0 / 3.0).abs() < 0.02, "{mean}");
    }

    #[test]
    fn points_are_put_on_the_true_surface() {
        let s = scene();
        let (p, n) = s.on_surface(Vec3::new(0.0, 1.98, 0.0));
        assert!((n - Vec3::Y).length() < 1e-4);
        assert!((p.y - 2.001).abs() < 1e-3, "{p}");
        let (p, n) = s.on_surface(Vec3::new(4.0, -0.01, 1.0));
        assert_eq!(n, Vec3::Y);
        assert!((p.y - 1e-3).abs() < 1e-6);
    }
}
