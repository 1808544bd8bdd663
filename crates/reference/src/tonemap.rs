//! Tone mapping on the CPU: exposure, luminance and the tone operators (the
//! ones of Emeshe, plus ACES and AgX), each from linear HDR radiance to
//! linear display values in 0..1 (the swapchain's sRGB encoding comes later).
//! `shaders/lib/tonemap.wgsl` (`spreadlight::tonemap`) has the same
//! functions, constants and operator ids under the same names.
//!
//! Every operator takes any colour: negative channels count as 0 and huge
//! ones (up to infinity) saturate, through [`tonemap_input`], so 0 maps to 0,
//! nothing exceeds 1 and nothing is NaN.

use glam::{Mat3, Vec3};

/// A tone operator. Its id (`as u32`, [`TonemapOperator::id`]) is the
/// `TONEMAP_*` constant of the same name in `shaders/lib/tonemap.wgsl`, which
/// the tonemap pass's uniform carries.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[repr(u32)]
pub enum TonemapOperator {
    Linear = 0,
    Reinhard = 1,
    ReinhardModified = 2,
    FilmicUncharted2 = 3,
    FilmicAlu = 4,
    Drago = 5,
    Logarithmic = 6,
    Exponential = 7,
    Aces = 8,
    Agx = 9,
}

impl TonemapOperator {
    /// Every operator, in id order.
    pub const ALL: [TonemapOperator; 10] = [
        TonemapOperator::Linear,
        TonemapOperator::Reinhard,
        TonemapOperator::ReinhardModified,
        TonemapOperator::FilmicUncharted2,
        TonemapOperator::FilmicAlu,
        TonemapOperator::Drago,
        TonemapOperator::Logarithmic,
        TonemapOperator::Exponential,
        TonemapOperator::Aces,
        TonemapOperator::Agx,
    ];

    /// The operators' names as patches spell them, in id order.
    pub const NAMES: [&'static str; 10] = [
        "Linear",
        "Reinhard",
        "Reinhard Modified",
        "Filmic Uncharted 2",
        "Filmic ALU",
        "Drago",
        "Logarithmic",
        "Exponential",
        "ACES",
        "AgX",
    ];

    /// The id the WGSL knows it by.
    pub const fn id(self) -> u32 {
        self as u32
    }

    pub const fn name(self) -> &'static str {
        Self::NAMES[self as usize]
    }
}

/// Largest channel value an operator looks at: every operator has saturated
/// long before, and the rational ones would overflow (inf / inf) past ~1e19.
pub const HDR_MAX: f32 = 1e9;
/// Smallest luminance the luminance-scaling operators divide by.
const MIN_LUMINANCE: f32 = 1e-6;

/// Rec. 709 relative luminance of linear RGB.
pub fn luminance(c: Vec3) -> f32 {
    c.dot(Vec3::new(0.2126, 0.7152, 0.0722))
}

/// A linear exposure multiplier from EV100 (the photometric convention of
/// Lagarde & de Rousiers 2014: the saturation-based sensor sensitivity
/// with a 1.2 headroom factor). The bench scenes use EV100 9.7.
pub fn ev100_to_exposure(ev100: f32) -> f32 {
    1.0 / (1.2 * ev100.exp2())
}

/// What every operator sees: channels clamped to 0..[`HDR_MAX`].
pub fn tonemap_input(c: Vec3) -> Vec3 {
    c.clamp(Vec3::ZERO, Vec3::splat(HDR_MAX))
}

/// No curve: clip to 0..1.
pub fn tonemap_linear(c: Vec3) -> Vec3 {
    tonemap_input(c).min(Vec3::ONE)
}

/// Reinhard 2002, per channel: c / (1 + c).
pub fn tonemap_reinhard(c: Vec3) -> Vec3 {
    let x = tonemap_input(c);
    x / (Vec3::ONE + x)
}

