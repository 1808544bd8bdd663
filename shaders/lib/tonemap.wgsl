// Tone mapping: exposure, luminance and the tone operators, each from linear
// HDR to linear display values in 0..1. The CPU reference, with the same
// names, ids and the reasoning (sources, which ACES and AgX), is
// crates/render/src/reference/tonemap.rs; tests run both.
//
// Every operator takes any colour: negative channels count as 0 and huge
// ones saturate (tonemap_input), so 0 maps to 0 and nothing exceeds 1.
#define_import_path spreadlight::tonemap

const TONEMAP_LINEAR: u32 = 0u;
const TONEMAP_REINHARD: u32 = 1u;
const TONEMAP_REINHARD_MODIFIED: u32 = 2u;
const TONEMAP_UNCHARTED2: u32 = 3u;
const TONEMAP_FILMIC_ALU: u32 = 4u;
const TONEMAP_DRAGO: u32 = 5u;
const TONEMAP_LOGARITHMIC: u32 = 6u;
const TONEMAP_EXPONENTIAL: u32 = 7u;
const TONEMAP_ACES: u32 = 8u;
const TONEMAP_AGX: u32 = 9u;

const HDR_MAX: f32 = 1e9;
const MIN_LUMINANCE: f32 = 1e-6;

// Rec. 709.
fn luminance(c: vec3<f32>) -> f32 {
    return dot(c, vec3<f32>(0.2126, 0.7152, 0.0722));
}

// Linear exposure from EV100 (1.2 headroom, Lagarde & de Rousiers 2014).
fn ev100_to_exposure(ev100: f32) -> f32 {
    return 1.0 / (1.2 * exp2(ev100));
}

fn tonemap_input(c: vec3<f32>) -> vec3<f32> {
    return clamp(c, vec3<f32>(0.0), vec3<f32>(HDR_MAX));
}

fn tonemap_linear(c: vec3<f32>) -> vec3<f32> {
    return min(tonemap_input(c), vec3<f32>(1.0));
}

fn tonemap_reinhard(c: vec3<f32>) -> vec3<f32> {
    let x = tonemap_input(c);
    return x / (vec3<f32>(1.0) + x);
}

// `white` (floored at 1e-3) and above map to 1.
fn tonemap_reinhard_modified(c: vec3<f32>, white: f32) -> vec3<f32> {
    let x = tonemap_input(c);
    let w = max(white, 1e-3);
    return min(x * (vec3<f32>(1.0) + x / (w * w)) / (vec3<f32>(1.0) + x), vec3<f32>(1.0));
}

fn hable_partial(x: vec3<f32>) -> vec3<f32> {
    let a = 0.15;
    let b = 0.50;
    let c = 0.10;
    let d = 0.20;
    let e = 0.02;
    let f = 0.30;
    return (x * (a * x + vec3<f32>(c * b)) + vec3<f32>(d * e))
        / (x * (a * x + vec3<f32>(b)) + vec3<f32>(d * f))
        - vec3<f32>(e / f);
}

const HABLE_EXPOSURE_BIAS: f32 = 2.0;
const HABLE_WHITE: f32 = 11.2;

// Hable's Uncharted 2 curve with his exposure bias 2, white point 11.2 -> 1.
fn tonemap_filmic_uncharted2(c: vec3<f32>) -> vec3<f32> {
    let x = tonemap_input(c);
    let curve = hable_partial(x * HABLE_EXPOSURE_BIAS);
    let white = hable_partial(vec3<f32>(HABLE_WHITE));
    return clamp(curve / white, vec3<f32>(0.0), vec3<f32>(1.0));
}

// Hejl & Burgess-Dawson: their curve is gamma-encoded (1/2.2 baked in); the
// 2.2 power makes it linear like the other operators.
fn tonemap_filmic_alu(c: vec3<f32>) -> vec3<f32> {
    let x = max(tonemap_input(c) - vec3<f32>(0.004), vec3<f32>(0.0));
    let encoded = (x * (6.2 * x + vec3<f32>(0.5))) / (x * (6.2 * x + vec3<f32>(1.7)) + vec3<f32>(0.06));
    return pow(min(encoded, vec3<f32>(1.0)), vec3<f32>(2.2));
}

const DRAGO_BIAS: f32 = 0.85;

// Drago et al. 2003 on luminance, bias 0.85; `l_max` maps to 1.
fn tonemap_drago(c: vec3<f32>, l_max_in: f32) -> vec3<f32> {
    let x = tonemap_input(c);
    let l = luminance(x);
    let l_max = max(l_max_in, 1e-3);
    let exponent = log(DRAGO_BIAS) / log(0.5);
    let base = 2.0 + 8.0 * pow(l / l_max, exponent);
    let ld = log(l + 1.0) / log(l_max + 1.0) * (log(10.0) / log(base));
    return min(x * (ld / max(l, MIN_LUMINANCE)), vec3<f32>(1.0));
}

// log(1 + L) / log(1 + l_max) on luminance; `l_max` maps to 1.
fn tonemap_logarithmic(c: vec3<f32>, l_max: f32) -> vec3<f32> {
    let x = tonemap_input(c);
    let l = luminance(x);
    let ld = log(l + 1.0) / log(max(l_max, 1e-3) + 1.0);
    return min(x * (ld / max(l, MIN_LUMINANCE)), vec3<f32>(1.0));
}

