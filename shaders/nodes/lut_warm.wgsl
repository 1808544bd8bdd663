// A procedural 16x16x16 colour lookup table laid out as a 256x16 strip
// (blue picks the 16x16 tile): the identity, warmed and with lifted shadows.
// Feed it to ColorGrade (Shader)'s LUT pin, or replace it with a LUT image.
// @category Source
// @help A 16x16x16 colour LUT as a 256x16 strip (blue selects the tile): identity bent warm by Warmth, shadows lifted by Lift.
// @target lut permanent rgba16float size=256x16
// @pass build -> lut

struct Params {
    warmth: f32, // @pin default=0.3 min=-1 max=1
    lift: f32, // @pin default=0.05 min=0 max=0.5
}

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var lut: texture_storage_2d<rgba16float, write>;

@compute @workgroup_size(16, 16)
fn build(@builtin(global_invocation_id) id: vec3<u32>) {
    if (id.x >= 256u || id.y >= 16u) {
        return;
    }
    let rgb = vec3<f32>(f32(id.x % 16u), f32(id.y), f32(id.x / 16u)) / 15.0;
    var c = rgb * (1.0 - params.lift) + params.lift;
    c = c * vec3<f32>(1.0 + 0.1 * params.warmth, 1.0, 1.0 - 0.1 * params.warmth);
    textureStore(lut, id.xy, vec4<f32>(clamp(c, vec3<f32>(0.0), vec3<f32>(1.0)), 1.0));
}
