// CookTorrance for one light type (Emeshe's light renderer, in compute):
// point lights by default, LIGHT_SPOT for spot lights (projectors: lit inside
// their frustum, through a layer of a texture array with SPOT_TEXTURE, else a
// round cone), LIGHT_SUN for parallel lights.
// per pixel, the G-buffer's surface lit by the lights of its froxel
// (CLUSTERED: shared by 16x16 blocks, slice by slice; with TILED over
// depth-bounded tiles; with PER_PIXEL each pixel alone, for CPU adapters)
// or by every light (the naive reference). GGX distribution,
// height-correlated Smith visibility, Schlick Fresnel; ENERGY_COMPENSATION
// adds the multiple-scattering term. Outputs diffuse (albedo applied, so
// metals and F0 are exact) and specular radiance (and, with FAKE_SSS, a
// subsurface term for materials with the FakeSSS feature), clamped below half-float
// overflow so no infinity reaches a target. CLEARCOAT (some material has
// the Clearcoat feature): a second GGX lobe, f0 0.04, over the base, which
// it dims by its Fresnel reflectance at N.V (glTF's KHR_materials_clearcoat
// as the Khronos sample viewer shades it), its factor and roughness scaled
// by their maps where the G-buffer resolved them (material::clearcoat_at),
// on its own normal where a clearcoat normal map gave one
// (material::clearcoat_normal_at; else the pixel's).
// ANISOTROPY (some surface-mapped material has the Anisotropy feature,
// KHR_materials_anisotropy): for such a material's pixels, the specular lobe
// stretched along the G-buffer's anisotropy direction (its anisotropy
// target: the tangent turned by the rotation and the map) by its strength
// (lib/anisotropy.wgsl); the diffuse, Fresnel and energy compensation stay
// the isotropic lobe's.
// IRIDESCENCE (some material has the Iridescence feature): a thin film's
// Fresnel reflectance at N.V (lib/iridescence.wgsl, Belcour & Barla as the
// Khronos sample viewer evaluates it) replaces Schlick's F, mixed by the
// film's factor, in the specular lobe and the diffuse's 1 - F (glTF's
// KHR_materials_iridescence); made once per pixel, it costs a light one
// more sum (of radiance N.L, for the diffuse).
// SHEEN (some material has the Sheen feature): the Charlie sheen lobe
// (lib/sheen.wgsl) tinted by the material's sheen colour, under the coat and
// over the base, which it dims by 1 - max(colour) x the lobe's albedo at N.V
// (glTF's KHR_materials_sheen as the Khronos sample viewer shades it).
// LIGHT_SUM (only in the fused light sets' copies, never a permutation of
// this file alone): the loop's entry takes the pixel's G-buffer texels,
// read once for all sets, and two sums it adds its terms to, for
// CompositeLight to read as one pair; OUT_DIFFUSE, OUT_SPECULAR and
// OUT_SSS then say which of the set's own targets are still written.
// SHEEN and IRIDESCENCE read a glTF material's mapped sheen and film from
// the G-buffer's sheen and film target (lib/sheen_film.wgsl; binding 33, a
// 1x1 "unwritten" stand-in where the G-buffer has none: the factors).
// CUSTOM_LIGHT: a light shader node's `light` function (lib/light_shader.wgsl,
// spliced in for lib/custom_light.wgsl) replaces the BRDF: the same walk,
// clusters and shadows, its outputs summed into the two targets.
#import spreadlight::camera::Camera
#import spreadlight::brdf::{BrdfSurface, LightSums, brdf_surface, no_light_sums, add_light, light_sums_brdf, cook_torrance_weights_scaled, half_vector_cosines, surface_energy_compensation, schlick_weight, DIELECTRIC_F0}
#import spreadlight::lights::{range_window, inverse_square, cutoff_range}
#import spreadlight::packing::{channel_to_id, safe_normalize}
// The material library, imported once: MATERIALS reads CookTorrance
// parameters from it, FAKE_SSS the FakeSSS tint. SURFACE_TARGET: the
// G-buffer has a surface target (shaders/lib/surface_target.wgsl); where a
// pixel's is written, its roughness and metallic replace the material's
// (or the node's pins').
#ifdef MATERIALS
#import spreadlight::material::{feature_param_at, FEATURE_COOK_TORRANCE, FEATURE_FAKE_SSS}
#else
#ifdef FAKE_SSS
#import spreadlight::material::{feature_param_at, FEATURE_FAKE_SSS}
#endif
// SURFACE_TARGET without the material library: roughness and metallic
// where the G-buffer resolved them (with it, feature_param_at reads them).
#ifdef SURFACE_TARGET
#import spreadlight::surface_target::surface_at
#endif
#endif
#ifdef CLEARCOAT
#import spreadlight::material::{clearcoat_at, clearcoat_normal_at}
// The pixel's coat: its coverage (0: none), its lobe's surface (the coat's
// normal, its roughness, f0 0.04) and its summed specular.
var<private> coat_factor: f32;
var<private> coat_surface: BrdfSurface;
var<private> coat_sum: vec3<f32>;
#endif
#ifdef ANISOTROPY
#import spreadlight::material::{has_feature, FEATURE_ANISOTROPY}
#import spreadlight::anisotropy::{AnisotropicSurface, anisotropic_surface, anisotropic_weights_scaled}
// View-space anisotropy direction (rgb) and strength (a), written by the
// G-buffer resolve for pixels of Anisotropy materials only.
@group(0) @binding(32) var anisotropy_target: texture_2d<f32>;
// The pixel's anisotropic lobe (strength 0: the isotropic one).
var<private> aniso: AnisotropicSurface;
#endif
#ifdef IRIDESCENCE
#import spreadlight::sheen_film::film_at
#import spreadlight::iridescence::iridescence_fresnel
#ifndef SHEEN
// The G-buffer's sheen and film target (lib/sheen_film.wgsl), or a 1x1
// stand-in of one unwritten texel where it has none (factors only).
@group(0) @binding(33) var sheen_film_target: texture_2d<u32>;
fn sheen_film_texel(pixel: vec2<u32>) -> vec4<u32> {
    return textureLoad(sheen_film_target, min(pixel, textureDimensions(sheen_film_target) - vec2<u32>(1u)), 0);
}
#endif
// The pixel's film: its factor (0: none), its Fresnel at N.V, and the
// summed radiance N.L its diffuse takes.
var<private> film_factor: f32;
var<private> film_fresnel: vec3<f32>;
var<private> film_lit: vec3<f32>;
#endif
#ifdef SHEEN
#import spreadlight::sheen_film::sheen_at
#import spreadlight::sheen::{sheen_weight, sheen_scaling}
// The G-buffer's sheen and film target (lib/sheen_film.wgsl), or a 1x1
// stand-in of one unwritten texel where it has none (factors only).
@group(0) @binding(33) var sheen_film_target: texture_2d<u32>;
fn sheen_film_texel(pixel: vec2<u32>) -> vec4<u32> {
    return textureLoad(sheen_film_target, min(pixel, textureDimensions(sheen_film_target) - vec2<u32>(1u)), 0);
}
// The pixel's sheen colour (black: none), its roughness and the summed
// lobe (white, times each light's radiance).
var<private> sheen_color: vec3<f32>;
var<private> sheen_roughness: f32;
var<private> sheen_sum: vec3<f32>;
#endif
#ifdef SHADOWS
#import spreadlight::shadow_sampling::light_shadow
// World-space normal of the pixel being shaded, for the shadows' normal offset.
var<private> normal_world: vec3<f32>;
// Its camera depth, to pick a sun's cascade.
var<private> view_depth: f32;
#endif
#ifdef CUSTOM_LIGHT
#import spreadlight::light_shader::{LightInput, LIGHT_KIND_POINT, LIGHT_KIND_SPOT, LIGHT_KIND_SUN}
#import spreadlight::custom_light as user_light
// The pixel's half of the light function's input, filled once per pixel.
var<private> custom_input: LightInput;
var<private> custom_diffuse: vec3<f32>;
var<private> custom_specular: vec3<f32>;

