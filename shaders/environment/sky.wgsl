// Sky: the background where the G-buffer's depth is empty (0, reversed-Z),
// a procedural sky seen along each pixel's view ray: a gradient from the
// ground colour below the horizon through the horizon colour to the zenith
// colour, and a sun disk with a glow around `sun` (the direction towards
// the sun). Elsewhere the input passes through. Radiance is clamped below
// half-float overflow; a zero direction falls back to straight up.
#import spreadlight::camera::{Camera, pixel_to_ndc}
#import spreadlight::packing::safe_normalize

struct Sky {
    zenith: vec4<f32>,
    horizon: vec4<f32>,
    ground: vec4<f32>,
    // xyz: unit direction towards the sun, w: cosine of the disk's angular radius
    sun: vec4<f32>,
    // rgb: disk radiance, w: glow strength
    sun_color: vec4<f32>,
}

@group(0) @binding(0) var<uniform> camera: Camera;
@group(0) @binding(1) var<uniform> sky: Sky;
@group(0) @binding(2) var source: texture_2d<f32>;
@group(0) @binding(3) var depth: texture_2d<f32>;
@group(0) @binding(4) var output: texture_storage_2d<rgba16float, write>;

const HALF_MAX: f32 = 65000.0;

// The sky's radiance along world direction `d`.
fn radiance(d: vec3<f32>) -> vec3<f32> {
    let up = d.y;
    var color: vec3<f32>;
    if (up >= 0.0) {
        // Steeper near the horizon, as the air thickens there.
        color = mix(sky.horizon.rgb, sky.zenith.rgb, pow(up, 0.5));
    } else {
        color = mix(sky.horizon.rgb, sky.ground.rgb, clamp(-up * 4.0, 0.0, 1.0));
    }
    let c = dot(d, sky.sun.xyz);
    let edge = sky.sun.w;
    // The disk, its edge a few thousandths of a cosine soft.
    let disk = smoothstep(edge - 1e-4, edge + 1e-4, c);
    // The glow: a lobe around the sun, fading to nothing at 90 degrees.
    let glow = pow(max(c, 0.0), 64.0) * sky.sun_color.w;
    color += sky.sun_color.rgb * (disk + glow * 0.01);
    return min(max(color, vec3<f32>(0.0)), vec3<f32>(HALF_MAX));
}

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = vec2<u32>(camera.size.xy);
    if (id.x >= size.x || id.y >= size.y) {
        return;
    }
    let pixel = id.xy;
    if (textureLoad(depth, pixel, 0).r > 0.0) {
        textureStore(output, pixel, textureLoad(source, pixel, 0));
        return;
    }
    // The view ray through the pixel, in world space.
    let ndc = pixel_to_ndc(pixel, camera.size);
    let far = camera.projection_inverse * vec4<f32>(ndc, 0.5, 1.0);
    let view_dir = far.xyz / far.w;
    let world = (camera.view_inverse * vec4<f32>(view_dir, 0.0)).xyz;
    let d = safe_normalize(world, vec3<f32>(0.0, 1.0, 0.0));
    textureStore(output, pixel, vec4<f32>(radiance(d), 1.0));
}
