// PassChain (crates/render/src/bench/pass_chain.rs): passes that do almost
// nothing, so a chain of hundreds shows what the frame graph costs per pass
// on the CPU. `start` writes a ramp; each `step` turns the colour a little
// (its step number in the uniform), so the last image depends on every pass
// having run, in order, on the one before it.

struct Step {
    // x: this pass's step (1-based), y: the chain's steps
    index: vec4<u32>,
}

@group(0) @binding(0) var<uniform> step: Step;
@group(0) @binding(1) var source: texture_2d<f32>;
@group(0) @binding(2) var output: texture_storage_2d<rgba16float, write>;

@compute @workgroup_size(8, 8)
fn start(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(output);
    if (id.x >= size.x || id.y >= size.y) {
        return;
    }
    let uv = (vec2<f32>(id.xy) + 0.5) / vec2<f32>(size);
    textureStore(output, id.xy, vec4<f32>(uv, 0.0, 1.0));
}

@compute @workgroup_size(8, 8)
fn next(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(output);
    if (id.x >= size.x || id.y >= size.y) {
        return;
    }
    let c = textureLoad(source, id.xy, 0);
    // The channels rotate each step and blue takes a little of the step's
    // share: the order of the passes shows in the result, not only their
    // count, and the ramp survives 200 steps (at about a quarter).
    let share = f32(step.index.x) / f32(max(step.index.y, 1u));
    textureStore(output, id.xy, vec4<f32>(c.g, c.b * 0.98 + share * 0.02, c.r, 1.0));
}