// A light function's output, finite (NaN and overflow count as nothing).
fn custom_finite(v: vec3<f32>) -> vec3<f32> {
    return select(vec3<f32>(0.0), v, abs(v) <= vec3<f32>(HALF_MAX));
}

// One light through the node's function, its outputs summed.
fn add_custom_light(slot: u32, towards: vec3<f32>, n_dot_l: f32, reach: f32, radiance: vec3<f32>,
                    attenuation: f32, shadow: f32) {
    var input = custom_input;
    input.index = light_index(slot);
    input.direction = towards;
    input.n_dot_l = n_dot_l;
    input.distance = reach;
    input.radiance = radiance;
    input.attenuation = attenuation;
    input.shadow = shadow;
    let out = user_light::light(input);
    custom_diffuse += custom_finite(out.diffuse);
    custom_specular += custom_finite(out.specular);
}
#endif
#ifdef FAKE_SSS
// Wrap-lighting subsurface term, tinted per material by the FakeSSS feature.
@group(0) @binding(13) var out_sss: texture_storage_2d<rgba16float, write>;
var<private> sss_tint: vec3<f32>;
var<private> sss_sum: vec3<f32>;
#endif


// Matches `GpuLight` in crates/render/src/lighting/mod.rs.
struct Light {
    position_range: vec4<f32>,
    intensity: vec4<f32>,
    direction: vec4<f32>,
    cone: vec4<f32>,
}

struct Grid {
    dims: vec4<u32>,
    depth: vec4<f32>,
    // x: the light cutoff (clusters.wgsl's; 0: none).
    falloff: vec4<f32>,
}

// Per material id (wrapping): roughness, metallic.
struct Surface {
    roughness_metallic: vec2<f32>,
}

@group(0) @binding(0) var<uniform> camera: Camera;
@group(0) @binding(1) var<uniform> grid: Grid;
@group(0) @binding(2) var<storage, read> lights: array<Light>;
#ifdef CLUSTERED
// The lights in view space (position, range), written by the assignment.
@group(0) @binding(3) var<storage, read> view_lights: array<vec4<f32>>;
@group(0) @binding(4) var<storage, read> counts: array<u32>;
@group(0) @binding(5) var<storage, read> offsets: array<u32>;
@group(0) @binding(6) var<storage, read> indices: array<u32>;
#ifdef MERGED
// Light Merge: each light's band in view space (clusters.wgsl's
// `transform`): its cube's centroid and the merge distance, + for a
// member, - for the merged light, 0 for a light not merged.
@group(0) @binding(34) var<storage, read> view_bands: array<vec4<f32>>;

// Whether a pixel at `p` shades a light of `band`: a member nearer than the
// merge distance to its cube's centroid, the merged light at it or farther.
// clusters.wgsl's `in_band` listed every side some point of the froxel may
// be on, so a pixel always finds the side it keeps.
fn band_keeps(band: vec4<f32>, p: vec3<f32>) -> bool {
    if (band.w == 0.0) {
        return true;
    }
    let offset = band.xyz - p;
    return (dot(offset, offset) < band.w * band.w) == (band.w > 0.0);
}

// The squared distances from `c` to the nearest (x) and the farthest (y)
// point of the box [lo, hi].
fn box_distances2(c: vec3<f32>, lo: vec3<f32>, hi: vec3<f32>) -> vec2<f32> {
    let nearest = c - clamp(c, lo, hi);
    let farthest = max(abs(c - lo), abs(hi - c));
    return vec2<f32>(dot(nearest, nearest), dot(farthest, farthest));
}

// Whether some point of the box [lo, hi] keeps a light of `band` (the
// block's cull of its list): `band_keeps` for its nearest point (a member)
// or its farthest (the merged light), a little generous as the
// assignment's `in_band` is (the pixel decides).
fn band_reaches(band: vec4<f32>, lo: vec3<f32>, hi: vec3<f32>) -> bool {
    if (band.w == 0.0) {
        return true;
    }
    let d2 = band.w * band.w;
    let to_box = box_distances2(band.xyz, lo, hi);
    if (band.w > 0.0) {
        return to_box.x < d2 * 1.001;
    }
    return to_box.y >= d2 * 0.999;
}

// Whether every point of the box [lo, hi] keeps a light of `band`, by a
// margin the per-pixel test's rounding cannot cross: its farthest point
// nearer than the merge distance (a member), its nearest point farther (the
// merged light). Such a light's band becomes 0 for the block's pixels, and
// each pixel still keeps the side it would have kept.
fn band_holds_box(band: vec4<f32>, lo: vec3<f32>, hi: vec3<f32>) -> bool {
    let d2 = band.w * band.w;
    let to_box = box_distances2(band.xyz, lo, hi);
    if (band.w > 0.0) {
        return to_box.y < d2 * 0.999;
    }
    return to_box.x >= d2 * 1.001;
}
#endif
#endif
@group(0) @binding(7) var<storage, read> surfaces: array<Surface>;
@group(0) @binding(8) var color: texture_2d<f32>;
@group(0) @binding(9) var normals: texture_2d<f32>;
@group(0) @binding(10) var depth: texture_2d<f32>;
@group(0) @binding(11) var out_diffuse: texture_storage_2d<rgba16float, write>;
@group(0) @binding(12) var out_specular: texture_storage_2d<rgba16float, write>;
#ifdef LIGHT_SPOT
// Projectors: shaders/lib/spot.wgsl (lit transparency shares it).
#import spreadlight::spot::spot_mask
#endif