fn tonemap_exponential(c: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(1.0) - exp(-tonemap_input(c));
}

// Stephen Hill's ACES RRT + ODT fit (BakingLab ACES.hlsl), no pre-scale.
const ACES_INPUT: mat3x3<f32> = mat3x3<f32>(
    vec3<f32>(0.59719, 0.07600, 0.02840),
    vec3<f32>(0.35458, 0.90834, 0.13383),
    vec3<f32>(0.04823, 0.01566, 0.83777),
);
const ACES_OUTPUT: mat3x3<f32> = mat3x3<f32>(
    vec3<f32>(1.60475, -0.10208, -0.00327),
    vec3<f32>(-0.53108, 1.10813, -0.07276),
    vec3<f32>(-0.07367, -0.00605, 1.07602),
);

fn rrt_and_odt_fit(v: vec3<f32>) -> vec3<f32> {
    let a = v * (v + vec3<f32>(0.0245786)) - vec3<f32>(0.000090537);
    let b = v * (0.983729 * v + vec3<f32>(0.432951)) + vec3<f32>(0.238081);
    return a / b;
}

fn tonemap_aces(c: vec3<f32>) -> vec3<f32> {
    let v = ACES_INPUT * tonemap_input(c);
    return clamp(ACES_OUTPUT * rrt_and_odt_fit(v), vec3<f32>(0.0), vec3<f32>(1.0));
}

// AgX as three.js implements it (from Filament, from Blender; Rec. 2020).
const LINEAR_SRGB_TO_LINEAR_REC2020: mat3x3<f32> = mat3x3<f32>(
    vec3<f32>(0.6274, 0.0691, 0.0164),
    vec3<f32>(0.3293, 0.9195, 0.0880),
    vec3<f32>(0.0433, 0.0113, 0.8956),
);
const LINEAR_REC2020_TO_LINEAR_SRGB: mat3x3<f32> = mat3x3<f32>(
    vec3<f32>(1.6605, -0.1246, -0.0182),
    vec3<f32>(-0.5876, 1.1329, -0.1006),
    vec3<f32>(-0.0728, -0.0083, 1.1187),
);
const AGX_INSET: mat3x3<f32> = mat3x3<f32>(
    vec3<f32>(0.856627153315983, 0.137318972929847, 0.11189821299995),
    vec3<f32>(0.0951212405381588, 0.761241990602591, 0.0767994186031903),
    vec3<f32>(0.0482516061458583, 0.101439036467562, 0.811302368396859),
);
const AGX_OUTSET: mat3x3<f32> = mat3x3<f32>(
    vec3<f32>(1.1271005818144368, -0.1413297634984383, -0.14132976349843826),
    vec3<f32>(-0.11060664309660323, 1.157823702216272, -0.11060664309660294),
    vec3<f32>(-0.016493938717834573, -0.016493938717834257, 1.2519364065950405),
);
const AGX_MIN_EV: f32 = -12.47393;
const AGX_MAX_EV: f32 = 4.026069;

// The 6th-order polynomial of AgX's default contrast sigmoid.
fn agx_contrast(x: vec3<f32>) -> vec3<f32> {
    let x2 = x * x;
    let x4 = x2 * x2;
    return 15.5 * x4 * x2 - 40.14 * x4 * x + 31.96 * x4 - 6.868 * x2 * x + 0.4298 * x2 + 0.1191 * x
        - vec3<f32>(0.00232);
}

fn tonemap_agx(c: vec3<f32>) -> vec3<f32> {
    let x = AGX_INSET * (LINEAR_SRGB_TO_LINEAR_REC2020 * tonemap_input(c));
    let encoded = (log2(max(x, vec3<f32>(1e-10))) - vec3<f32>(AGX_MIN_EV)) / (AGX_MAX_EV - AGX_MIN_EV);
    let curve = AGX_OUTSET * agx_contrast(clamp(encoded, vec3<f32>(0.0), vec3<f32>(1.0)));
    let linear = pow(max(curve, vec3<f32>(0.0)), vec3<f32>(2.2));
    return clamp(LINEAR_REC2020_TO_LINEAR_SRGB * linear, vec3<f32>(0.0), vec3<f32>(1.0));
}

// Exposure (a linear multiplier) then operator `op` (a TONEMAP_* id; unknown
// ids are Linear; `operator` is a reserved word in WGSL). `param`: Reinhard
// Modified's white point, Drago's and Logarithmic's max luminance.
fn tonemap(c: vec3<f32>, op: u32, exposure: f32, param: f32) -> vec3<f32> {
    let x = c * exposure;
    switch op {
        case TONEMAP_REINHARD: { return tonemap_reinhard(x); }
        case TONEMAP_REINHARD_MODIFIED: { return tonemap_reinhard_modified(x, param); }
        case TONEMAP_UNCHARTED2: { return tonemap_filmic_uncharted2(x); }
        case TONEMAP_FILMIC_ALU: { return tonemap_filmic_alu(x); }
        case TONEMAP_DRAGO: { return tonemap_drago(x, param); }
        case TONEMAP_LOGARITHMIC: { return tonemap_logarithmic(x, param); }
        case TONEMAP_EXPONENTIAL: { return tonemap_exponential(x); }
        case TONEMAP_ACES: { return tonemap_aces(x); }
        case TONEMAP_AGX: { return tonemap_agx(x); }
        default: { return tonemap_linear(x); }
    }
}
