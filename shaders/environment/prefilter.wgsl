// The environment's precomputation (crates/render/src/environment/prefilter.rs),
// one entry point per step, each a thread per output texel in 8x8 groups
// (z: the cube face):
//  - from_equirect / from_sky: the base cube's level 0, from an
//    equirectangular image (each texel the average of the image's samples
//    under it, so a small bright spot keeps its energy at any cube size) or
//    from the procedural sky;
//  - downsample: each base mip the 2x2 average of the one above (the
//    source mips filtered importance sampling reads);
//  - prefilter: level m of the specular cube, roughness m / (levels - 1),
//    GGX-importance-sampled with N = V = R (split-sum), each sample read
//    from the base mip whose texel covers its share of the lobe
//    (Krivanek & Colbert's filtered importance sampling: a bright texel is
//    averaged into its neighbours instead of landing in a few samples as a
//    firefly);
//  - irradiance: the cosine-weighted integral over every texel of a small
//    base mip, divided by pi (what a white Lambertian surface reflects);
//  - brdf_lut: the split-sum scale and bias (A, B) of F0 by N.V (x) and
//    roughness (y), for the renderer's GGX / height-correlated Smith.
// Every value is clamped below half-float overflow.
#import spreadlight::brdf::{d_ggx, v_smith_ggx_correlated, roughness_to_alpha}
#import spreadlight::ibl::{hammersley, importance_sample_ggx, cube_direction, equirect_uv}
#import spreadlight::sky::{Sky, sky_radiance}

struct Params {
    // Output face size in texels.
    size: u32,
    // Samples per texel (prefilter, LUT), or per side (equirect supersampling).
    samples: u32,
    // The base cube's level-0 size and its number of mips.
    base_size: u32,
    base_mips: u32,
    roughness: f32,
    pad0: f32,
    pad1: f32,
    pad2: f32,
}

const HALF_MAX: f32 = 65000.0;
const PI: f32 = 3.14159265358979;

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var equirect: texture_2d<f32>;
@group(0) @binding(2) var linear_sampler: sampler;
@group(0) @binding(3) var out_faces: texture_storage_2d_array<rgba16float, write>;
@group(0) @binding(4) var<uniform> sky: Sky;
@group(0) @binding(5) var source_faces: texture_2d_array<f32>;
@group(0) @binding(6) var base: texture_cube<f32>;
@group(0) @binding(7) var out_lut: texture_storage_2d<rgba16float, write>;

fn clean(c: vec3<f32>) -> vec3<f32> {
    // NaN fails both comparisons: select it away.
    let finite = c == c;
    return select(vec3<f32>(0.0), min(max(c, vec3<f32>(0.0)), vec3<f32>(HALF_MAX)), finite);
}

fn texel_uv(texel: vec2<f32>, size: u32) -> vec2<f32> {
    return texel / f32(size) * 2.0 - 1.0;
}

@compute @workgroup_size(8, 8)
fn from_equirect(@builtin(global_invocation_id) id: vec3<u32>) {
    if (id.x >= params.size || id.y >= params.size || id.z >= 6u) {
        return;
    }
    // params.samples per side: enough that the image's texels under this one are all seen.
    let k = max(params.samples, 1u);
    var sum = vec3<f32>(0.0);
    for (var j = 0u; j < k; j++) {
        for (var i = 0u; i < k; i++) {
            let sub = vec2<f32>(id.xy) + (vec2<f32>(f32(i), f32(j)) + 0.5) / f32(k);
            let d = cube_direction(id.z, texel_uv(sub, params.size));
            sum += textureSampleLevel(equirect, linear_sampler, equirect_uv(d), 0.0).rgb;
        }
    }
    textureStore(out_faces, id.xy, id.z, vec4<f32>(clean(sum / f32(k * k)), 1.0));
}

@compute @workgroup_size(8, 8)
fn from_sky(@builtin(global_invocation_id) id: vec3<u32>) {
    if (id.x >= params.size || id.y >= params.size || id.z >= 6u) {
        return;
    }
    // 2x2 samples a texel, so a sun smaller than a texel is neither lost nor doubled.
    var sum = vec3<f32>(0.0);
    for (var j = 0u; j < 2u; j++) {
        for (var i = 0u; i < 2u; i++) {
            let sub = vec2<f32>(id.xy) + (vec2<f32>(f32(i), f32(j)) + 0.5) * 0.5;
            sum += sky_radiance(sky, cube_direction(id.z, texel_uv(sub, params.size)));
        }
    }
    textureStore(out_faces, id.xy, id.z, vec4<f32>(clean(sum * 0.25), 1.0));
}

@compute @workgroup_size(8, 8)
fn downsample(@builtin(global_invocation_id) id: vec3<u32>) {
    if (id.x >= params.size || id.y >= params.size || id.z >= 6u) {
        return;
    }
    let src = vec2<i32>(id.xy) * 2;
    let layer = i32(id.z);
    let sum = textureLoad(source_faces, src, layer, 0).rgb
        + textureLoad(source_faces, src + vec2<i32>(1, 0), layer, 0).rgb
        + textureLoad(source_faces, src + vec2<i32>(0, 1), layer, 0).rgb
        + textureLoad(source_faces, src + vec2<i32>(1, 1), layer, 0).rgb;
    textureStore(out_faces, id.xy, id.z, vec4<f32>(clean(sum * 0.25), 1.0));
}

