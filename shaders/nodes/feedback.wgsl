// Feedback: a persistent target keeps last frame's image; each frame blends
// the input over it, so moving things leave trails. Cleared on a cut.
// @category Filter
// @help Video feedback: each frame keeps Decay of the last frame's result (a persistent target) and adds the input over it. A cut (reset) clears it.
// @input source "Texture"
// @target trail persistent rgba16float scale=1 clear=0,0,0,0
// @pass blend -> trail

struct Params {
    decay: f32, // @pin default=0.9 min=0 max=1
    size: vec2<f32>,
    fresh: u32,
}

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var source: texture_2d<f32>;
// Last frame's trail (a copy the frame graph makes), and this frame's.
@group(0) @binding(2) var trail: texture_2d<f32>;
@group(0) @binding(3) var trail_out: texture_storage_2d<rgba16float, write>;

@compute @workgroup_size(8, 8)
fn blend(@builtin(global_invocation_id) id: vec3<u32>) {
    if (f32(id.x) >= params.size.x || f32(id.y) >= params.size.y) {
        return;
    }
    let src = vec2<f32>(textureDimensions(source));
    let c = textureLoad(source, vec2<u32>((vec2<f32>(id.xy) + 0.5) / params.size * src), 0);
    let last = textureLoad(trail, id.xy, 0);
    // Keep whichever is brighter of the input and the fading trail.
    textureStore(trail_out, id.xy, max(c, last * params.decay));
}
