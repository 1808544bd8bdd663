// Shadow-map depth into the map shading samples (R32F, conventional depth:
// 0 at the near plane, 1 at the far plane and where nothing was drawn).
// from_visibility: the compute rasterizer's 32-bit words (DEPTH_ONLY in
// gbuffer/raster.wgsl: reversed-Z depth bits, 0 where nothing was drawn),
// so 1 - depth. from_depth: the raster hardware's Depth32F
// attachments, copied. OVER_STILL: the nearer of that and the still
// casters' cached map (a node caches what did not move, and draws only what
// moved over it each frame). Either fills `Info.region` of the layer: the
// whole layer, or a strip a scrolled cascade uncovered (the compute
// rasterizer drew the strip alone, as a target of the strip's size; the raster
// hardware drew it into the layer's attachment, scissored to it).
// from_visibility_layers: every part of a layered raster (LAYERED in
// gbuffer/raster.wgsl, SPREADLIGHT_SHADOW_LAYERS=together) in one dispatch:
// workgroups run over each part's 8x8 tiles in turn (`Part.first_group`),
// and each texel goes through the same `store_depth` test as from_visibility.
#import spreadlight::camera::Camera

struct Info {
    // x: the array layer to read
    layer: vec4<u32>,
    // The texels written: origin (x, y) and size (z, w)
    region: vec4<u32>,
}

@group(0) @binding(0) var<storage, read> visibility: array<u32>;
@group(0) @binding(1) var depth: texture_depth_2d_array;
@group(0) @binding(2) var<uniform> camera: Camera;
@group(0) @binding(3) var out_depth: texture_storage_2d<r32float, write>;
@group(0) @binding(4) var<uniform> info: Info;
#ifdef OVER_STILL
@group(0) @binding(5) var still: texture_2d<f32>;
#endif

// One part of a layered raster: the layer written, where its words start,
// its first workgroup and its width in workgroups, and its region (origin,
// size: the size is its camera's, so its words are region.z wide).
struct Part {
    layer: u32,
    words: u32,
    first_group: u32,
    groups_across: u32,
    region: vec4<u32>,
}

@group(0) @binding(6) var<storage, read> parts: array<Part>;
@group(0) @binding(7) var out_layers: texture_storage_2d_array<r32float, write>;
#ifdef OVER_STILL
@group(0) @binding(8) var still_layers: texture_2d_array<f32>;
#endif

fn store_depth(at: vec2<u32>, drawn: f32) {
    // NaN or infinity (a broken caster on a rasterizer that lets it through)
    // never reaches the map: written so that NaN fails the test too.
    var d = select(1.0, drawn, drawn >= 0.0 && drawn <= 1.0);
#ifdef OVER_STILL
    d = min(d, textureLoad(still, vec2<i32>(at), 0).x);
#endif
    textureStore(out_depth, at, vec4<f32>(d, 0.0, 0.0, 0.0));
}

// `store_depth` for a layer of the whole array.
fn store_depth_layer(at: vec2<u32>, layer: u32, drawn: f32) {
    var d = select(1.0, drawn, drawn >= 0.0 && drawn <= 1.0);
#ifdef OVER_STILL
    d = min(d, textureLoad(still_layers, vec2<i32>(at), i32(layer), 0).x);
#endif
    textureStore(out_layers, at, layer, vec4<f32>(d, 0.0, 0.0, 0.0));
}

@compute @workgroup_size(8, 8)
fn from_visibility_layers(@builtin(workgroup_id) wid: vec3<u32>, @builtin(local_invocation_id) lid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    // Over 65,535 workgroups spill into y; folded back into one index.
    let group = wid.x + wid.y * groups.x;
    // The part this workgroup is in: the last that starts at or before it
    // (a few parts: a map's layers and strips).
    let count = arrayLength(&parts);
    var p = 0u;
    for (var k = 1u; k < count; k++) {
        if (parts[k].first_group <= group) {
            p = k;
        }
    }
    let part = parts[p];
    let local = group - part.first_group;
    let id = vec2<u32>(local % part.groups_across, local / part.groups_across) * 8u + lid.xy;
    if (id.x >= part.region.z || id.y >= part.region.w) {
        return;
    }
    let word = visibility[part.words + id.y * part.region.z + id.x];
    var d = 1.0;
    if (word != 0u) {
        d = clamp(1.0 - bitcast<f32>(word), 0.0, 1.0);
    }
    store_depth_layer(part.region.xy + id, part.layer, d);
}

@compute @workgroup_size(8, 8)
fn from_visibility(@builtin(global_invocation_id) id: vec3<u32>) {
    // The words cover the region alone (the camera's size is the region's).
    let size = vec2<u32>(camera.size.xy);
    if (id.x >= size.x || id.y >= size.y || id.x >= info.region.z || id.y >= info.region.w) {
        return;
    }
    let word = visibility[id.y * size.x + id.x];
    var d = 1.0;
    if (word != 0u) {
        d = clamp(1.0 - bitcast<f32>(word), 0.0, 1.0);
    }
    store_depth(info.region.xy + id.xy, d);
}

@compute @workgroup_size(8, 8)
fn from_depth(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(depth);
    let at = info.region.xy + id.xy;
    if (id.x >= info.region.z || id.y >= info.region.w || at.x >= size.x || at.y >= size.y) {
        return;
    }
    store_depth(at, textureLoad(depth, vec2<i32>(at), i32(info.layer.x), 0));
}
