// Shifting a scrolled cascade's layer into place (crates/render/src/shadows/
// scroll.rs): `to_scratch` writes each texel the move keeps where the new
// view sees it, into a scratch layer; `back` writes those texels into the
// layer. Two dispatches, because a layer cannot be read and written in
// place where its source and destination overlap. The texels the move
// uncovers are left as they were: the strips drawn next overwrite them.
// Compute, not texture copies: the copies ran at about 200 GB/s on the H200,
// so shifting a 1,024 VSM sun's map, still cache and moments cost more than
// drawing them again (docs/benchmarks.md, session 26). MOMENTS: VSM's
// two-channel moments instead of one-channel depth.

struct Shift {
    // Texels right and down.
    offset: vec2<i32>,
    // The layer's size.
    size: vec2<u32>,
}

@group(0) @binding(0) var<uniform> shift: Shift;
@group(0) @binding(1) var source: texture_2d<f32>;
#ifdef MOMENTS
@group(0) @binding(2) var destination: texture_storage_2d<rg32float, write>;
#else
@group(0) @binding(2) var destination: texture_storage_2d<r32float, write>;
#endif

// Where the texel now at `at` was before the move, if it was in the layer.
fn kept_from(at: vec2<u32>) -> vec3<i32> {
    let before = vec2<i32>(at) - shift.offset;
    let inside = all(at < shift.size) && all(before >= vec2<i32>(0)) && all(before < vec2<i32>(shift.size));
    return vec3<i32>(before, i32(inside));
}

@compute @workgroup_size(8, 8)
fn to_scratch(@builtin(global_invocation_id) id: vec3<u32>) {
    let kept = kept_from(id.xy);
    if (kept.z == 0) {
        return;
    }
    textureStore(destination, id.xy, textureLoad(source, kept.xy, 0));
}

@compute @workgroup_size(8, 8)
fn back(@builtin(global_invocation_id) id: vec3<u32>) {
    if (kept_from(id.xy).z == 0) {
        return;
    }
    textureStore(destination, id.xy, textureLoad(source, vec2<i32>(id.xy), 0));
}