/// Reinhard 2002's extended operator, per channel, with a white point:
/// `white` (floored at 1e-3) and everything above map to 1.
pub fn tonemap_reinhard_modified(c: Vec3, white: f32) -> Vec3 {
    let x = tonemap_input(c);
    let w = white.max(1e-3);
    (x * (Vec3::ONE + x / (w * w)) / (Vec3::ONE + x)).min(Vec3::ONE)
}

/// Hable's filmic curve for Uncharted 2 (the shoulder/linear/toe constants).
fn hable_partial(x: Vec3) -> Vec3 {
    let (a, b, c, d, e, f) = (0.15, 0.50, 0.10, 0.20, 0.02, 0.30);
    (x * (a * x + Vec3::splat(c * b)) + Vec3::splat(d * e))
        / (x * (a * x + Vec3::splat(b)) + Vec3::splat(d * f))
        - Vec3::splat(e / f)
}

/// Hable's exposure bias: his curve is tuned for input scaled by 2.
const HABLE_EXPOSURE_BIAS: f32 = 2.0;
/// Hable's linear white point: 11.2 maps to 1.
const HABLE_WHITE: f32 = 11.2;

/// Hable's Uncharted 2 filmic operator (John Hable, "Filmic Tonemapping
/// Operators", 2010), as he wrote it: input times his exposure bias of 2,
/// normalised so that the white point W = 11.2 maps to 1.
pub fn tonemap_filmic_uncharted2(c: Vec3) -> Vec3 {
    let x = tonemap_input(c);
    let curve = hable_partial(x * HABLE_EXPOSURE_BIAS);
    let white = hable_partial(Vec3::splat(HABLE_WHITE));
    (curve / white).clamp(Vec3::ZERO, Vec3::ONE)
}

/// Hejl and Burgess-Dawson's filmic operator ("Filmic ALU", 2010). Their
/// curve outputs gamma-encoded values (the 1/2.2 power is baked in); here it
/// is raised to 2.2 so that it returns linear values like every other operator.
pub fn tonemap_filmic_alu(c: Vec3) -> Vec3 {
    let x = (tonemap_input(c) - Vec3::splat(0.004)).max(Vec3::ZERO);
    let encoded =
        (x * (6.2 * x + Vec3::splat(0.5))) / (x * (6.2 * x + Vec3::splat(1.7)) + Vec3::splat(0.06));
    encoded.min(Vec3::ONE).powf(2.2)
}

/// Drago's bias parameter (0.85, the paper's recommended value).
const DRAGO_BIAS: f32 = 0.85;

/// Drago et al. 2003, "Adaptive Logarithmic Mapping", with display maximum
/// 100 cd/m^2 (so that `l_max`, the scene's maximum luminance, maps to 1) and
/// bias 0.85: the logarithm's base runs from 2 in the shadows to 10 at
/// `l_max`. Applied to luminance; the colour is scaled with it.
pub fn tonemap_drago(c: Vec3, l_max: f32) -> Vec3 {
    let x = tonemap_input(c);
    let l = luminance(x);
    let l_max = l_max.max(1e-3);
    let exponent = DRAGO_BIAS.ln() / 0.5f32.ln();
    let base = 2.0 + 8.0 * (l / l_max).powf(exponent);
    let ld = (l + 1.0).ln() / (l_max + 1.0).ln() * (10.0f32.ln() / base.ln());
    (x * (ld / l.max(MIN_LUMINANCE))).min(Vec3::ONE)
}

/// Logarithmic mapping: log(1 + L) / log(1 + l_max) of luminance, so that
/// `l_max` (the scene's maximum luminance) maps to 1; the colour is scaled
/// with it.
pub fn tonemap_logarithmic(c: Vec3, l_max: f32) -> Vec3 {
    let x = tonemap_input(c);
    let l = luminance(x);
    let ld = (l + 1.0).ln() / (l_max.max(1e-3) + 1.0).ln();
    (x * (ld / l.max(MIN_LUMINANCE))).min(Vec3::ONE)
}