@compute @workgroup_size(8, 8)
fn prefilter(@builtin(global_invocation_id) id: vec3<u32>) {
    if (id.x >= params.size || id.y >= params.size || id.z >= 6u) {
        return;
    }
    let n = cube_direction(id.z, texel_uv(vec2<f32>(id.xy) + 0.5, params.size));
    let r = clamp(params.roughness, 0.0, 1.0);
    if (r <= 0.0) {
        textureStore(out_faces, id.xy, id.z, vec4<f32>(clean(textureSampleLevel(base, linear_sampler, n, 0.0).rgb), 1.0));
        return;
    }
    let alpha = roughness_to_alpha(r);
    let count = max(params.samples, 1u);
    // The solid angle of one base texel at level 0.
    let texel_solid_angle = 4.0 * PI / (6.0 * f32(params.base_size * params.base_size));
    let max_lod = f32(params.base_mips - 1u);
    var sum = vec3<f32>(0.0);
    var weight = 0.0;
    for (var i = 0u; i < count; i++) {
        let h = importance_sample_ggx(hammersley(i, count), alpha, n);
        let n_dot_h = dot(n, h);
        let l = 2.0 * n_dot_h * h - n;
        let n_dot_l = dot(n, l);
        if (n_dot_l <= 0.0) {
            continue;
        }
        // pdf(l) = D (n.h) / (4 v.h), and v = n: D / 4.
        let pdf = max(d_ggx(n_dot_h, r) * 0.25, 1e-8);
        let sample_solid_angle = 1.0 / (f32(count) * pdf);
        let lod = clamp(0.5 * log2(sample_solid_angle / texel_solid_angle) + 1.0, 0.0, max_lod);
        sum += textureSampleLevel(base, linear_sampler, l, lod).rgb * n_dot_l;
        weight += n_dot_l;
    }
    textureStore(out_faces, id.xy, id.z, vec4<f32>(clean(sum / max(weight, 1e-6)), 1.0));
}

@compute @workgroup_size(8, 8)
fn irradiance(@builtin(global_invocation_id) id: vec3<u32>) {
    if (id.x >= params.size || id.y >= params.size || id.z >= 6u) {
        return;
    }
    let n = cube_direction(id.z, texel_uv(vec2<f32>(id.xy) + 0.5, params.size));
    let s = textureDimensions(source_faces).x;
    var sum = vec3<f32>(0.0);
    for (var face = 0u; face < 6u; face++) {
        for (var y = 0u; y < s; y++) {
            for (var x = 0u; x < s; x++) {
                let uv = texel_uv(vec2<f32>(f32(x), f32(y)) + 0.5, s);
                let d = cube_direction(face, uv);
                let cos_n = dot(n, d);
                if (cos_n <= 0.0) {
                    continue;
                }
                // A texel's solid angle: (2/s)^2 / (1 + u^2 + v^2)^(3/2).
                let t = 1.0 + dot(uv, uv);
                let solid_angle = 4.0 / (f32(s * s) * t * sqrt(t));
                sum += textureLoad(source_faces, vec2<u32>(x, y), face, 0).rgb * cos_n * solid_angle;
            }
        }
    }
    textureStore(out_faces, id.xy, id.z, vec4<f32>(clean(sum / PI), 1.0));
}

@compute @workgroup_size(8, 8)
fn brdf_lut(@builtin(global_invocation_id) id: vec3<u32>) {
    if (id.x >= params.size || id.y >= params.size) {
        return;
    }
    let n_dot_v = max((f32(id.x) + 0.5) / f32(params.size), 1e-4);
    let r = (f32(id.y) + 0.5) / f32(params.size);
    let alpha = roughness_to_alpha(r);
    let n = vec3<f32>(0.0, 0.0, 1.0);
    let v = vec3<f32>(sqrt(max(1.0 - n_dot_v * n_dot_v, 0.0)), 0.0, n_dot_v);
    let count = max(params.samples, 1u);
    var a = 0.0;
    var b = 0.0;
    for (var i = 0u; i < count; i++) {
        let h = importance_sample_ggx(hammersley(i, count), alpha, n);
        let v_dot_h = dot(v, h);
        let l = 2.0 * v_dot_h * h - v;
        let n_dot_l = l.z;
        let n_dot_h = h.z;
        if (n_dot_l <= 0.0 || v_dot_h <= 0.0) {
            continue;
        }
        // D V F (n.l) / pdf(l), pdf(l) = D (n.h) / (4 v.h): F times this weight.
        let w = v_smith_ggx_correlated(n_dot_v, n_dot_l, r) * 4.0 * n_dot_l * v_dot_h / max(n_dot_h, 1e-6);
        let x = 1.0 - v_dot_h;
        let fc = x * x * x * x * x;
        a += (1.0 - fc) * w;
        b += fc * w;
    }
    textureStore(out_lut, id.xy, vec4<f32>(clamp(a / f32(count), 0.0, 1.0), clamp(b / f32(count), 0.0, 1.0), 0.0, 1.0));
}
