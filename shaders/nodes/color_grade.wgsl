// Colour grading through a 3D lookup table given as a 2D strip texture
// (N*N x N: blue selects the tile), as most grading tools export it.
// @category Filter
// @help Grades the image through a colour LUT strip (N*N x N, blue selects the tile) with trilinear lookup; Intensity mixes graded and original.
// @input source "Texture"
// @input lut "LUT"
// @sampler smp clamp
// @target graded temporary rgba16float scale=1
// @pass grade -> graded

struct Params {
    intensity: f32, // @pin default=1 min=0 max=1
    size: vec2<f32>,
}

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var source: texture_2d<f32>;
@group(0) @binding(2) var lut: texture_2d<f32>;
@group(0) @binding(3) var smp: sampler;
@group(0) @binding(4) var graded: texture_storage_2d<rgba16float, write>;

fn lookup(c: vec3<f32>) -> vec3<f32> {
    let dims = vec2<f32>(textureDimensions(lut));
    let n = dims.y;
    let b = clamp(c.b, 0.0, 1.0) * (n - 1.0);
    let b0 = floor(b);
    let b1 = min(b0 + 1.0, n - 1.0);
    // Sample the centres of texels inside a tile so red and green interpolate.
    let rg = (clamp(c.rg, vec2<f32>(0.0), vec2<f32>(1.0)) * (n - 1.0) + 0.5);
    let uv0 = vec2<f32>(b0 * n + rg.x, rg.y) / dims;
    let uv1 = vec2<f32>(b1 * n + rg.x, rg.y) / dims;
    let c0 = textureSampleLevel(lut, smp, uv0, 0.0).rgb;
    let c1 = textureSampleLevel(lut, smp, uv1, 0.0).rgb;
    return mix(c0, c1, b - b0);
}

@compute @workgroup_size(8, 8)
fn grade(@builtin(global_invocation_id) id: vec3<u32>) {
    if (f32(id.x) >= params.size.x || f32(id.y) >= params.size.y) {
        return;
    }
    let src = vec2<f32>(textureDimensions(source));
    let p = vec2<u32>((vec2<f32>(id.xy) + 0.5) / params.size * src);
    let c = textureLoad(source, p, 0);
    let g = lookup(c.rgb);
    textureStore(graded, id.xy, vec4<f32>(mix(c.rgb, g, params.intensity), c.a));
}