/// Exponential mapping, per channel: 1 - exp(-c).
pub fn tonemap_exponential(c: Vec3) -> Vec3 {
    Vec3::ONE - (-tonemap_input(c)).exp()
}

/// Stephen Hill's fit of the ACES RRT and ODT (BakingLab's `ACES.hlsl`,
/// 2016): sRGB to ACES AP1 with the RRT's saturation, the curve fit, back to
/// sRGB. Columns as in GLSL/WGSL. No exposure pre-scale (three.js adds 1/0.6).
const ACES_INPUT: Mat3 = Mat3::from_cols(
    Vec3::new(0.59719, 0.07600, 0.02840),
    Vec3::new(0.35458, 0.90834, 0.13383),
    Vec3::new(0.04823, 0.01566, 0.83777),
);
const ACES_OUTPUT: Mat3 = Mat3::from_cols(
    Vec3::new(1.60475, -0.10208, -0.00327),
    Vec3::new(-0.53108, 1.10813, -0.07276),
    Vec3::new(-0.07367, -0.00605, 1.07602),
);

fn rrt_and_odt_fit(v: Vec3) -> Vec3 {
    let a = v * (v + Vec3::splat(0.0245786)) - Vec3::splat(0.000090537);
    let b = v * (0.983729 * v + Vec3::splat(0.432951)) + Vec3::splat(0.238081);
    a / b
}

/// ACES filmic: Stephen Hill's RRT + ODT fit (see `ACES_INPUT`), not
/// Narkowicz's single curve; it desaturates highlights as ACES does.
pub fn tonemap_aces(c: Vec3) -> Vec3 {
    let v = ACES_INPUT * tonemap_input(c);
    (ACES_OUTPUT * rrt_and_odt_fit(v)).clamp(Vec3::ZERO, Vec3::ONE)
}

// AgX as three.js implements it (r160+, `AgXToneMapping`; from Filament,
// from Blender's AgX with Rec. 2020 primaries). Columns as in GLSL/WGSL; the
// inset and outset matrices are three.js' digits, kept verbatim.
const LINEAR_SRGB_TO_LINEAR_REC2020: Mat3 = Mat3::from_cols(
    Vec3::new(0.6274, 0.0691, 0.0164),
    Vec3::new(0.3293, 0.9195, 0.0880),
    Vec3::new(0.0433, 0.0113, 0.8956),
);
const LINEAR_REC2020_TO_LINEAR_SRGB: Mat3 = Mat3::from_cols(
    Vec3::new(1.6605, -0.1246, -0.0182),
    Vec3::new(-0.5876, 1.1329, -0.1006),
    Vec3::new(-0.0728, -0.0083, 1.1187),
);
#[allow(clippy::excessive_precision)]
const AGX_INSET: Mat3 = Mat3::from_cols(
    Vec3::new(0.856627153315983, 0.137318972929847, 0.11189821299995),
    Vec3::new(0.0951212405381588, 0.761241990602591, 0.0767994186031903),
    Vec3::new(0.0482516061458583, 0.101439036467562, 0.811302368396859),
);
#[allow(clippy::excessive_precision)]
const AGX_OUTSET: Mat3 = Mat3::from_cols(
    Vec3::new(
        1.1271005818144368,
        -0.1413297634984383,
        -0.14132976349843826,
    ),
    Vec3::new(
        -0.11060664309660323,
        1.157823702216272,
        -0.11060664309660294,
    ),
    Vec3::new(
        -0.016493938717834573,
        -0.016493938717834257,
        1.2519364065950405,
    ),
);
/// log2 of 0.18 * 2^-10 and 0.18 * 2^6.5: the log encoding's range.
const AGX_MIN_EV: f32 = -12.47393;
const AGX_MAX_EV: f32 = 4.026069;

