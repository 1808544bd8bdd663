// The camera as passes see it: Emeshe's CAM_* semantics. Reversed-Z:
// depth 1 at the near plane, 0 at infinity/far.
#define_import_path spreadlight::camera

struct Camera {
    view: mat4x4<f32>,
    view_inverse: mat4x4<f32>,
    projection: mat4x4<f32>,
    projection_inverse: mat4x4<f32>,
    view_projection: mat4x4<f32>,
    previous_view_projection: mat4x4<f32>,
    // xyz: world position of the eye.
    position: vec4<f32>,
    // (width, height, 1/width, 1/height) of the target in pixels.
    size: vec4<f32>,
}

// The NDC position of a pixel's centre.
fn pixel_to_ndc(pixel: vec2<u32>, size: vec4<f32>) -> vec2<f32> {
    let uv = (vec2<f32>(pixel) + 0.5) * size.zw;
    return vec2<f32>(uv.x * 2.0 - 1.0, 1.0 - uv.y * 2.0);
}
