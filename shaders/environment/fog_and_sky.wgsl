// Fog and a Sky over it (or the Sky, then Fog) in one pass: the two touch
// disjoint pixels (the fog only where the depth holds a surface, the sky
// only where it is empty), so in either order each pixel is the fog's
// (spreadlight::fog) or the sky's (spreadlight::sky; with ENVIRONMENT an
// environment cube's level 0), as the two passes would leave it. The frame
// graph runs this in their place when nothing else reads the first's
// output (crates/render/src/environment/pass.rs).
#import spreadlight::camera::Camera
#import spreadlight::fog::{Fog, fogged}
#import spreadlight::sky::{Sky, sky_radiance, view_direction}

@group(0) @binding(0) var<uniform> camera: Camera;
@group(0) @binding(1) var<uniform> fog: Fog;
@group(0) @binding(2) var source: texture_2d<f32>;
@group(0) @binding(3) var depth: texture_2d<f32>;
@group(0) @binding(4) var output: texture_storage_2d<rgba16float, write>;
#ifdef ENVIRONMENT
@group(0) @binding(5) var environment: texture_cube<f32>;
@group(0) @binding(6) var environment_sampler: sampler;
#endif
@group(0) @binding(7) var<uniform> sky: Sky;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = vec2<u32>(camera.size.xy);
    if (id.x >= size.x || id.y >= size.y) {
        return;
    }
    let pixel = id.xy;
    let d = textureLoad(depth, pixel, 0).r;
    if (d > 0.0) {
        textureStore(output, pixel, fogged(camera, fog, textureLoad(source, pixel, 0), pixel, d));
        return;
    }
    let dir = view_direction(camera, pixel);
#ifdef ENVIRONMENT
    let color = min(max(textureSampleLevel(environment, environment_sampler, dir, 0.0).rgb, vec3<f32>(0.0)), vec3<f32>(65000.0));
#else
    let color = sky_radiance(sky, dir);
#endif
    textureStore(output, pixel, vec4<f32>(color, 1.0));
}
