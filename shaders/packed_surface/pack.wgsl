// The packed surface of a G-buffer (crates/render/src/packed_surface): per
// pixel the view distance (f32 bits) and the octahedron-encoded unit normal
// in one RG32Uint texel (shaders/lib/screen.wgsl's NO_SURFACE / NO_NORMAL
// where there is none), written once a frame and read by every
// depth-aware blur of SSAO, SAO, HBAO and SSGI; and in an R32Float target
// the view z itself (EMPTY_Z where depth is empty), which SSAO's and
// SSGI's rays read (screen.wgsl's march_packed).
#import spreadlight::camera::Camera
#import spreadlight::screen::{view_position, pack_surface_normal, NO_SURFACE, NO_NORMAL, EMPTY_Z}

@group(0) @binding(0) var<uniform> camera: Camera;
@group(0) @binding(1) var depth: texture_2d<f32>;
@group(0) @binding(2) var normals: texture_2d<f32>;
@group(0) @binding(3) var output: texture_storage_2d<rg32uint, write>;
@group(0) @binding(4) var view_z: texture_storage_2d<r32float, write>;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = vec2<u32>(camera.size.xy);
    if (id.x >= size.x || id.y >= size.y) {
        return;
    }
    let d = textureLoad(depth, id.xy, 0).r;
    var texel = vec2<u32>(NO_SURFACE, NO_NORMAL);
    var z = EMPTY_Z;
    if (d > 0.0) {
        // The expression the blurs and rays computed per tap, so the same bits.
        z = view_position(camera, id.xy, d).z;
        texel = vec2<u32>(bitcast<u32>(-z), pack_surface_normal(textureLoad(normals, id.xy, 0).xyz));
    }
    textureStore(output, id.xy, vec4<u32>(texel, 0u, 0u));
    textureStore(view_z, id.xy, vec4<f32>(z, 0.0, 0.0, 0.0));
}