const HALF_MAX: f32 = 65000.0;

// A light's view-space position with 1 / range^2 (w), as `shade` takes it;
// the floor keeps a range whose square underflows finite.
fn with_inverse_range(lv: vec4<f32>) -> vec4<f32> {
    return vec4<f32>(lv.xyz, 1.0 / max(lv.w * lv.w, 1e-30));
}

// `slot`: the light's place in the clustered loop's batch (light_index,
// light_radiance), or its index for the naive loop; `lv`: its view-space
// position and 1 / range^2 (callers leave out lights without a range; the
// clustered loop keeps both in workgroup memory, so a pixel divides by no
// range, and reads the intensity only for a light that reaches it). Adds
// the light's radiance times its BRDF weights to `sums` (brdf.wgsl's
// `LightSums`: F0, the surface's albedo and the energy compensation are
// applied once, after the loop).
fn shade(slot: u32, lv: vec4<f32>, p: vec3<f32>, pw: vec3<f32>, surface: BrdfSurface,
         sums: ptr<function, LightSums>) {
    let n = surface.n;
    // The light's shadow factor (1: lit); CUSTOM_LIGHT hands it over apart.
    var shadow = 1.0;
#ifdef LIGHT_SUN
    let light = light_index(slot);
    let record = lights[light];
    let travel = safe_normalize((camera.view * vec4<f32>(record.direction.xyz, 0.0)).xyz, vec3<f32>(0.0, 0.0, -1.0));
    let l = -travel;
    let n_dot_l = dot(n, l);
    let v_dot_l = dot(surface.v, l);
#ifdef CLEARCOAT
    let coat_n_dot_l = dot(coat_surface.n, l);
#endif
    var radiance = light_radiance(slot);
#ifdef SHADOWS
    if (record.cone.z >= 0.0) {
        shadow = light_shadow(u32(record.cone.z), pw, normal_world, record.direction.xyz, view_depth, n_dot_l);
    }
#endif
    let attenuation = 1.0;
#ifdef CUSTOM_LIGHT
    let reach = 0.0;
    let towards = -record.direction.xyz;
#endif
#else
    let to_light = lv.xyz - p;
    let distance2 = dot(to_light, to_light);
    // (distance / range)^2. Most of a froxel's list does not reach this
    // pixel: leave before any square root (point_attenuation is 0 from the
    // range on).
    let ratio2 = distance2 * lv.w;
    if (!(ratio2 < 1.0)) {
        return;
    }
    // N.L's sign, before any square root: to_light scaled by a positive
    // 1 / distance keeps it.
    let facing = dot(n, to_light);
#ifndef CUSTOM_LIGHT
#ifndef FAKE_SSS
    // A light behind the surface adds nothing (cook_torrance_weights is 0
    // for N.L <= 0): leave before its radiance is read and its half vector
    // made. Not with FAKE_SSS, which wraps light past the terminator, nor
    // for a light shader, which sees every light in range. A light at the
    // surface point is lit from along the normal (below). With a coat,
    // behind both the surface and the coat (a coat normal map bends the
    // coat's own way).
#ifdef CLEARCOAT
    let coat_facing = dot(coat_surface.n, to_light);
    if (!(facing > 0.0) && !(coat_factor > 0.0 && coat_facing > 0.0) && distance2 > 1e-20) {
        return;
    }
#else
    if (!(facing > 0.0) && distance2 > 1e-20) {
        return;
    }
#endif
#endif
#endif
    // point_attenuation_squared, with one reciprocal square root for both
    // the inverse square and the direction to the light. The cosines come
    // from `to_light` scaled once, not from a normalised vector.
    let inverse_distance = inverseSqrt(max(distance2, 1e-20));
    let attenuation = range_window(ratio2) * inverse_square(inverse_distance);
    var n_dot_l = facing * inverse_distance;
    var v_dot_l = dot(surface.v, to_light) * inverse_distance;
#ifdef ANISOTROPY
    var l = to_light * inverse_distance;
#endif
    if (!(distance2 > 1e-20)) {
        // A light at the surface point: from along the normal, as
        // safe_normalize makes its direction.
        n_dot_l = 1.0;
        v_dot_l = surface.view_cosine;
#ifdef ANISOTROPY
        l = n;
#endif
    }
#ifdef CLEARCOAT
    var coat_n_dot_l = dot(coat_surface.n, to_light) * inverse_distance;
    if (!(distance2 > 1e-20)) {
        coat_n_dot_l = 1.0;
    }
#endif
#ifdef LIGHT_SPOT
    // The 64-byte record only for lights that reach the pixel: most of a
    // froxel's list does not (its 256-pixel tile is wider than a light's reach
    // seen from any one pixel).
    let light = light_index(slot);
    let record = lights[light];
    let mask = spot_mask(light, record.cone, pw);
    if (all(mask <= vec3<f32>(0.0))) {
        return;
    }
    var radiance = light_radiance(slot) * mask;
#else
    var radiance = light_radiance(slot);
#endif
#ifdef SHADOWS
    // A light's own shadow slice (cone.z; -1: casts none).
    let caster = lights[light_index(slot)];
    if (caster.cone.z >= 0.0) {
        shadow = light_shadow(u32(caster.cone.z), pw, normal_world, pw - caster.position_range.xyz, view_depth, n_dot_l);
    }
#endif
#ifdef CUSTOM_LIGHT
    let reach = distance2 * inverse_distance;
    let towards = safe_normalize(lights[light_index(slot)].position_range.xyz - pw, custom_input.normal);
#endif
#endif
#ifdef CUSTOM_LIGHT
    add_custom_light(slot, towards, n_dot_l, reach, radiance, attenuation, shadow);
#else
    // The shadow and the falloff are scalars: folded into the weights
    // through N.L (cook_torrance_weights_scaled), one multiplication a light.
    let scale = attenuation * shadow;
    let cosines = half_vector_cosines(surface, n_dot_l, v_dot_l);
#ifdef ANISOTROPY
    if (aniso.strength > 0.0) {
        add_light(sums, radiance, anisotropic_weights_scaled(surface, aniso, l, n_dot_l, scale));
    } else {
        add_light(sums, radiance, cook_torrance_weights_scaled(surface, n_dot_l, cosines.x, cosines.y, scale));
    }
#else
    add_light(sums, radiance, cook_torrance_weights_scaled(surface, n_dot_l, cosines.x, cosines.y, scale));
#endif
#ifdef IRIDESCENCE
    if (film_factor > 0.0 && n_dot_l > 0.0) {
        film_lit += radiance * (min(n_dot_l, 1.0) * scale);
    }
#endif
#ifdef CLEARCOAT
    if (coat_factor > 0.0) {
        // D V N.L (F0 + (1 - F0) w): the coat's Schlick Fresnel at V.H,
        // its cosines on its own normal.
        let coat_cosines = half_vector_cosines(coat_surface, coat_n_dot_l, v_dot_l);
        let coat = cook_torrance_weights_scaled(coat_surface, coat_n_dot_l, coat_cosines.x, coat_cosines.y, scale);
        coat_sum += radiance * (coat.x * DIELECTRIC_F0 + coat.y * (1.0 - DIELECTRIC_F0));
    }
#endif
#ifdef SHEEN
    if (any(sheen_color > vec3<f32>(0.0))) {
        sheen_sum += radiance * sheen_weight(surface.n_dot_v, n_dot_l, cosines.x, sheen_roughness, scale);
    }
#endif
#ifdef FAKE_SSS
    // Light that wraps past the terminator (wrap 0.5), beyond what Lambert gives.
    let wrapped = max((n_dot_l + 0.5) / 1.5, 0.0) - max(n_dot_l, 0.0);
    sss_sum += sss_tint * radiance * scale * max(wrapped, 0.0) * 0.31830988;
#endif
#endif
}

