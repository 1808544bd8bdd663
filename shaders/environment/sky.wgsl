// Sky: the background where the G-buffer's depth is empty (0, reversed-Z),
// a procedural sky seen along each pixel's view ray (spreadlight::sky), or
// with ENVIRONMENT an environment cube (a file's or a baked sky's, level 0:
// unblurred). Elsewhere the input passes through. Radiance is clamped below
// half-float overflow; a zero direction falls back to straight up.
//
// FOG: a Fog under or over this Sky, in this one pass. The two touch
// disjoint pixels (the fog only surfaces, the sky only the empty
// background), so in either order each pixel is the fog's
// (spreadlight::fog, its parameters at binding 7) or the sky's, as the two
// passes would leave it (but for the half-float rounding of the image
// between them, when the input is finer). The frame graph runs this in
// their place when nothing else reads the inner pass's image
// (crates/render/src/environment/pass.rs).
#import spreadlight::camera::Camera
#import spreadlight::sky::{Sky, sky_radiance, view_direction}
#ifdef FOG
#import spreadlight::fog::{Fog, fogged}
#endif

@group(0) @binding(0) var<uniform> camera: Camera;
@group(0) @binding(1) var<uniform> sky: Sky;
@group(0) @binding(2) var source: texture_2d<f32>;
@group(0) @binding(3) var depth: texture_2d<f32>;
@group(0) @binding(4) var output: texture_storage_2d<rgba16float, write>;
#ifdef ENVIRONMENT
@group(0) @binding(5) var environment: texture_cube<f32>;
@group(0) @binding(6) var environment_sampler: sampler;
#endif
#ifdef FOG
@group(0) @binding(7) var<uniform> fog: Fog;
#endif

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = vec2<u32>(camera.size.xy);
    if (id.x >= size.x || id.y >= size.y) {
        return;
    }
    let pixel = id.xy;
    let surface = textureLoad(depth, pixel, 0).r;
    if (surface > 0.0) {
        let lit = textureLoad(source, pixel, 0);
#ifdef FOG
        textureStore(output, pixel, fogged(camera, fog, lit, pixel, surface));
#else
        textureStore(output, pixel, lit);
#endif
        return;
    }
    // The view ray through the pixel, in world space.
    let d = view_direction(camera, pixel);
#ifdef ENVIRONMENT
    let color = min(max(textureSampleLevel(environment, environment_sampler, d, 0.0).rgb, vec3<f32>(0.0)), vec3<f32>(65000.0));
#else
    let color = sky_radiance(sky, d);
#endif
    textureStore(output, pixel, vec4<f32>(color, 1.0));
}
