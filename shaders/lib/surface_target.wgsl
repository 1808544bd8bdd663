// The G-buffer's surface target as lighting reads it. Whatever resolved a
// pixel's surface in the G-buffer (a glTF material's surface maps, a shader
// node material's `surface` function; shaders/gbuffer/resolve.wgsl) wrote
// there, per pixel (Rgba32Uint):
//   x: pack2x16unorm(roughness, metallic)
//   y: pack2x16unorm(occlusion, written: 1)
//   z: emission, RGB9E5 (pack_rgb9e5)
//   w: 0, or for a material with a material extension's map (clearcoat,
//      specular; pack_extension): the coat's factor (bits 0..8, unorm),
//      its roughness (8..18, unorm), the reflectance (18..31, unorm) and
//      bit 31 set
// A material with a clearcoat normal map (pack_coat_normal) also keeps the
// coat's own normal, view space, octahedral in 2 x 10 bits, where no other
// pixel has anything to keep: y's bits 16..30, which pack_surface sets all
// to 1 (the written flag, bit 31, and a unorm of 1 above it), are 14 bits
// of the normal and bit 30 clear (what marks it), and w trades bits of
// precision no coat needs for the other 6: factor 8 bits (0..8), roughness
// 8 (8..16), the square root of the reflectance 9 (16..25: 0.04 within
// 2e-4), the normal's 6 (25..31), bit 31 set. So every other pixel packs
// and reads exactly as before, and `written`, the occlusion and the rest of
// x, y and z read the same for this one.
// Zero where nothing was written: such a pixel is shaded from its material
// (or the lighting node's pins) exactly as without a surface target; w
// zero: the coat and the reflectance are the material's.
//
// SURFACE_TARGET: the G-buffer has a surface target, bound at group 0,
// binding 30 (SURFACE_TARGET_BINDING in crates/render/src/gbuffer/mod.rs;
// no pass that imports this library uses that binding for anything else).
// Without it `surface_at` reads nothing and says "not written", so passes
// over G-buffers without one compile exactly what they did before.
#define_import_path spreadlight::surface_target

#ifdef SURFACE_TARGET
@group(0) @binding(30) var surface_target: texture_2d<u32>;
#endif

struct SurfaceSample {
    // Whether the G-buffer resolve wrote this pixel's surface; the rest is
    // meaningful only then.
    written: bool,
    roughness: f32,
    metallic: f32,
    // Ambient occlusion, 1: none.
    occlusion: f32,
    // Emitted radiance, linear RGB, not negative.
    emission: vec3<f32>,
    // Whether the next three are the maps' (w written), not the material's.
    extended: bool,
    coat: f32,
    coat_roughness: f32,
    // The dielectric f0 (CookTorrance's reflectance).
    reflectance: f32,
    // Whether the next is the coat's own normal (a clearcoat normal map):
    // else the coat shares the pixel's normal.
    coat_normal_written: bool,
    // View space, unit.
    coat_normal: vec3<f32>,
}

// Non-negative HDR colour in one u32, shared-exponent 9-9-9-5 (the
// RGB9E5 layout): 9-bit mantissas, exponent bias 15. Up to 65408.
fn pack_rgb9e5(rgb: vec3<f32>) -> u32 {
    let c = clamp(rgb, vec3<f32>(0.0), vec3<f32>(65408.0));
    let top = max(c.r, max(c.g, c.b));
    var exponent = i32(max(-16.0, floor(log2(max(top, 1e-30))))) + 16;
    var unit = exp2(f32(exponent - 24));
    if (floor(top / unit + 0.5) >= 512.0) {
        exponent += 1;
        unit *= 2.0;
    }
    let m = vec3<u32>(min(floor(c / unit + 0.5), vec3<f32>(511.0)));
    return m.r | (m.g << 9u) | (m.b << 18u) | (u32(exponent) << 27u);
}

fn unpack_rgb9e5(bits: u32) -> vec3<f32> {
    let unit = exp2(f32(i32(bits >> 27u) - 24));
    return vec3<f32>(f32(bits & 511u), f32((bits >> 9u) & 511u), f32((bits >> 18u) & 511u)) * unit;
}

// The texel the resolve writes for a resolved surface (values already
// finite and in range: roughness, metallic, occlusion 0..1, emission 0..65000).
fn pack_surface(roughness: f32, metallic: f32, occlusion: f32, emission: vec3<f32>) -> vec4<u32> {
    return vec4<u32>(
        pack2x16unorm(vec2<f32>(roughness, metallic)),
        pack2x16unorm(vec2<f32>(occlusion, 1.0)),
        pack_rgb9e5(emission),
        0u,
    );
}

