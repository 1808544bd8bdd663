// The custom surface function the G-buffer resolve calls with
// CUSTOM_SURFACE. A shader node material replaces this module with its own
// file when its layer's resolve is composed (crates/render/src/shaders.rs,
// `ShaderCache::surface_pipeline`); this default keeps every permutation of
// the resolve composable on its own.
#define_import_path spreadlight::custom_surface
#import spreadlight::surface::{SurfaceInput, SurfaceOutput, surface_default}

fn surface(in: SurfaceInput) -> SurfaceOutput {
    return surface_default(in);
}
