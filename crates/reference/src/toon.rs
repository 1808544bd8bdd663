//! Toon (cel) shading on the CPU: what `shaders/nodes/toon_lights.wgsl`, the
//! shipped light shader node, returns for one light, and the sum over
//! lights the light loop makes of it. Quantised: at a band's edge the
//! smallest rounding flips a step, so [`band_margin`] says how far a
//! surface is from one (a test compares pixels away from the edges).

use std::f32::consts::PI;

use glam::Vec3;

/// The node's pins.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ToonParams {
    pub bands: f32,
    pub highlight_size: f32,
    pub specular: f32,
}

/// One light as the light loop hands it over (shared by every light shader's reference).
pub use super::lights::ShaderLight as ToonLight;

/// The bands, as the shader rounds the pin: at least one.
fn bands(params: &ToonParams) -> f32 {
    params.bands.round().max(1.0)
}

/// How lit the surface is before quantising (0..1).
fn lit(n: Vec3, light: &ToonLight) -> f32 {
    n.dot(light.direction).clamp(0.0, 1.0) * light.shadow
}

/// (diffuse, specular) of one light at a surface with unit normal `n`,
/// unit view vector `v` and `albedo`.
pub fn toon_light(
    n: Vec3,
    v: Vec3,
    albedo: Vec3,
    light: &ToonLight,
    params: &ToonParams,
) -> (Vec3, Vec3) {
    let lit = lit(n, light);
    let bands = bands(params);
    let band = (lit * bands).ceil() / bands;
    let incident = light.radiance * light.attenuation;
    let diffuse = albedo * incident * (band / PI);
    let h = (light.direction + v).try_normalize().unwrap_or(n);
    let on = n.dot(h) > 1.0 - params.highlight_size && lit > 0.0;
    let specular = if on {
        incident * (params.specular * light.shadow / PI)
    } else {
        Vec3::ZERO
    };
    (diffuse, specular)
}

/// The light loop's sum of [`toon_light`] over `lights`.
pub fn toon_sum(
    n: Vec3,
    v: Vec3,
    albedo: Vec3,
    lights: &[ToonLight],
    params: &ToonParams,
) -> (Vec3, Vec3) {
    lights.iter().fold((Vec3::ZERO, Vec3::ZERO), |(d, s), l| {
        let (dl, sl) = toon_light(n, v, albedo, l, params);
        (d + dl, s + sl)
    })
}

/// The distance, over all `lights`, to the nearest step of the quantised
/// diffuse (in lit x bands) and of the highlight (in N.H): where it is tiny,
/// a rounding difference between two correct implementations flips a step.
pub fn band_margin(n: Vec3, v: Vec3, lights: &[ToonLight], params: &ToonParams) -> f32 {
    let bands = bands(params);
    lights
        .iter()
        .map(|l| {
            let x = lit(n, l) * bands;
            let band = if x > 0.0 {
                (x - x.round()).abs()
            } else {
                f32::INFINITY
            };
            let h = (l.direction + v).try_normalize().unwrap_or(n);
            let highlight = (n.dot(h) - (1.0 - params.highlight_size)).abs();
            // The highlight's `lit > 0` test: a light at grazing incidence.
            band.min(highlight)
                .min(lit(n, l).max(1.0 - lit(n, l)).min(x.abs().max(1.0)))
        })
        .fold(f32::INFINITY, f32::min)
}

#[cfg(test)]
mod tests {
    use super::*;

    const PARAMS: ToonParams = ToonParams {
        bands: 3.0,
        highlight_size: 0.04,
        specular: 0.5,
    };

    fn light(direction: Vec3, shadow: f32) -> ToonLight {
        ToonLight {
            direction: direction.normalize(),
            radiance: Vec3::splat(2.0),
            attenuation: 0.5,
            shadow,
        }
    }

    #[test]
    fn the_diffuse_steps_in_bands_and_sums_over_lights() {
        let (n, v, albedo) = (Vec3::Y, Vec3::Y, Vec3::ONE);
        // N.L = 1: the top band, albedo / pi x incident.
        let (d, _) = toon_light(n, v, albedo, &light(Vec3::Y, 1.0), &PARAMS);
        assert!((d.x - 1.0 / PI).abs() < 1e-6, "{d}");
        // N.L = 0.5: the second of three bands (ceil(1.5) / 3).
        let half = Vec3::new(0.75f32.sqrt(), 0.5, 0.0);
        let (d, _) = toon_light(n, v, albedo, &light(half, 1.0), &PARAMS);
        assert!((d.x - 2.0 / 3.0 / PI).abs() < 1e-6, "{d}");
        // A shadow of 0.2 leaves the first band; a full shadow nothing.
        let (d, s) = toon_light(n, v, albedo, &light(Vec3::Y, 0.2), &PARAMS);
        assert!((d.x - 1.0 / 3.0 / PI).abs() < 1e-6 && s.x > 0.0, "{d} {s}");
        let (d, s) = toon_light(n, v, albedo, &light(Vec3::Y, 0.0), &PARAMS);
        assert_eq!((d, s), (Vec3::ZERO, Vec3::ZERO));
        // Behind the surface: nothing.
        let (d, s) = toon_light(n, v, albedo, &light(Vec3::NEG_Y, 1.0), &PARAMS);
        assert_eq!((d, s), (Vec3::ZERO, Vec3::ZERO));
        let both = [light(Vec3::Y, 1.0), light(half, 1.0)];
        let (sum, _) = toon_sum(n, v, albedo, &both, &PARAMS);
        assert!((sum.x - (1.0 + 2.0 / 3.0) / PI).abs() < 1e-6, "{sum}");
    }

    #[test]
    fn the_highlight_is_flat_and_only_near_the_mirror_direction() {
        let n = Vec3::Y;
        let v = Vec3::new(0.3, 1.0, 0.0).normalize();
        let mirror = Vec3::new(-0.3, 1.0, 0.0).normalize();
        let (_, on) = toon_light(n, v, Vec3::ONE, &light(mirror, 1.0), &PARAMS);
        assert!((on.x - 0.5 / PI).abs() < 1e-6, "{on}");
        let (_, off) = toon_light(n, v, Vec3::ONE, &light(Vec3::X + Vec3::Y, 1.0), &PARAMS);
        assert_eq!(off, Vec3::ZERO);
        assert!(band_margin(n, v, &[light(mirror, 1.0)], &PARAMS) < 0.5);
    }
}
