// Chromatic aberration as in Dagon's post-processing: red and blue sampled
// at radially scaled coordinates around a centre, green in place.
// @category Filter
// @help Lens-like chromatic aberration: red and blue drift apart towards the edges by Strength (in UV units at the corners) around Center.
// @input source "Texture"
// @sampler smp clamp
// @target aberrated temporary rgba16float scale=1
// @pass aberrate -> aberrated

struct Params {
    strength: f32, // @pin default=0.01 min=0 max=0.2
    center: vec2<f32>, // @pin default=0.5,0.5
    texel: vec2<f32>,
    size: vec2<f32>,
}

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var source: texture_2d<f32>;
@group(0) @binding(2) var smp: sampler;
@group(0) @binding(3) var aberrated: texture_storage_2d<rgba16float, write>;

@compute @workgroup_size(8, 8)
fn aberrate(@builtin(global_invocation_id) id: vec3<u32>) {
    if (f32(id.x) >= params.size.x || f32(id.y) >= params.size.y) {
        return;
    }
    let uv = (vec2<f32>(id.xy) + 0.5) * params.texel;
    let d = uv - params.center;
    let r = textureSampleLevel(source, smp, uv + d * params.strength * 2.0, 0.0).r;
    let g = textureSampleLevel(source, smp, uv, 0.0);
    let b = textureSampleLevel(source, smp, uv - d * params.strength * 2.0, 0.0).b;
    textureStore(aberrated, id.xy, vec4<f32>(r, g.g, b, g.a));
}
