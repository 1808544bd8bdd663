// DeferredBase, raster half: writes depth (reversed-Z) and a visibility
// buffer of (instance + 1, triangle) per pixel, 12 bytes a pixel instead of
// MRE's 28: on the H100 raster output costs per byte, compute does not.
// Vertices are pulled from storage by index, so a triangle's id is
// vertex_index / 3 and no primitive_index feature is needed.
// ALPHA_MASK: the layer's material world has glTF materials in MASK mode;
// their pixels whose alpha (instance colour x base colour map) is below the
// cutoff are discarded (group 1: the world, group 3: its map arrays); the
// alpha is instance colour x base colour map (on its UV set) x COLOR_0.
#import spreadlight::camera::Camera
#import spreadlight::mesh_fetch::{instances, triangle_vertex, view_right, view_up}
#ifdef ALPHA_MASK
#import spreadlight::material_maps::{MapCoords, sample_map, map_settings, MAP_BASE_COLOR}
#import spreadlight::mesh::vertex_color
#import spreadlight::vertex_extras::corner_extra
#endif

@group(0) @binding(0) var<uniform> camera: Camera;

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) @interpolate(flat) ids: vec2<u32>,
#ifdef ALPHA_MASK
    @location(1) uv: vec2<f32>,
    // Material id, and the instance colour's alpha as bits.
    @location(2) @interpolate(flat) material: vec2<u32>,
    @location(3) second_uv: vec2<f32>,
    // COLOR_0's alpha.
    @location(4) alpha: f32,
#endif
}

@vertex
fn vs(@builtin(vertex_index) vertex: u32, @builtin(instance_index) instance_index: u32) -> VertexOut {
    // Field by field: loading the whole 224-byte instance per vertex would waste bandwidth.
    let info = instances[instance_index].info;
    // A mirroring transform (negative determinant) turns the winding
    // around: take the triangle's corners in the other order so back-face
    // culling still culls back faces.
    let m = instances[instance_index].model;
    let mirrored = determinant(mat3x3<f32>(m[0].xyz, m[1].xyz, m[2].xyz)) < 0.0;
    let corner = vertex % 3u;
    let corner_used = select(corner, (3u - corner) % 3u, mirrored);
    let v = triangle_vertex(instance_index, vertex / 3u, corner_used, view_right(camera.view), view_up(camera.view));
    let position = v.position_u.xyz;
    var out: VertexOut;
    out.clip = camera.view_projection * instances[instance_index].model * vec4<f32>(position, 1.0);
    out.ids = vec2<u32>(instance_index + 1u, vertex / 3u);
#ifdef ALPHA_MASK
    out.uv = vec2<f32>(v.position_u.w, v.normal_v.w);
    out.material = vec2<u32>(info.z, bitcast<u32>(instances[instance_index].color.a));
    let extra = corner_extra(instance_index, vertex / 3u, corner_used, v);
    out.second_uv = extra.second_uv;
    out.alpha = vertex_color(extra).a;
#endif
    return out;
}

@fragment
fn fs(in: VertexOut) -> @location(0) vec2<u32> {
#ifdef ALPHA_MASK
    // Derivatives first, in uniform control flow.
    var coords: MapCoords;
    coords.uv = in.uv;
    coords.dx = dpdx(in.uv);
    coords.dy = dpdy(in.uv);
    coords.second_uv = in.second_uv;
    coords.second_dx = dpdx(in.second_uv);
    coords.second_dy = dpdy(in.second_uv);
    let settings = map_settings(in.material.x);
    if ((u32(settings.x) & 3u) == 1u) {
        let alpha = bitcast<f32>(in.material.y) * in.alpha * sample_map(in.material.x, MAP_BASE_COLOR, coords, vec4<f32>(1.0)).a;
        if (alpha < settings.y) {
            discard;
        }
    }
#endif
    return in.ids;
}
