// CompositeLight: the lit image from CookTorrance's components. Diffuse
// already carries albedo; ambient (until image-based light lands) is a
// constant term times albedo. Clamped below half-float overflow.
#import spreadlight::camera::Camera

struct Params {
    // rgb ambient radiance, w unused
    ambient: vec4<f32>,
}

@group(0) @binding(0) var<uniform> camera: Camera;
@group(0) @binding(1) var<uniform> params: Params;
@group(0) @binding(2) var color: texture_2d<f32>;
@group(0) @binding(3) var diffuse: texture_2d<f32>;
@group(0) @binding(4) var specular: texture_2d<f32>;
@group(0) @binding(5) var depth: texture_2d<f32>;
@group(0) @binding(6) var output: texture_storage_2d<rgba16float, write>;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = vec2<u32>(camera.size.xy);
    if (id.x >= size.x || id.y >= size.y) {
        return;
    }
    let p = id.xy;
    var lit = vec3<f32>(0.0);
    if (textureLoad(depth, p, 0).r > 0.0) {
        let albedo = textureLoad(color, p, 0).rgb;
        lit = textureLoad(diffuse, p, 0).rgb + textureLoad(specular, p, 0).rgb + params.ambient.rgb * albedo;
    }
    textureStore(output, p, vec4<f32>(min(lit, vec3<f32>(65000.0)), 1.0));
}
