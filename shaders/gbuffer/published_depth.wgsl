// A G-buffer's depth so far (its meshes, before its particles), copied
// into the R32Float target it publishes for next frame's particle
// collisions (crates/render/src/gbuffer/published_depth.rs).
// COMPUTE_RASTER: from the compute rasterizer's 64-bit words (depth bits in
// the high half, 0 where nothing was drawn); else the hardware depth.
#ifdef COMPUTE_RASTER
@group(0) @binding(0) var<storage, read> visibility: array<vec2<u32>>;
#else
@group(0) @binding(0) var depth: texture_depth_2d;
#endif
@group(0) @binding(1) var out_depth: texture_storage_2d<r32float, write>;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(out_depth);
    if (id.x >= size.x || id.y >= size.y) {
        return;
    }
#ifdef COMPUTE_RASTER
    let z = bitcast<f32>(visibility[id.y * size.x + id.x].y);
#else
    let z = textureLoad(depth, id.xy, 0);
#endif
    textureStore(out_depth, id.xy, vec4<f32>(z, 0.0, 0.0, 0.0));
}