/// The 6th-order polynomial approximation of AgX's default contrast
/// sigmoid (three.js, Godot; mean error^2 3.67e-6).
fn agx_contrast(x: Vec3) -> Vec3 {
    let x2 = x * x;
    let x4 = x2 * x2;
    15.5 * x4 * x2 - 40.14 * x4 * x + 31.96 * x4 - 6.868 * x2 * x + 0.4298 * x2 + 0.1191 * x
        - Vec3::splat(0.00232)
}

/// AgX (Troy Sobotka), base look, in three.js' implementation: Rec. 2020,
/// inset, log2 encoding over -10..+6.5 stops around 0.18, the polynomial
/// contrast approximation, outset, 2.2 power back to linear, sRGB, clip.
pub fn tonemap_agx(c: Vec3) -> Vec3 {
    let x = AGX_INSET * (LINEAR_SRGB_TO_LINEAR_REC2020 * tonemap_input(c));
    let encoded =
        (x.max(Vec3::splat(1e-10)).log2() - Vec3::splat(AGX_MIN_EV)) / (AGX_MAX_EV - AGX_MIN_EV);
    let curve = AGX_OUTSET * agx_contrast(encoded.clamp(Vec3::ZERO, Vec3::ONE));
    let linear = curve.max(Vec3::ZERO).powf(2.2);
    (LINEAR_REC2020_TO_LINEAR_SRGB * linear).clamp(Vec3::ZERO, Vec3::ONE)
}

