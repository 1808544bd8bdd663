// What a shader node material (a DeferredBase layer's custom surface
// function, docs/shader-nodes.md) receives at a pixel and returns. The
// G-buffer surface resolve fills a SurfaceInput from the pixel's triangle,
// calls the material's `fn surface(in: SurfaceInput) -> SurfaceOutput`,
// and writes the result into the MRE targets: albedo into `color`, the normal
// into `normals` (in view space), roughness, metallic, occlusion and emission
// into the `surface` target that lighting reads.
#define_import_path spreadlight::surface

struct SurfaceInput {
    // World-space position of the surface at the pixel.
    position: vec3<f32>,
    // The same point in the mesh's own (object) space: patterns that stick
    // to a moving object.
    object_position: vec3<f32>,
    // World-space unit normal (after the layer's normal map, if any).
    normal: vec3<f32>,
    // Texture coordinates (Texture Coordinates or Triplanar on the layer; 0 otherwise).
    uv: vec2<f32>,
    // The instance's Color (times the layer's Color Texture).
    color: vec4<f32>,
    // Unit vector from the surface towards the camera, world space.
    view: vec3<f32>,
    pixel: vec2<u32>,
    material_id: u32,
    object_id: u32,
}

struct SurfaceOutput {
    // Linear RGB albedo (base colour), not negative.
    albedo: vec3<f32>,
    // World-space normal; need not be unit length (a zero one keeps the input's).
    normal: vec3<f32>,
    roughness: f32,
    metallic: f32,
    // Ambient occlusion, 1: none.
    occlusion: f32,
    // Emitted linear radiance.
    emission: vec3<f32>,
}

// The surface as DeferredBase would shade it without a material: the
// instance colour and normal, roughness 0.5, not metallic, no emission.
fn surface_default(in: SurfaceInput) -> SurfaceOutput {
    var out: SurfaceOutput;
    out.albedo = in.color.rgb;
    out.normal = in.normal;
    out.roughness = 0.5;
    out.metallic = 0.0;
    out.occlusion = 1.0;
    out.emission = vec3<f32>(0.0);
    return out;
}

fn finite3(v: vec3<f32>, fallback: vec3<f32>) -> vec3<f32> {
    // NaN fails every comparison; infinity fails the bound.
    let ok = (v == v) & (abs(v) < vec3<f32>(3.0e38));
    return select(fallback, v, ok);
}

fn finite1(v: f32, fallback: f32) -> f32 {
    return select(fallback, v, v == v && abs(v) < 3.0e38);
}

// A material's output held to what the G-buffer can store: finite, albedo
// and emission not negative, roughness, metallic and occlusion in 0..1, a
// unit normal (`fallback` where it is zero or not finite).
fn surface_finite(out: SurfaceOutput, fallback: vec3<f32>) -> SurfaceOutput {
    var s: SurfaceOutput;
    s.albedo = clamp(finite3(out.albedo, vec3<f32>(0.0)), vec3<f32>(0.0), vec3<f32>(65000.0));
    let n = finite3(out.normal, fallback);
    let len = length(n);
    s.normal = select(fallback, n / len, len > 1e-12 && len < 3.0e38);
    s.roughness = clamp(finite1(out.roughness, 0.5), 0.0, 1.0);
    s.metallic = clamp(finite1(out.metallic, 0.0), 0.0, 1.0);
    s.occlusion = clamp(finite1(out.occlusion, 1.0), 0.0, 1.0);
    s.emission = clamp(finite3(out.emission, vec3<f32>(0.0)), vec3<f32>(0.0), vec3<f32>(65000.0));
    return s;
}