// The w of a material with an extension's map: the coat's factor (8
// bits: a coverage), its roughness (10 bits: GGX's alpha is its square),
// the reflectance (13 bits: 0.04 within 6e-5), bit 31 set. All 0..1.
fn pack_extension(coat: f32, coat_roughness: f32, reflectance: f32) -> u32 {
    let c = u32(round(clamp(coat, 0.0, 1.0) * 255.0));
    let r = u32(round(clamp(coat_roughness, 0.0, 1.0) * 1023.0));
    let f = u32(round(clamp(reflectance, 0.0, 1.0) * 8191.0));
    return c | (r << 8u) | (f << 18u) | 0x80000000u;
}

// A unit vector on the octahedron, unfolded onto 0..1 squared.
fn octahedral_unit(n: vec3<f32>) -> vec2<f32> {
    let p = n.xy / max(abs(n.x) + abs(n.y) + abs(n.z), 1e-20);
    var e = p;
    if (n.z < 0.0) {
        e = (1.0 - abs(p.yx)) * select(vec2<f32>(-1.0), vec2<f32>(1.0), p >= vec2<f32>(0.0));
    }
    return clamp(e * 0.5 + 0.5, vec2<f32>(0.0), vec2<f32>(1.0));
}

fn from_octahedral_unit(u: vec2<f32>) -> vec3<f32> {
    let e = u * 2.0 - 1.0;
    var n = vec3<f32>(e, 1.0 - abs(e.x) - abs(e.y));
    let t = max(-n.z, 0.0);
    n = vec3<f32>(n.x + select(t, -t, n.x >= 0.0), n.y + select(t, -t, n.y >= 0.0), n.z);
    return normalize(n);
}

// 1022 steps, so the middle of the square (a normal straight along z) is exact.
const COAT_NORMAL_STEPS: f32 = 1022.0;

// `texel` (pack_surface's) with the coat of a material that has a
// clearcoat normal map: its factor, roughness, the reflectance and the
// coat's unit view-space normal `n` (see the layout above). All 0..1 but n.
fn pack_coat_normal(texel: vec4<u32>, coat: f32, coat_roughness: f32, reflectance: f32, n: vec3<f32>) -> vec4<u32> {
    let q = vec2<u32>(round(octahedral_unit(n) * COAT_NORMAL_STEPS));
    let bits = q.x | (q.y << 10u);
    let c = u32(round(clamp(coat, 0.0, 1.0) * 255.0));
    let r = u32(round(clamp(coat_roughness, 0.0, 1.0) * 255.0));
    let f = u32(round(sqrt(clamp(reflectance, 0.0, 1.0)) * 511.0));
    var out = texel;
    out.y = (texel.y & 0xffffu) | 0x80000000u | ((bits & 0x3fffu) << 16u);
    out.w = c | (r << 8u) | (f << 16u) | ((bits >> 14u) << 25u) | 0x80000000u;
    return out;
}

// The surface the G-buffer resolved at `pixel` (full-resolution G-buffer coordinates).
fn surface_at(pixel: vec2<u32>) -> SurfaceSample {
    var s: SurfaceSample;
    s.written = false;
    s.roughness = 0.5;
    s.metallic = 0.0;
    s.occlusion = 1.0;
    s.emission = vec3<f32>(0.0);
    s.extended = false;
    s.coat = 0.0;
    s.coat_roughness = 0.0;
    s.reflectance = 0.04;
    s.coat_normal_written = false;
    s.coat_normal = vec3<f32>(0.0, 0.0, 1.0);
#ifdef SURFACE_TARGET
    let bits = textureLoad(surface_target, pixel, 0);
    let ao = unpack2x16unorm(bits.y);
    if (ao.y > 0.5) {
        let rm = unpack2x16unorm(bits.x);
        s.written = true;
        s.roughness = clamp(rm.x, 0.0, 1.0);
        s.metallic = clamp(rm.y, 0.0, 1.0);
        s.occlusion = clamp(ao.x, 0.0, 1.0);
        // The resolve stores at most 65000; an RGB9E5 word it did not write
        // (exponent 31) can read up to 65408: hold it below half-float overflow.
        s.emission = min(unpack_rgb9e5(bits.z), vec3<f32>(65000.0));
        if ((bits.w & 0x80000000u) != 0u) {
            s.extended = true;
            s.coat = f32(bits.w & 255u) / 255.0;
            if ((bits.y & 0x40000000u) == 0u) {
                // A clearcoat normal map's pixel (pack_coat_normal).
                s.coat_roughness = f32((bits.w >> 8u) & 255u) / 255.0;
                let f = f32((bits.w >> 16u) & 511u) / 511.0;
                s.reflectance = f * f;
                let e = ((bits.y >> 16u) & 0x3fffu) | (((bits.w >> 25u) & 63u) << 14u);
                s.coat_normal_written = true;
                s.coat_normal = from_octahedral_unit(vec2<f32>(f32(e & 1023u), f32(e >> 10u)) / COAT_NORMAL_STEPS);
            } else {
                s.coat_roughness = f32((bits.w >> 8u) & 1023u) / 1023.0;
                s.reflectance = f32((bits.w >> 18u) & 8191u) / 8191.0;
            }
        }
    }
#endif
    return s;
}
