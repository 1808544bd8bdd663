// Image-based light helpers shared by the environment's prefilter and the
// passes that read it (Reflection, SSR): low-discrepancy sequences, GGX
// importance sampling and the cube-face convention. Their CPU twins are in
// crates/render/src/reference/reflection.rs.
#define_import_path spreadlight::ibl

const IBL_PI: f32 = 3.14159265358979;

// Van der Corput in base 2 paired with i/n: evenly spread points in [0,1)^2.
fn hammersley(i: u32, n: u32) -> vec2<f32> {
    return vec2<f32>(f32(i) / f32(max(n, 1u)), f32(reverseBits(i)) * 2.3283064365386963e-10);
}

// An orthonormal frame around unit `n`: tangent, bitangent.
fn tangent_frame(n: vec3<f32>) -> mat3x3<f32> {
    var up = vec3<f32>(0.0, 0.0, 1.0);
    if (abs(n.z) > 0.999) {
        up = vec3<f32>(1.0, 0.0, 0.0);
    }
    let t = normalize(cross(up, n));
    let b = cross(n, t);
    return mat3x3<f32>(t, b, n);
}

// A half vector around `n` distributed as GGX's D(h) (h.n) for `alpha`
// (roughness squared): the pdf of the reflected direction is D (h.n) / (4 v.h).
fn importance_sample_ggx(xi: vec2<f32>, alpha: f32, n: vec3<f32>) -> vec3<f32> {
    let a2 = alpha * alpha;
    let phi = 2.0 * IBL_PI * xi.x;
    let cos_theta = sqrt(clamp((1.0 - xi.y) / (1.0 + (a2 - 1.0) * xi.y), 0.0, 1.0));
    let sin_theta = sqrt(max(1.0 - cos_theta * cos_theta, 0.0));
    let local = vec3<f32>(sin_theta * cos(phi), sin_theta * sin(phi), cos_theta);
    return normalize(tangent_frame(n) * local);
}

// The world direction through texel centre `uv` (-1..1) of cube face
// `face` (+X, -X, +Y, -Y, +Z, -Z: the layer order of a cube texture).
fn cube_direction(face: u32, uv: vec2<f32>) -> vec3<f32> {
    var d: vec3<f32>;
    switch (face) {
        case 0u: { d = vec3<f32>(1.0, -uv.y, -uv.x); }
        case 1u: { d = vec3<f32>(-1.0, -uv.y, uv.x); }
        case 2u: { d = vec3<f32>(uv.x, 1.0, uv.y); }
        case 3u: { d = vec3<f32>(uv.x, -1.0, -uv.y); }
        case 4u: { d = vec3<f32>(uv.x, -uv.y, 1.0); }
        default: { d = vec3<f32>(-uv.x, -uv.y, -1.0); }
    }
    return normalize(d);
}

// Where unit direction `d` lands in an equirectangular image (u right, v
// down): u = 0.5 looks along -z, v = 0 straight up.
fn equirect_uv(d: vec3<f32>) -> vec2<f32> {
    let u = 0.5 + atan2(d.x, -d.z) / (2.0 * IBL_PI);
    let v = acos(clamp(d.y, -1.0, 1.0)) / IBL_PI;
    return vec2<f32>(u, v);
}

// The split-sum factor F0 * A + B (Karis 2013) from the table of
// prefilter.wgsl's brdf_lut, by N.V (x) and roughness (y): what the
// prefiltered radiance is multiplied by to give the specular reflection.
fn split_sum(lut: texture_2d<f32>, lut_sampler: sampler, f0: vec3<f32>, n_dot_v: f32, roughness: f32) -> vec3<f32> {
    let ab = textureSampleLevel(lut, lut_sampler, vec2<f32>(clamp(n_dot_v, 0.0, 1.0), clamp(roughness, 0.0, 1.0)), 0.0).xy;
    return f0 * ab.x + vec3<f32>(ab.y);
}

// A normal the viewer can see: one facing away (interpolated normals at
// silhouettes, back faces) is bent towards `v` until N.V is a little above
// zero, so reflected directions stay in front of the surface.
fn facing_normal(n: vec3<f32>, v: vec3<f32>) -> vec3<f32> {
    let n_dot_v = dot(n, v);
    if (n_dot_v >= 0.01) {
        return n;
    }
    let bent = n + (0.01 - n_dot_v) * v;
    let len2 = dot(bent, bent);
    if (len2 > 1e-12) {
        return bent * inverseSqrt(len2);
    }
    return v;
}
