//! Shadow rays on the CPU: how much of a disk-shaped light a point sees past
//! a set of spheres. The ground truth the shadow filters are measured
//! against (`spreadlight accuracy shadows`): many rays per point, no maps,
//! no bias, no filtering.

use glam::Vec3;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sphere {
    pub center: Vec3,
    pub radius: f32,
}

/// A light as a disk of `radius` around `center`, facing `normal`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DiskLight {
    pub center: Vec3,
    pub normal: Vec3,
    pub radius: f32,
}

/// Points spread evenly over a unit disk (Vogel's golden-angle spiral): deterministic.
pub fn disk_samples(n: u32) -> Vec<(f32, f32)> {
    (0..n)
        .map(|i| {
            let r = ((i as f32 + 0.5) / n.max(1) as f32).sqrt();
            let theta = i as f32 * 2.399_963;
            (r * theta.cos(), r * theta.sin())
        })
        .collect()
}

/// Whether the segment from `a` to `b` passes through a sphere (ends excluded).
fn blocked(a: Vec3, b: Vec3, spheres: &[Sphere]) -> bool {
    let d = b - a;
    let len2 = d.length_squared();
    if len2 <= 0.0 {
        return false;
    }
    spheres.iter().any(|s| {
        // |a + t d - c|^2 = r^2, for t in (0, 1).
        let oc = a - s.center;
        let half_b = oc.dot(d);
        let c = oc.length_squared() - s.radius * s.radius;
        let disc = half_b * half_b - len2 * c;
        if disc < 0.0 {
            return false;
        }
        let root = disc.sqrt();
        let (t0, t1) = ((-half_b - root) / len2, (-half_b + root) / len2);
        (t0 > 1e-4 && t0 < 1.0 - 1e-4) || (t1 > 1e-4 && t1 < 1.0 - 1e-4) || (t0 < 0.0 && t1 > 1.0)
    })
}

/// The fraction of `light` that `point` sees, 0..1, by one ray to each of `samples` points of the disk.
pub fn visibility(
    point: Vec3,
    light: &DiskLight,
    spheres: &[Sphere],
    samples: &[(f32, f32)],
) -> f32 {
    let n = light.normal.try_normalize().unwrap_or(Vec3::NEG_Y);
    let (u, v) = n.any_orthonormal_pair();
    if samples.is_empty() {
        return if blocked(point, light.center, spheres) {
            0.0
        } else {
            1.0
        };
    }
    let seen = samples
        .iter()
        .filter(|(x, y)| {
            let target = light.center + (u * *x + v * *y) * light.radius;
            !blocked(point, target, spheres)
        })
        .count();
    seen as f32 / samples.len() as f32
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn umbra_penumbra_and_light_are_told_apart() {
        let light = DiskLight {
            center: Vec3::new(0.0, 10.0, 0.0),
            normal: Vec3::NEG_Y,
            radius: 1.0,
        };
        let ball = [Sphere {
            center: Vec3::new(0.0, 2.0, 0.0),
            radius: 1.0,
        }];
        let samples = disk_samples(256);
        assert_eq!(
            visibility(Vec3::ZERO, &light, &ball, &samples),
            0.0,
            "umbra"
        );
        assert_eq!(
            visibility(Vec3::new(5.0, 0.0, 0.0), &light, &ball, &samples),
            1.0,
            "lit"
        );
        let edge = visibility(Vec3::new(1.25, 0.0, 0.0), &light, &ball, &samples);
        assert!(edge > 0.05 && edge < 0.95, "penumbra: {edge}");
        // A point light (no samples) gives a hard answer.
        let hard = visibility(Vec3::new(1.25, 0.0, 0.0), &light, &ball, &[]);
        assert!(hard == 0.0 || hard == 1.0);
        // The sphere behind the point or beyond the light blocks nothing.
        let behind = [Sphere {
            center: Vec3::new(0.0, -3.0, 0.0),
            radius: 1.0,
        }];
        assert_eq!(visibility(Vec3::ZERO, &light, &behind, &samples), 1.0);
    }
}
