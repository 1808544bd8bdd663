// A procedural material for DeferredBase layers: a material shader node.
// Its `surface` function runs in the G-buffer resolve for every pixel of the
// layer wired through it, writing albedo, normal and roughness. The Pattern
// enum picks one of three permutations (`#ifdef PATTERN_...`).
// @category Material
// @material
// @help Procedural marble, checker or wood in the object's own space (the pattern moves with the object): Color and Second Color mixed by the pattern. Scale is pattern cells per unit; Turbulence bends marble veins and wood rings; Roughness goes to the surface target.
// @enum PATTERN "Pattern" Marble|Checker|Wood
#import spreadlight::surface::{SurfaceInput, SurfaceOutput, surface_default}
#import spreadlight::packing::safe_normalize

struct Params {
    // @pin "Color" color default=0.92,0.9,0.86,1
    color: vec4<f32>,
    // @pin "Second Color" color default=0.12,0.14,0.2,1
    second_color: vec4<f32>,
    scale: f32, // @pin default=3 min=0.01 max=100
    turbulence: f32, // @pin default=4 min=0 max=16
    roughness: f32, // @pin default=0.25 min=0 max=1
}

@group(1) @binding(0) var<uniform> params: Params;

fn hash_cell(p: vec3<f32>) -> f32 {
    let q = fract(p * vec3<f32>(0.1031, 0.1030, 0.0973));
    let r = q + dot(q, q.yxz + 33.33);
    return fract((r.x + r.y) * r.z);
}

fn value_noise(p: vec3<f32>) -> f32 {
    let i = floor(p);
    let f = fract(p);
    let u = f * f * (3.0 - 2.0 * f);
    let a = mix(hash_cell(i), hash_cell(i + vec3<f32>(1.0, 0.0, 0.0)), u.x);
    let b = mix(hash_cell(i + vec3<f32>(0.0, 1.0, 0.0)), hash_cell(i + vec3<f32>(1.0, 1.0, 0.0)), u.x);
    let c = mix(hash_cell(i + vec3<f32>(0.0, 0.0, 1.0)), hash_cell(i + vec3<f32>(1.0, 0.0, 1.0)), u.x);
    let d = mix(hash_cell(i + vec3<f32>(0.0, 1.0, 1.0)), hash_cell(i + vec3<f32>(1.0, 1.0, 1.0)), u.x);
    return mix(mix(a, b, u.y), mix(c, d, u.y), u.z);
}

fn fbm(p: vec3<f32>) -> f32 {
    var sum = 0.0;
    var amplitude = 0.5;
    var q = p;
    for (var octave = 0; octave < 5; octave++) {
        sum += amplitude * value_noise(q);
        q = q * 2.03 + vec3<f32>(1.7, 9.2, 3.1);
        amplitude *= 0.5;
    }
    return sum;
}

// 0 where the pattern shows Second Color, 1 where it shows Color.
fn pattern(p: vec3<f32>) -> f32 {
#ifdef PATTERN_CHECKER
    let cell = floor(p + vec3<f32>(1e-3));
    return select(0.0, 1.0, (i32(cell.x + cell.y + cell.z) & 1) == 0);
#endif
#ifdef PATTERN_WOOD
    let rings = length(p.xz) * 4.0 + params.turbulence * 0.25 * fbm(p * vec3<f32>(1.0, 0.2, 1.0));
    return smoothstep(0.1, 0.6, fract(rings));
#endif
#ifdef PATTERN_MARBLE
    let phase = (p.x + p.y * 0.5 + params.turbulence * fbm(p)) * 3.14159265;
    return pow(abs(sin(phase)), 0.35);
#endif
}

fn surface(in: SurfaceInput) -> SurfaceOutput {
    var out = surface_default(in);
    let p = in.object_position * params.scale;
    let mask = pattern(p);
    out.albedo = mix(params.second_color.rgb, params.color.rgb, mask) * in.color.rgb;
    // Second Color sits slightly lower: bend the normal along the pattern's gradient.
    let e = 0.01;
    let gradient = vec3<f32>(
        pattern(p + vec3<f32>(e, 0.0, 0.0)) - mask,
        pattern(p + vec3<f32>(0.0, e, 0.0)) - mask,
        pattern(p + vec3<f32>(0.0, 0.0, e)) - mask,
    ) / e;
    let along = gradient - in.normal * dot(gradient, in.normal);
    out.normal = safe_normalize(in.normal - 0.02 * along, in.normal);
    out.roughness = params.roughness;
    out.metallic = 0.0;
    return out;
}