/// Scale by `exposure` (a linear multiplier, e.g. [`ev100_to_exposure`]) and
/// apply operator `op`.
/// `param` is the white point of Reinhard Modified and the maximum
/// luminance of Drago and Logarithmic, and unused by the others.
pub fn tonemap(c: Vec3, op: TonemapOperator, exposure: f32, param: f32) -> Vec3 {
    let x = c * exposure;
    match op {
        TonemapOperator::Linear => tonemap_linear(x),
        TonemapOperator::Reinhard => tonemap_reinhard(x),
        TonemapOperator::ReinhardModified => tonemap_reinhard_modified(x, param),
        TonemapOperator::FilmicUncharted2 => tonemap_filmic_uncharted2(x),
        TonemapOperator::FilmicAlu => tonemap_filmic_alu(x),
        TonemapOperator::Drago => tonemap_drago(x, param),
        TonemapOperator::Logarithmic => tonemap_logarithmic(x, param),
        TonemapOperator::Exponential => tonemap_exponential(x),
        TonemapOperator::Aces => tonemap_aces(x),
        TonemapOperator::Agx => tonemap_agx(x),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The parameter each operator is tested with (white point, max luminance).
    const PARAM: f32 = 4.0;

    fn all_operators() -> impl Iterator<Item = TonemapOperator> {
        TonemapOperator::ALL.into_iter()
    }

    /// 0, then 1e-6..1e6 in logarithmic steps.
    fn ramp() -> impl Iterator<Item = f32> {
        std::iter::once(0.0).chain((0..=1200).map(|i| 10f32.powf(-6.0 + i as f32 * 0.01)))
    }

    fn in_unit_range(c: Vec3) -> bool {
        c.is_finite() && c.min_element() >= 0.0 && c.max_element() <= 1.0
    }

    #[test]
    fn zero_is_black_and_huge_is_at_most_white() {
        for op in all_operators() {
            let name = op.name();
            let black = tonemap(Vec3::ZERO, op, 1.0, PARAM);
            assert!(
                black.max_element() <= 1e-6 && black.min_element() >= 0.0,
                "{name}: {black}"
            );
            for huge in [1e6, 1e20, f32::MAX, f32::INFINITY] {
                let c = tonemap(Vec3::splat(huge), op, 1.0, PARAM);
                assert!(in_unit_range(c), "{name} of {huge}: {c}");
            }
            // A big white maps to (nearly) white for every curve that has a shoulder.
            let bright = tonemap(Vec3::splat(1e6), op, 1.0, PARAM);
            assert!(bright.min_element() > 0.95, "{name}: {bright}");
        }
    }

    #[test]
    fn operators_are_monotonic_and_in_range_on_a_grey_ramp() {
        for op in all_operators() {
            let name = op.name();
            let mut previous = Vec3::ZERO;
            for x in ramp() {
                let c = tonemap(Vec3::splat(x), op, 1.0, PARAM);
                assert!(in_unit_range(c), "{name} of {x}: {c}");
                assert!(
                    c.cmpge(previous - Vec3::splat(1e-6)).all(),
                    "{name} decreases at {x}: {c} < {previous}"
                );
                previous = c;
            }
        }
    }

    #[test]
    fn coloured_and_odd_inputs_stay_in_range() {
        let colours = [
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(0.0, 0.0, 1.0),
            Vec3::new(1.0, 0.5, 0.1),
            Vec3::new(-1.0, 0.5, 2.0),
        ];
        for op in all_operators() {
            let name = op.name();
            for colour in colours {
                for x in ramp() {
                    let c = tonemap(colour * x, op, 1.0, PARAM);
                    assert!(in_unit_range(c), "{name} of {colour} * {x}: {c}");
                }
            }
            // Parameters at and beyond their ends.
            for param in [0.0, -1.0, 1e-9, 1e9] {
                for x in [0.0, 1e-7, 0.5, 1e6] {
                    let c = tonemap(Vec3::splat(x), op, 1.0, param);
                    assert!(in_unit_range(c), "{name} ({param}) of {x}: {c}");
                }
            }
        }
    }

    #[test]
    fn per_channel_operators_are_monotonic_on_coloured_ramps() {
        // ACES and AgX mix channels through matrices with negative entries
        // (hue shifts, the path to white), so only the others are monotonic
        // per channel on a saturated ramp.
        for op in TonemapOperator::ALL
            .into_iter()
            .filter(|o| !matches!(o, TonemapOperator::Aces | TonemapOperator::Agx))
        {
            let name = op.name();
            let mut previous = Vec3::ZERO;
            for x in ramp() {
                let c = tonemap(Vec3::new(1.0, 0.5, 0.1) * x, op, 1.0, PARAM);
                assert!(c.cmpge(previous - Vec3::splat(1e-6)).all(), "{name} at {x}");
                previous = c;
            }
        }
    }

    #[test]
    fn known_values() {
        let grey = |op, x: f32, param| tonemap(Vec3::splat(x), op, 1.0, param).x;
        assert!((grey(TonemapOperator::Linear, 0.25, 0.0) - 0.25).abs() < 1e-7);
        assert!((grey(TonemapOperator::Reinhard, 1.0, 0.0) - 0.5).abs() < 1e-7);
        assert!((grey(TonemapOperator::ReinhardModified, 4.0, 4.0) - 1.0).abs() < 1e-6);
        assert!(
            (grey(TonemapOperator::FilmicUncharted2, HABLE_WHITE / 2.0, 0.0) - 1.0).abs() < 1e-5
        );
        assert!((grey(TonemapOperator::Drago, 100.0, 100.0) - 1.0).abs() < 1e-5);
        assert!((grey(TonemapOperator::Logarithmic, 100.0, 100.0) - 1.0).abs() < 1e-5);
        assert!(
            (grey(TonemapOperator::Exponential, 1.0, 0.0) - (1.0 - (-1.0f32).exp())).abs() < 1e-7
        );
        // Exposure multiplies before the curve.
        assert_eq!(
            tonemap(Vec3::splat(0.5), TonemapOperator::Reinhard, 2.0, 0.0),
            tonemap_reinhard(Vec3::ONE)
        );
        // EV100 9.7, the bench's exposure: about 1/1000.
        let e = ev100_to_exposure(9.7);
        assert!((e - 1.0 / (1.2 * 831.75)).abs() < 1e-7, "{e}");
        assert!((ev100_to_exposure(0.0) - 1.0 / 1.2).abs() < 1e-7);
        assert!((luminance(Vec3::ONE) - 1.0).abs() < 1e-6);
    }
}