// A 16x16 workgroup shades a block of pixels. With CLUSTERED it reads its
// froxels' light lists together: each batch of 256 list entries is loaded
// once for the block (not once per pixel), and only the lights whose sphere
// touches the box around the block's surface points (depth-bounded, much
// tighter than the 256-pixel froxel) are kept, packed in list order, so every
// pixel walks the survivors in list order: the sums, and so the pictures, are the
// same bit for bit as a pixel walking its whole list (a light that misses the
// box misses every pixel in it), at a fraction of the loads and tests.
const GROUP: u32 = 16u;
const BATCH: u32 = 256u;
const MASK_WORDS: u32 = 8u;

#ifdef CLUSTERED
#ifdef PER_PIXEL
// Each pixel walks its own froxel list: slots are light indices, as in the
// naive loop.
fn light_index(slot: u32) -> u32 {
    return slot;
}

fn light_radiance(slot: u32) -> vec3<f32> {
    return lights[slot].intensity.rgb;
}
#else
var<workgroup> box_lo: array<atomic<u32>, 3>;
var<workgroup> box_hi: array<atomic<u32>, 3>;
var<workgroup> slice_span: array<atomic<u32>, 2>;
var<workgroup> span_read: vec2<u32>;
var<workgroup> froxel_read: vec2<u32>;
// Which lanes' lights survived, to pack them. Two masks, alternating by
// batch, so one can be cleared while the other is read.
var<workgroup> batch_mask: array<array<atomic<u32>, MASK_WORDS>, 2>;
// View-space position and 1 / range^2 (with_inverse_range).
var<workgroup> batch_view: array<vec4<f32>, BATCH>;
// The lights' intensities (their records' `intensity`), read once per block.
var<workgroup> batch_intensity: array<vec4<f32>, BATCH>;
var<workgroup> batch_light: array<u32, BATCH>;
#ifdef MERGED
// Each survivor's band, 0 where the whole block lies on the side it keeps.
var<workgroup> batch_band: array<vec4<f32>, BATCH>;
#endif

fn light_index(slot: u32) -> u32 {
    return batch_light[slot];
}

// Whether this pixel shades the survivor at `slot`: with MERGED, the side
// of its band the pixel lies on (`band_keeps`); every survivor without.
fn keeps_slot(slot: u32, p: vec3<f32>) -> bool {
#ifdef MERGED
    return band_keeps(batch_band[slot], p);
#else
    return true;
#endif
}

fn light_radiance(slot: u32) -> vec3<f32> {
    return batch_intensity[slot].rgb;
}

// Floats to unsigned integers in the same order, for atomicMin/Max.
fn ordered(f: f32) -> u32 {
    let b = bitcast<u32>(f);
    return select(b | 0x80000000u, ~b, (b & 0x80000000u) != 0u);
}

fn unordered(u: u32) -> f32 {
    return bitcast<f32>(select(~u, u & 0x7fffffffu, (u & 0x80000000u) != 0u));
}
// From a batch's survivor mask (`batch_mask[parity]`, a bit per lane):
// x, the place of `lane`'s light among the survivors (how many survived
// before it, in list order), and y, how many survived. Both walks pack their
// survivors by it, so the sums keep the list's order.
fn survivor_place(parity: u32, lane: u32) -> vec2<u32> {
    var survivors = 0u;
    var place = 0u;
    for (var w = 0u; w < MASK_WORDS; w++) {
        let word = atomicLoad(&batch_mask[parity][w]);
        let before = select(0u, select(word, word & ((1u << (lane % 32u)) - 1u), w == lane / 32u), w <= lane / 32u);
        place += countOneBits(before);
        survivors += countOneBits(word);
    }
    return vec2<u32>(place, survivors);
}

#ifdef TILED
// TILED (LightLoop::Tiled): the clustered walk over depth-bounded tiles
// (Harada's 2.5D culling over Olsson's froxel lists). Per 16x16 tile: the
// slices its pixels occupy (a bit each, so the empty slices between a
// sphere and the floor behind it are not read), the box around its points
// and 32 depth bins between their nearest and farthest (a light whose depth
// range covers no occupied bin is dropped), and a box per 32 lanes (8x4
// pixels). The occupied slices' lists are read as one sequence, 256 entries
// a round, so rounds are full however short each list is; a survivor keeps
// its slice and which lane groups' boxes it touches, and a lane group skips
// the others together. A pixel shades only its own slice's entries, in list
// order: the same lights in the same order as the clustered walk.
const WARPS: u32 = 8u;
// Slices a bit each: ClusterGrid::SLICES stays within 32 (cook_torrance.rs).
const MAX_TILE_SLICES: u32 = 32u;
const DEPTH_BINS: f32 = 32.0;
var<workgroup> tile_slices: atomic<u32>;
var<workgroup> depth_bins: atomic<u32>;
var<workgroup> warp_slices: array<atomic<u32>, WARPS>;
var<workgroup> warp_lo: array<array<atomic<u32>, 3>, WARPS>;
var<workgroup> warp_hi: array<array<atomic<u32>, 3>, WARPS>;
// The lane groups' boxes as floats (nearest, farthest corner), made once.
var<workgroup> warp_box: array<array<vec3<f32>, 2>, WARPS>;
// Each slice's list (first entry, length; 0 for unoccupied slices) and
// where it starts in the sequence of all of them.
var<workgroup> slice_first: array<u32, MAX_TILE_SLICES>;
var<workgroup> slice_count: array<u32, MAX_TILE_SLICES>;
var<workgroup> slice_start: array<u32, MAX_TILE_SLICES>;
var<workgroup> total_read: u32;
// A survivor's slice (low 8 bits) and the lane groups it may reach (bits 8..15).
var<workgroup> batch_tag: array<u32, BATCH>;

