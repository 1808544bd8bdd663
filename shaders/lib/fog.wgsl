// Distance and height fog over a lit pixel, shared by the Fog pass
// (environment/fog.wgsl) and Fog with a Sky over it in one pass
// (environment/sky.wgsl with FOG). Along the view ray from the camera to the
// pixel's surface, fog density is `density * exp(-falloff * (y - base))`
// (thinning with height; falloff 0 is uniform fog), starting `start` units
// from the camera. Its optical depth has a closed form (the integral of an
// exponential along a line), so it is one expression per pixel:
// transmittance T = exp(-depth), colour = lit * T + fog * (1 - T). Where
// depth is empty (the sky) the pixel passes through.
#define_import_path spreadlight::fog
#import spreadlight::camera::{Camera, pixel_to_ndc}

struct Fog {
    // rgb: fog radiance, w: density per unit length
    color_density: vec4<f32>,
    // x: height falloff per unit, y: base height, z: start distance
    shape: vec4<f32>,
}

// The optical depth from `origin` along unit `dir` over `distance`.
fn optical_depth(fog: Fog, origin: vec3<f32>, dir: vec3<f32>, distance: f32) -> f32 {
    let density = fog.color_density.w;
    let falloff = fog.shape.x;
    let start = density * exp(-falloff * (origin.y - fog.shape.y));
    let k = falloff * dir.y;
    // (1 - exp(-k d)) / k, which tends to d as k -> 0: a ray along the level.
    var integral = distance;
    if (abs(k) > 1e-5) {
        integral = (1.0 - exp(-k * distance)) / k;
    }
    return max(start * integral, 0.0);
}

// `lit` at `pixel` (reversed-Z depth `d`) seen through the fog.
fn fogged(camera: Camera, fog: Fog, lit: vec4<f32>, pixel: vec2<u32>, d: f32) -> vec4<f32> {
    if (d <= 0.0) {
        return lit;
    }
    let h = camera.projection_inverse * vec4<f32>(pixel_to_ndc(pixel, camera.size), d, 1.0);
    let p_view = h.xyz / h.w;
    let p = (camera.view_inverse * vec4<f32>(p_view, 1.0)).xyz;
    let eye = camera.position.xyz;
    let to_p = p - eye;
    let length_to_p = length(to_p);
    let start = max(fog.shape.z, 0.0);
    if (length_to_p <= start || length_to_p <= 1e-6) {
        return lit;
    }
    let dir = to_p / length_to_p;
    let origin = eye + dir * start;
    let transmittance = exp(-optical_depth(fog, origin, dir, length_to_p - start));
    let color = lit.rgb * transmittance + fog.color_density.rgb * (1.0 - transmittance);
    return vec4<f32>(min(color, vec3<f32>(65000.0)), lit.a);
}
