// Light falloff: the windowed inverse-square law, the spot cone, and
// photometric power to intensity. The CPU reference, with the same names and
// the reasoning, is crates/render/src/reference/lights.rs; tests run both.
#define_import_path spreadlight::lights

const PI: f32 = 3.14159265358979;
const MIN_DISTANCE_SQUARED: f32 = 1e-4;
const MIN_CONE_SOFTNESS: f32 = 1e-4;

// Inverse-square times Karis' window: exactly 0 at `range`, finite at the
// light's centre, 0 for a light with no range.
fn point_attenuation(distance: f32, range: f32) -> f32 {
    let d = max(distance, 0.0);
    return point_attenuation_squared(d * d, range);
}

// `point_attenuation` from the squared distance: the light loops have it
// from their range test, and the window needs no square root.
fn point_attenuation_squared(distance2: f32, range: f32) -> f32 {
    if (range <= 0.0) {
        return 0.0;
    }
    let d2 = max(distance2, 0.0);
    // (d / range)^2; the floor keeps a range whose square underflows finite.
    return range_window(d2 / max(range * range, 1e-30)) / max(d2, MIN_DISTANCE_SQUARED);
}

// Karis' window of `point_attenuation` from (distance / range)^2: 1 at the
// light, 0 from the range on. The light loops combine it with an inverse
// square of their own (one reciprocal square root serves that and the
// light's direction).
fn range_window(ratio2: f32) -> f32 {
    let window = clamp(1.0 - ratio2 * ratio2, 0.0, 1.0);
    return window * window;
}

// 1 / max(distance^2, MIN_DISTANCE_SQUARED), from 1 / distance.
fn inverse_square(inverse_distance: f32) -> f32 {
    return min(inverse_distance * inverse_distance, 1.0 / MIN_DISTANCE_SQUARED);
}

// The range a light keeps under a cutoff (CookTorrance's Light Cutoff):
// where its brightest channel's inverse-square illuminance, intensity /
// distance^2, falls to `cutoff`, if that is nearer than its own `range`.
// The clusters list the light only that far, and the window of
// `range_window` fades it to 0 there, so there is no edge, only a shorter
// reach. A cutoff of 0 (or less, or NaN) keeps the range: the exact image.
fn cutoff_range(range: f32, intensity: vec3<f32>, cutoff: f32) -> f32 {
    if (!(cutoff > 0.0)) {
        return range;
    }
    let brightest = max(max(abs(intensity.r), abs(intensity.g)), abs(intensity.b));
    let reach = sqrt(brightest / cutoff);
    // A NaN reach (a NaN intensity) fails the test: the range stays.
    return select(range, reach, reach < range);
}

// Cosines from the spot's axis: 1 inside the inner cone, 0 outside the outer,
// smoothstep between; a hard step where the edges meet.
fn spot_attenuation(cos_angle: f32, cos_outer: f32, cos_inner: f32) -> f32 {
    if (cos_inner <= cos_outer + MIN_CONE_SOFTNESS) {
        return select(0.0, 1.0, cos_angle >= cos_outer);
    }
    return smoothstep(cos_outer, cos_inner, cos_angle);
}

// Candela from lumen for a point light (4 pi steradians).
fn luminous_intensity_from_power(lumens: f32) -> f32 {
    return lumens / (4.0 * PI);
}