// A view depth's bin between the tile's nearest and farthest (z: view space,
// negative). Monotonic in z, so a pixel's bin lies within the bins of any
// depth range holding it.
fn depth_bin(z: f32, lo: f32, scale: f32) -> u32 {
    return u32(clamp((z - lo) * scale, 0.0, DEPTH_BINS - 1.0));
}

fn sphere_touches(lv: vec4<f32>, lo: vec3<f32>, hi: vec3<f32>) -> bool {
    let offset = lv.xyz - clamp(lv.xyz, lo, hi);
    return dot(offset, offset) < lv.w * lv.w;
}


// Every lane calls it (barriers). `slice`: the pixel's, when `covered`.
fn walk_tiled(lane: u32, wid: vec2<u32>, covered: bool, slice: u32, p: vec3<f32>, pw: vec3<f32>,
              surface: BrdfSurface, sums: ptr<function, LightSums>) {
    let warp = lane / 32u;
    if (lane == 0u) {
        for (var i = 0u; i < 3u; i++) {
            atomicStore(&box_lo[i], 0xffffffffu);
            atomicStore(&box_hi[i], 0u);
        }
        atomicStore(&tile_slices, 0u);
        atomicStore(&depth_bins, 0u);
    }
    if (lane < WARPS) {
        for (var i = 0u; i < 3u; i++) {
            atomicStore(&warp_lo[lane][i], 0xffffffffu);
            atomicStore(&warp_hi[lane][i], 0u);
        }
        atomicStore(&warp_slices[lane], 0u);
    }
    if (lane < MASK_WORDS) {
        atomicStore(&batch_mask[0][lane], 0u);
        atomicStore(&batch_mask[1][lane], 0u);
    }
    workgroupBarrier();
    if (covered) {
        let q = vec3<u32>(ordered(p.x), ordered(p.y), ordered(p.z));
        for (var i = 0u; i < 3u; i++) {
            atomicMin(&box_lo[i], q[i]);
            atomicMax(&box_hi[i], q[i]);
            atomicMin(&warp_lo[warp][i], q[i]);
            atomicMax(&warp_hi[warp][i], q[i]);
        }
        atomicOr(&tile_slices, 1u << slice);
        atomicOr(&warp_slices[warp], 1u << slice);
    }
    workgroupBarrier();
    let lo = vec3<f32>(unordered(atomicLoad(&box_lo[0])), unordered(atomicLoad(&box_lo[1])), unordered(atomicLoad(&box_lo[2])));
    let hi = vec3<f32>(unordered(atomicLoad(&box_hi[0])), unordered(atomicLoad(&box_hi[1])), unordered(atomicLoad(&box_hi[2])));
    if (lane < WARPS) {
        // An empty group's box is NaN; its slice bits are 0, so it is never tested.
        warp_box[lane][0] = vec3<f32>(unordered(atomicLoad(&warp_lo[lane][0])), unordered(atomicLoad(&warp_lo[lane][1])), unordered(atomicLoad(&warp_lo[lane][2])));
        warp_box[lane][1] = vec3<f32>(unordered(atomicLoad(&warp_hi[lane][0])), unordered(atomicLoad(&warp_hi[lane][1])), unordered(atomicLoad(&warp_hi[lane][2])));
    }
    // 0 when the tile is flat in depth (or empty): one bin, no division by 0.
    let scale = select(0.0, DEPTH_BINS / (hi.z - lo.z), hi.z > lo.z);
    if (covered) {
        atomicOr(&depth_bins, 1u << depth_bin(p.z, lo.z, scale));
    }
    // The occupied slices' lists, a lane each.
    let occupied = atomicLoad(&tile_slices);
    let tile = min(wid * GROUP / u32(grid.depth.w), grid.dims.xy - 1u);
    if (lane < MAX_TILE_SLICES) {
        var first = 0u;
        var count = 0u;
        if (lane < grid.dims.z && (occupied & (1u << lane)) != 0u) {
            let cluster = (lane * grid.dims.y + tile.y) * grid.dims.x + tile.x;
            first = offsets[cluster];
            // Never past the end of a cut list (see the clustered walk).
            count = min(counts[cluster], arrayLength(&indices) - min(first, arrayLength(&indices)));
        }
        slice_first[lane] = first;
        slice_count[lane] = count;
    }
    workgroupBarrier();
    if (lane == 0u) {
        var running = 0u;
        for (var z = 0u; z < MAX_TILE_SLICES; z++) {
            slice_start[z] = running;
            running += slice_count[z];
        }
        total_read = running;
    }
    let total = workgroupUniformLoad(&total_read);
    let bins = atomicLoad(&depth_bins);
    var round = 0u;
    for (var start = 0u; start < total; start += BATCH) {
        let parity = round & 1u;
        let k = start + lane;
        var survives = false;
        var light = 0u;
        var lv = vec4<f32>(0.0);
        var intensity = vec4<f32>(0.0);
        var tag = 0u;
        if (k < total) {
            // The last slice whose list starts at or before k (empty
            // slices start where the next one does, and lose to it).
            var z = 0u;
            for (var step = MAX_TILE_SLICES / 2u; step > 0u; step /= 2u) {
                if (slice_start[z + step] <= k) {
                    z += step;
                }
            }
            light = indices[slice_first[z] + k - slice_start[z]];
            lv = view_lights[light];
            // A light without a range lights nothing (shade leaves it to this test).
            survives = lv.w > 0.0 && sphere_touches(lv, lo, hi);
            if (survives) {
                // Its depth range, widened a little so that rounding never
                // drops a light that reaches a pixel of an occupied bin.
                let reach = lv.w * 1.001;
                let b0 = depth_bin(lv.z - reach, lo.z, scale);
                let b1 = depth_bin(lv.z + reach, lo.z, scale);
                let range = (0xffffffffu >> (31u - b1)) & (0xffffffffu << b0);
                survives = (range & bins) != 0u;
            }
            if (survives) {
                var warps = 0u;
                for (var w = 0u; w < WARPS; w++) {
                    let in_slice = (atomicLoad(&warp_slices[w]) & (1u << z)) != 0u;
                    if (in_slice && sphere_touches(lv, warp_box[w][0], warp_box[w][1])) {
                        warps |= 1u << w;
                    }
                }
                survives = warps != 0u;
                tag = z | (warps << 8u);
            }
            if (survives) {
                atomicOr(&batch_mask[parity][lane / 32u], 1u << (lane % 32u));
                intensity = lights[light].intensity;
            }
        }
        if (lane < MASK_WORDS) {
            atomicStore(&batch_mask[1u - parity][lane], 0u);
        }
        workgroupBarrier();
        let counted = survivor_place(parity, lane);
        let place = counted.x;
        let survivors = counted.y;
        if (survives) {
            batch_view[place] = with_inverse_range(lv);
            batch_intensity[place] = intensity;
            batch_light[place] = light;
            batch_tag[place] = tag;
        }
        workgroupBarrier();
        // Whole lane groups skip a survivor none of their pixels can see
        // (the tag is the same for all of them); a lane of another slice
        // skips it alone.
        let group_bit = 1u << (8u + warp);
        for (var slot = 0u; slot < survivors; slot++) {
            let entry = batch_tag[slot];
            if ((entry & group_bit) == 0u) {
                continue;
            }
            if (covered && (entry & 0xffu) == slice) {
                shade(slot, batch_view[slot], p, pw, surface, sums);
            }
        }
        round++;
    }
}
#endif
#endif
#else
fn light_index(slot: u32) -> u32 {
    return slot;
}

