//! Light falloff on the CPU: the windowed inverse-square law of point and
//! spot lights, the spot cone, and photometric power to intensity.
//! `shaders/lib/lights.wgsl` (`spreadlight::lights`) has the same functions
//! under the same names.

use std::f32::consts::PI;

/// Squared distance below which the inverse-square law stops growing (1 cm
/// in metres): a surface at the light's centre gets a large, finite value.
pub const MIN_DISTANCE_SQUARED: f32 = 1e-4;
/// Cone edges closer than this (in cosine) are one hard edge.
pub const MIN_CONE_SOFTNESS: f32 = 1e-4;

/// Inverse-square falloff times Karis' smooth window (UE4, "Real Shading in
/// Unreal Engine 4", 2013), which reaches exactly 0 at `range`, so a light
/// can be culled there without a visible edge:
/// saturate(1 - (d / range)^4)^2 / max(d^2, 1e-4). A light with no range
/// (<= 0) lights nothing.
pub fn point_attenuation(distance: f32, range: f32) -> f32 {
    if range <= 0.0 {
        return 0.0;
    }
    let d = distance.max(0.0);
    let ratio = d / range;
    let ratio2 = ratio * ratio;
    let window = (1.0 - ratio2 * ratio2).clamp(0.0, 1.0);
    window * window / (d * d).max(MIN_DISTANCE_SQUARED)
}

/// WGSL's `smoothstep` (edge0 < edge1).
fn smoothstep(edge0: f32, edge1: f32, x: f32) -> f32 {
    let t = ((x - edge0) / (edge1 - edge0)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// The spot cone: 1 inside the inner cone, 0 outside the outer one,
/// smoothstep between (all three arguments are cosines of angles from the
/// spot's axis). Where the edges meet (a cone with no soft edge, a 0° cone) it
/// is a hard step at the outer edge, so nothing divides by zero.
pub fn spot_attenuation(cos_angle: f32, cos_outer: f32, cos_inner: f32) -> f32 {
    if cos_inner <= cos_outer + MIN_CONE_SOFTNESS {
        return if cos_angle >= cos_outer { 1.0 } else { 0.0 };
    }
    smoothstep(cos_outer, cos_inner, cos_angle)
}

/// A point light's luminous intensity (candela) from its luminous power
/// (lumen): the power spreads over the full sphere, 4 pi steradians.
pub fn luminous_intensity_from_power(lumens: f32) -> f32 {
    lumens / (4.0 * PI)
}

/// One light at one surface point as the light loop hands it to a light
/// shader node (`LightInput`'s light half, `shaders/lib/light_shader.wgsl`):
/// what the references of the shipped light shaders
/// ([`super::toon`], [`super::ashikhmin_shirley`]) take.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShaderLight {
    /// Unit vector from the surface towards the light.
    pub direction: glam::Vec3,
    /// Colour times intensity (a spot's cone applied).
    pub radiance: glam::Vec3,
    /// Windowed inverse square; 1 for a sun.
    pub attenuation: f32,
    /// 1 lit, 0 shadowed.
    pub shadow: f32,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn point_attenuation_is_finite_windowed_and_decreasing() {
        assert!(point_attenuation(0.0, 10.0).is_finite());
        assert_eq!(point_attenuation(0.0, 10.0), 1.0 / MIN_DISTANCE_SQUARED);
        assert_eq!(point_attenuation(-1.0, 10.0), 1.0 / MIN_DISTANCE_SQUARED);
        assert_eq!(point_attenuation(1.0, 0.0), 0.0);
        assert_eq!(point_attenuation(0.0, 0.0), 0.0);
        assert_eq!(point_attenuation(1.0, -5.0), 0.0);
        assert_eq!(point_attenuation(10.0, 10.0), 0.0);
        assert_eq!(point_attenuation(20.0, 10.0), 0.0);
        assert_eq!(point_attenuation(1e30, 1e-30), 0.0);
        // Close to the light, far from the range, it is the inverse-square law.
        assert!((point_attenuation(2.0, 1000.0) - 0.25).abs() < 1e-6);
        let mut previous = f32::INFINITY;
        for i in 0..=2000 {
            let d = i as f32 * 0.01;
            let a = point_attenuation(d, 15.0);
            assert!(a.is_finite() && a >= 0.0);
            assert!(a <= previous, "attenuation grows at {d}: {a} > {previous}");
            previous = a;
        }
    }

    #[test]
    fn spot_cone_edges() {
        let (outer, inner) = (40f32.to_radians().cos(), 30f32.to_radians().cos());
        assert_eq!(spot_attenuation(1.0, outer, inner), 1.0);
        assert_eq!(spot_attenuation(inner, outer, inner), 1.0);
        assert_eq!(spot_attenuation(outer, outer, inner), 0.0);
        assert_eq!(spot_attenuation(0.0, outer, inner), 0.0);
        let mid = spot_attenuation(35f32.to_radians().cos(), outer, inner);
        assert!(mid > 0.3 && mid < 0.7, "{mid}");
        // Monotonic from the edge to the axis.
        let mut previous = 0.0;
        for i in 0..=100 {
            let a = spot_attenuation(-1.0 + i as f32 * 0.02, outer, inner);
            assert!(a >= previous);
            previous = a;
        }
        // A 0° cone lights only its axis; a 180° one (half-angle 90°) the
        // front hemisphere; a 360° one everything. Edges that meet or cross
        // are a hard step, never NaN.
        assert_eq!(spot_attenuation(1.0, 1.0, 1.0), 1.0);
        assert_eq!(spot_attenuation(0.999, 1.0, 1.0), 0.0);
        assert_eq!(spot_attenuation(0.0, 0.0, 0.0), 1.0);
        assert_eq!(spot_attenuation(-0.1, 0.0, 0.0), 0.0);
        assert_eq!(spot_attenuation(-1.0, -1.0, -1.0), 1.0);
        assert_eq!(spot_attenuation(0.5, 0.9, 0.2), 0.0);
        for c in [-1.0, -0.5, 0.0, 0.5, 1.0] {
            for (o, i) in [
                (1.0, 1.0),
                (0.0, 0.0),
                (-1.0, -1.0),
                (0.5, 0.50001),
                (-1.0, 1.0),
            ] {
                assert!(spot_attenuation(c, o, i).is_finite());
            }
        }
    }

    #[test]
    fn power_to_intensity() {
        assert!((luminous_intensity_from_power(4.0 * PI * 100.0) - 100.0).abs() < 1e-4);
        assert_eq!(luminous_intensity_from_power(0.0), 0.0);
    }
}
