// The procedural sky as a function of direction, shared by the Sky
// background pass and the environment cube it can be baked into (so a
// reflection sees the same sky the background shows). Its CPU twin is
// `sky_radiance` in crates/render/src/reference/reflection.rs.
#define_import_path spreadlight::sky
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

const SKY_HALF_MAX: f32 = 65000.0;

// The sky's radiance along unit world direction `d`: a gradient from the
// ground colour below the horizon through the horizon colour to the zenith
// colour, and a sun disk with a glow. Clamped below half-float overflow.
fn sky_radiance(sky: Sky, d: vec3<f32>) -> vec3<f32> {
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
    return min(max(color, vec3<f32>(0.0)), vec3<f32>(SKY_HALF_MAX));
}

// The unit world direction of the view ray through `pixel` (straight up
// when degenerate): where the background is seen.
fn view_direction(camera: Camera, pixel: vec2<u32>) -> vec3<f32> {
    let ndc = pixel_to_ndc(pixel, camera.size);
    let far = camera.projection_inverse * vec4<f32>(ndc, 0.5, 1.0);
    let view_dir = far.xyz / far.w;
    let world = (camera.view_inverse * vec4<f32>(view_dir, 0.0)).xyz;
    return safe_normalize(world, vec3<f32>(0.0, 1.0, 0.0));
}