fn light_radiance(slot: u32) -> vec3<f32> {
    return lights[slot].intensity.rgb;
}
#endif

@compute @workgroup_size(16, 16)
fn main(@builtin(local_invocation_index) lane: u32, @builtin(workgroup_id) wid: vec3<u32>) {
    let size = vec2<u32>(camera.size.xy);
    // Each 32 lanes (a warp on NVIDIA, half a wave elsewhere) shade an 8x4
    // block of the 16x16, not two rows of 16: a light's sphere edge or a
    // depth slice boundary crosses fewer of them, so fewer lanes idle while
    // their neighbours shade a light only they reach. Which pixel a lane
    // shades changes nothing in its sums.
    let warp = lane / 32u;
    let local = vec2<u32>((warp & 1u) * 8u + (lane & 7u), (warp >> 1u) * 4u + ((lane >> 3u) & 3u));
    let pixel = wid.xy * GROUP + local;
    let inside = pixel.x < size.x && pixel.y < size.y;
    var d = 0.0;
    if (inside) {
#ifdef LIGHT_SUM
        // The fused sets' entry read the pixel's G-buffer texels once for all of them.
        d = gbuffer_depth;
#else
        d = textureLoad(depth, pixel, 0).r;
#endif
    }
    // No early return: with CLUSTERED every lane takes part in the barriers.
    let covered = inside && d > 0.0;
    if (inside && !covered) {
#ifdef LIGHT_SUM
        // A fused set's own targets only where something reads them (OUT_*).
#ifdef OUT_DIFFUSE
        textureStore(out_diffuse, pixel, vec4<f32>(0.0));
#endif
#ifdef OUT_SPECULAR
        textureStore(out_specular, pixel, vec4<f32>(0.0));
#endif
#ifdef OUT_SSS
        textureStore(out_sss, pixel, vec4<f32>(0.0));
#endif
#else
        textureStore(out_diffuse, pixel, vec4<f32>(0.0));
        textureStore(out_specular, pixel, vec4<f32>(0.0));
#ifdef FAKE_SSS
        textureStore(out_sss, pixel, vec4<f32>(0.0));
#endif
#endif
    }
    let uv = (vec2<f32>(pixel) + 0.5) * camera.size.zw;
    let ndc = vec2<f32>(uv.x * 2.0 - 1.0, 1.0 - uv.y * 2.0);
    let view_h = camera.projection_inverse * vec4<f32>(ndc, d, 1.0);
    let p = view_h.xyz / view_h.w;
    let pw = (camera.view_inverse * vec4<f32>(p, 1.0)).xyz;
    var n = vec3<f32>(0.0, 0.0, 1.0);
    var texel = vec4<f32>(0.0);
    if (inside) {
#ifdef LIGHT_SUM
        n = safe_normalize(gbuffer_normal.xyz, vec3<f32>(0.0, 0.0, 1.0));
        texel = gbuffer_color;
#else
        n = safe_normalize(textureLoad(normals, pixel, 0).xyz, vec3<f32>(0.0, 0.0, 1.0));
        texel = textureLoad(color, pixel, 0);
#endif
    }
    let v = safe_normalize(-p, vec3<f32>(0.0, 0.0, 1.0));
#ifdef SHADOWS
    normal_world = safe_normalize((camera.view_inverse * vec4<f32>(n, 0.0)).xyz, vec3<f32>(0.0, 1.0, 0.0));
    view_depth = -p.z;
#endif
    let albedo = texel.rgb;
    let material = channel_to_id(texel.a);
    var rm = vec3<f32>(0.5, 0.0, DIELECTRIC_F0);
    if (covered) {
#ifdef MATERIALS
        // A texture scales (roughness, metallic, reflectance); kept within 0..1.
        rm = clamp(feature_param_at(material, FEATURE_COOK_TORRANCE, 0u, vec4<f32>(0.5, 0.0, 0.04, 0.0), pixel).xyz, vec3<f32>(0.0), vec3<f32>(1.0));
#else
        rm = vec3<f32>(surfaces[material % arrayLength(&surfaces)].roughness_metallic, DIELECTRIC_F0);
#ifdef SURFACE_TARGET
        // A surface the G-buffer resolved (surface maps, a shader node
        // material) brings its own roughness and metallic.
        let resolved = surface_at(pixel);
        if (resolved.written) {
            rm = vec3<f32>(resolved.roughness, resolved.metallic, DIELECTRIC_F0);
        }
#endif
#endif
    }

    // rm: roughness, metallic, reflectance (the dielectric F0).
    let surface = brdf_surface(n, v, albedo, rm.x, rm.y, rm.z);
    var sums = no_light_sums();
#ifdef ANISOTROPY
    var aniso_texel = vec4<f32>(0.0);
    if (covered && has_feature(material, FEATURE_ANISOTROPY)) {
        aniso_texel = textureLoad(anisotropy_target, pixel, 0);
    }
    aniso = anisotropic_surface(surface, aniso_texel.xyz, aniso_texel.w);
#endif
#ifdef CUSTOM_LIGHT
    custom_diffuse = vec3<f32>(0.0);
    custom_specular = vec3<f32>(0.0);
    custom_input.position = pw;
    custom_input.normal = safe_normalize((camera.view_inverse * vec4<f32>(n, 0.0)).xyz, vec3<f32>(0.0, 1.0, 0.0));
    custom_input.view = safe_normalize(camera.position.xyz - pw, custom_input.normal);
    custom_input.albedo = albedo;
    custom_input.roughness = rm.x;
    custom_input.metallic = rm.y;
    custom_input.reflectance = rm.z;
    custom_input.material_id = material;
    custom_input.pixel = pixel;
#ifdef LIGHT_SUN
    custom_input.kind = LIGHT_KIND_SUN;
#else
#ifdef LIGHT_SPOT
    custom_input.kind = LIGHT_KIND_SPOT;
#else
    custom_input.kind = LIGHT_KIND_POINT;
#endif
#endif
#endif
#ifdef FAKE_SSS
    sss_tint = vec3<f32>(0.0);
    if (covered) {
        let sss = feature_param_at(material, FEATURE_FAKE_SSS, 0u, vec4<f32>(0.0), pixel);
        sss_tint = max(sss.rgb, vec3<f32>(0.0)) * max(sss.a, 0.0) * albedo;
    }
    sss_sum = vec3<f32>(0.0);
#endif
#ifdef CLEARCOAT
    coat_factor = 0.0;
    var coat_roughness = 0.0;
    var coat_n = n;
    if (covered) {
        // Scaled by its maps where the G-buffer resolved them.
        let coat = clearcoat_at(material, pixel);
        coat_factor = clamp(coat.x, 0.0, 1.0);
        coat_roughness = clamp(coat.y, 0.0, 1.0);
        if (coat_factor > 0.0) {
            coat_n = clearcoat_normal_at(pixel, n);
        }
    }
    coat_surface = brdf_surface(coat_n, v, vec3<f32>(0.0), coat_roughness, 0.0, DIELECTRIC_F0);
    coat_sum = vec3<f32>(0.0);
#endif
#ifdef IRIDESCENCE
    film_factor = 0.0;
    film_fresnel = vec3<f32>(0.0);
    film_lit = vec3<f32>(0.0);
    if (covered) {
        // Its maps' factor and thickness where the G-buffer resolved them.
        let film = film_at(material, pixel, sheen_film_texel(pixel));
        film_factor = film.x;
        if (film_factor > 0.0) {
            film_fresnel = iridescence_fresnel(rm.z, albedo, rm.y, surface.n_dot_v, film.y, film.z);
        }
    }
#endif
#ifdef SHEEN
    sheen_color = vec3<f32>(0.0);
    sheen_roughness = 0.0;
    sheen_sum = vec3<f32>(0.0);
    if (covered) {
        // Its maps' colour and roughness where the G-buffer resolved them.
        let sheen = sheen_at(material, sheen_film_texel(pixel));
        sheen_color = sheen.rgb;
        sheen_roughness = sheen.a;
    }
#endif
#ifdef CLUSTERED
    // The pixel's depth slice (covered pixels only).
    var slice = 0u;
    if (covered) {
        slice = u32(clamp(floor(log(max(-p.z, grid.depth.x) / grid.depth.x) / grid.depth.z * f32(grid.dims.z)), 0.0, f32(grid.dims.z - 1u)));
    }
#ifdef PER_PIXEL
    // CPU adapters: every pixel walks its own froxel list, with no
    // workgroup memory and no barrier (llvmpipe runs a barrier as a
    // coroutine switch per 8 lanes). Same lights, same order as the
    // clustered walk's survivors (those it drops reach no pixel of the block).
    if (covered) {
        let tile = min(pixel / u32(grid.depth.w), grid.dims.xy - 1u);
        let cluster = (slice * grid.dims.y + tile.y) * grid.dims.x + tile.x;
        let first = offsets[cluster];
        let count = min(counts[cluster], arrayLength(&indices) - min(first, arrayLength(&indices)));
        for (var k = 0u; k < count; k++) {
            let light = indices[first + k];
            let lv = view_lights[light];
            // A light without a range lights nothing (shade leaves it to this test).
            if (!(lv.w > 0.0)) {
                continue;
            }
#ifdef MERGED
            if (!band_keeps(view_bands[light], p)) {
                continue;
            }
#endif
            shade(light, with_inverse_range(lv), p, pw, surface, &sums);
        }
    }
#else
#ifdef TILED
    walk_tiled(lane, wid.xy, covered, slice, p, pw, surface, &sums);
#else
    if (lane == 0u) {
        for (var i = 0u; i < 3u; i++) {
            atomicStore(&box_lo[i], 0xffffffffu);
            atomicStore(&box_hi[i], 0u);
        }
        atomicStore(&slice_span[0], 0xffffffffu);
        atomicStore(&slice_span[1], 0u);
    }
    if (lane < MASK_WORDS) {
        atomicStore(&batch_mask[0][lane], 0u);
        atomicStore(&batch_mask[1][lane], 0u);
    }
    workgroupBarrier();
    if (covered) {
        atomicMin(&box_lo[0], ordered(p.x));
        atomicMin(&box_lo[1], ordered(p.y));
        atomicMin(&box_lo[2], ordered(p.z));
        atomicMax(&box_hi[0], ordered(p.x));
        atomicMax(&box_hi[1], ordered(p.y));
        atomicMax(&box_hi[2], ordered(p.z));
        atomicMin(&slice_span[0], slice);
        atomicMax(&slice_span[1], slice);
    }
    workgroupBarrier();
    if (lane == 0u) {
        span_read = vec2<u32>(atomicLoad(&slice_span[0]), atomicLoad(&slice_span[1]));
    }
    // A block of only background has an empty span (first > last).
    let span = workgroupUniformLoad(&span_read);
    let lo = vec3<f32>(unordered(atomicLoad(&box_lo[0])), unordered(atomicLoad(&box_lo[1])), unordered(atomicLoad(&box_lo[2])));
    let hi = vec3<f32>(unordered(atomicLoad(&box_hi[0])), unordered(atomicLoad(&box_hi[1])), unordered(atomicLoad(&box_hi[2])));
    // The block lies in one froxel column: tiles are a multiple of GROUP pixels (clusters.rs).
    let tile = min(wid.xy * GROUP / u32(grid.depth.w), grid.dims.xy - 1u);
    var round = 0u;
    for (var z = span.x; z <= span.y && z < grid.dims.z; z++) {
        if (lane == 0u) {
            let cluster = (z * grid.dims.y + tile.y) * grid.dims.x + tile.x;
            let first = offsets[cluster];
            // A list that overflowed the index buffer (sized for every light in
            // 256 froxels, see clusters.rs) is cut at its end; never read past it.
            let count = min(counts[cluster], arrayLength(&indices) - min(first, arrayLength(&indices)));
            froxel_read = vec2<u32>(first, count);
        }
        let froxel = workgroupUniformLoad(&froxel_read);
        for (var start = 0u; start < froxel.y; start += BATCH) {
            let parity = round & 1u;
            let k = start + lane;
            var survives = false;
            var light = 0u;
            var lv = vec4<f32>(0.0);
            var intensity = vec4<f32>(0.0);
#ifdef MERGED
            var band = vec4<f32>(0.0);
#endif
            if (k < froxel.y) {
                light = indices[froxel.x + k];
                lv = view_lights[light];
                let offset = lv.xyz - clamp(lv.xyz, lo, hi);
                // A light without a range lights nothing (shade leaves it to this test).
                survives = lv.w > 0.0 && dot(offset, offset) < lv.w * lv.w;
#ifdef MERGED
                band = view_bands[light];
                survives = survives && band_reaches(band, lo, hi);
                if (band_holds_box(band, lo, hi)) {
                    // Every pixel of the block keeps it: no test per pixel.
                    band.w = 0.0;
                }
#endif
                if (survives) {
                    atomicOr(&batch_mask[parity][lane / 32u], 1u << (lane % 32u));
                    // Read before the barrier, so the wait for it overlaps the other lanes'.
                    intensity = lights[light].intensity;
                }
            }
            // The other mask was last read before the previous batch's second barrier.
            if (lane < MASK_WORDS) {
                atomicStore(&batch_mask[1u - parity][lane], 0u);
            }
            workgroupBarrier();
            // The survivors, packed in list order: each one's place is the
            // count of survivors before it. The walk is then a counted loop
            // with no bit arithmetic per light, and the sums keep their order.
            let counted = survivor_place(parity, lane);
            let place = counted.x;
            let survivors = counted.y;
            // The packed arrays were last read by the previous batch's walk,
            // which every lane left before the barrier above.
            if (survives) {
                batch_view[place] = with_inverse_range(lv);
                batch_intensity[place] = intensity;
                batch_light[place] = light;
#ifdef MERGED
                batch_band[place] = band;
#endif
            }
            workgroupBarrier();
            if (covered && slice == z) {
                // Two lights a step, their positions loaded together: the
                // second's load and range test overlap the first's. With
                // MERGED, a block across a band holds a cube's members and
                // its merged light: each pixel keeps its side.
                var slot = 0u;
                for (; slot + 1u < survivors; slot += 2u) {
                    let first = batch_view[slot];
                    let second = batch_view[slot + 1u];
                    if (keeps_slot(slot, p)) {
                        shade(slot, first, p, pw, surface, &sums);
                    }
                    if (keeps_slot(slot + 1u, p)) {
                        shade(slot + 1u, second, p, pw, surface, &sums);
                    }
                }
                if (slot < survivors && keeps_slot(slot, p)) {
                    shade(slot, batch_view[slot], p, pw, surface, &sums);
                }
            }
            round++;
        }
    }
#endif
#endif
#else
    if (covered) {
        for (var i = 0u; i < grid.dims.w; i++) {
            // Few lights: each moved to view space here, which costs less
            // than a dispatch of its own and the barrier after it.
            let record = lights[i];
            // The range the cutoff leaves, as the clusters' transform makes it.
            let lv = vec4<f32>((camera.view * vec4<f32>(record.position_range.xyz, 1.0)).xyz, cutoff_range(record.position_range.w, record.intensity.rgb, grid.falloff.x));
#ifndef LIGHT_SUN
            // A light without a range lights nothing (shade leaves it to this test).
            if (!(lv.w > 0.0)) {
                continue;
            }
#endif
            shade(i, with_inverse_range(lv), p, pw, surface, &sums);
        }
    }
#endif
    if (!covered) {
        return;
    }
#ifdef CUSTOM_LIGHT
    let diffuse = max(custom_diffuse, vec3<f32>(0.0));
    let specular = max(custom_specular, vec3<f32>(0.0));
#else
    let lit = light_sums_brdf(surface, sums);
    var diffuse = lit.diffuse;
    var specular = lit.specular;
#ifdef IRIDESCENCE
    if (film_factor > 0.0) {
        // F = mix(Schlick's, the film's, factor): the film's F is one per
        // pixel, so its specular is F times the lobes' sum (D V N.L), its
        // diffuse (1 - F) times the Lambert term's.
        specular = mix(specular, film_fresnel * sums.specular, film_factor);
        diffuse = mix(diffuse, (vec3<f32>(1.0) - film_fresnel) * surface.diffuse * film_lit, film_factor);
    }
#endif
#ifdef ENERGY_COMPENSATION
    specular *= surface_energy_compensation(surface);
#endif
#ifdef SHEEN
    if (any(sheen_color > vec3<f32>(0.0))) {
        // The sheen lies over the base: what it reflects the base does not
        // receive (the albedo scaling); the coat, below, lies over both.
        let scaling = sheen_scaling(sheen_color, surface.n_dot_v, sheen_roughness);
        diffuse *= scaling;
        specular = specular * scaling + sheen_color * sheen_sum;
    }
#endif
#ifdef CLEARCOAT
    if (coat_factor > 0.0) {
        // What the coat reflects does not reach the base, nor leave it.
        let dim = 1.0 - coat_factor * (DIELECTRIC_F0 + (1.0 - DIELECTRIC_F0) * schlick_weight(coat_surface.n_dot_v));
        diffuse *= dim;
        specular = specular * dim + coat_factor * coat_sum;
    }
#endif
#endif
#ifdef LIGHT_SUM
    // Fused light sets that CompositeLight reads as one pair of sums
    // (crates/render/src/lighting/light_sets/sums.rs): this set's terms, as
    // its own targets would hold them (clamped; the subsurface term, which
    // CompositeLight adds to the rest, with the diffuse), added to the sums
    // the generated entry writes once; its own targets only where
    // something else reads them (OUT_*).
    let set_diffuse = min(diffuse, vec3<f32>(HALF_MAX));
    let set_specular = min(specular, vec3<f32>(HALF_MAX));
    *light_diffuse += set_diffuse;
    *light_specular += set_specular;
#ifdef FAKE_SSS
    *light_diffuse += min(sss_sum, vec3<f32>(HALF_MAX));
#endif
#ifdef OUT_DIFFUSE
    textureStore(out_diffuse, pixel, vec4<f32>(set_diffuse, 1.0));
#endif
#ifdef OUT_SPECULAR
    textureStore(out_specular, pixel, vec4<f32>(set_specular, 1.0));
#endif
#ifdef OUT_SSS
    textureStore(out_sss, pixel, vec4<f32>(min(sss_sum, vec3<f32>(HALF_MAX)), 1.0));
#endif
#else
    textureStore(out_diffuse, pixel, vec4<f32>(min(diffuse, vec3<f32>(HALF_MAX)), 1.0));
    textureStore(out_specular, pixel, vec4<f32>(min(specular, vec3<f32>(HALF_MAX)), 1.0));
#ifdef FAKE_SSS
    textureStore(out_sss, pixel, vec4<f32>(min(sss_sum, vec3<f32>(HALF_MAX)), 1.0));
#endif
#endif
}
