// What a light shader node (`// @light point spot sun`, docs/shader-nodes.md)
// receives for one light at one pixel, and returns. The CookTorrance light
// loop (shaders/lighting/cook_torrance.wgsl, CUSTOM_LIGHT), with the same
// clusters and shadow maps, calls the node's
// `fn light(in: LightInput) -> LightOutput` for every light of the buffer
// that reaches the pixel (in range, inside a spot's frustum) and sums the
// outputs into the Diffuse and Specular targets CompositeLight reads.
// Everything is world space, as a material's SurfaceInput is.
#define_import_path spreadlight::light_shader

// `LightInput.kind`: the light buffer's type (one permutation per type).
const LIGHT_KIND_POINT: u32 = 0u;
const LIGHT_KIND_SPOT: u32 = 1u;
const LIGHT_KIND_SUN: u32 = 2u;

const LIGHT_PI: f32 = 3.14159265358979;

struct LightInput {
    // The surface, from the G-buffer.
    // World-space position of the surface at the pixel.
    position: vec3<f32>,
    // World-space unit normal.
    normal: vec3<f32>,
    // Unit vector from the surface towards the camera.
    view: vec3<f32>,
    // Linear RGB albedo (MRE `color`).
    albedo: vec3<f32>,
    // CookTorrance's parameters of the pixel's material: the material world's
    // CookTorrance feature, a shader node material's or surface maps' output,
    // else the node's Roughness and Metallic pins (0.5 and 0 by default).
    roughness: f32,
    metallic: f32,
    // Dielectric F0 (0.04 without a material world).
    reflectance: f32,
    material_id: u32,
    pixel: vec2<u32>,
    // The light.
    // LIGHT_KIND_POINT, LIGHT_KIND_SPOT or LIGHT_KIND_SUN.
    kind: u32,
    // Its index in its light buffer.
    index: u32,
    // Unit vector from the surface towards the light (a sun: against its direction).
    direction: vec3<f32>,
    // dot(normal, direction), not clamped: negative behind the surface.
    n_dot_l: f32,
    // From the surface to the light (0 for a sun).
    distance: f32,
    // Colour times intensity (cd) or illuminance (lux); a spot's cone or
    // projected texture applied.
    radiance: vec3<f32>,
    // The windowed inverse-square falloff (0 from the light's range on); 1 for a sun.
    attenuation: f32,
    // 1 lit, 0 in the light's shadow (its ShadowMap slice, filtered); 1
    // without shadow maps.
    shadow: f32,
}

struct LightOutput {
    // Diffuse radiance towards the camera, albedo applied (as CookTorrance's
    // Diffuse: CompositeLight adds it as it is).
    diffuse: vec3<f32>,
    // Specular radiance towards the camera.
    specular: vec3<f32>,
}

// No light.
fn light_output_none() -> LightOutput {
    return LightOutput(vec3<f32>(0.0), vec3<f32>(0.0));
}

// The light arriving at the surface head on: radiance x attenuation x shadow.
fn light_incident(in: LightInput) -> vec3<f32> {
    return in.radiance * (in.attenuation * in.shadow);
}

// Lambert's diffuse, as CookTorrance's: albedo / pi x incident x N.L.
fn light_lambert(in: LightInput) -> vec3<f32> {
    return in.albedo * light_incident(in) * (max(in.n_dot_l, 0.0) / LIGHT_PI);
}
