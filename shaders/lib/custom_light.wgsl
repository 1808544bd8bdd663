// The light function the CookTorrance loop calls with CUSTOM_LIGHT. A light
// shader node (`// @light`) replaces this module with its own file when its
// permutation is composed (crates/render/src/shaders/cache.rs,
// `ShaderCache::surface_pipeline`); this default (Lambert, no specular)
// keeps every CUSTOM_LIGHT permutation composable on its own.
#define_import_path spreadlight::custom_light
#import spreadlight::light_shader::{LightInput, LightOutput, light_lambert}

fn light(in: LightInput) -> LightOutput {
    return LightOutput(light_lambert(in), vec3<f32>(0.0));
}
