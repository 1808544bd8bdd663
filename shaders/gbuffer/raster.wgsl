// DeferredBase's compute rasterizer: the visibility buffer without the
// raster hardware. On the H100 only a few units run vertex and pixel work
// while compute runs on all of them (DEVELOPERS.md, shared/GPU-HOST.md), so
// triangles are rasterized here, one thread per triangle, into a 64-bit
// buffer with atomicMax: depth (reversed-Z, so nearer is larger) in the high
// 32 bits, the triangle's global id + 1 in the low 32. Triangles that cover
// many pixels, or cross the near plane, are split into 32x32-pixel tiles and
// rasterized by a second kernel, a workgroup per tile. A giant triangle
// (more than GIANT_TILES tiles: a floor) is queued once, at the top of the
// tile list, and every workgroup of the second kernel takes its share of
// its tiles: its thread writing thousands of tile entries alone, one after
// another, took 0.3 ms on the H100 for a floor's two triangles.
//
// DEPTH_ONLY (shadow maps): 32-bit words of depth alone, atomicMax on the
// reversed-Z depth's bits (the same as atomicMin on conventional depth:
// non-negative floats order as their bits do). Half the bytes of the 64-bit
// words, and any adapter has 32-bit atomics (no SHADER_INT64 needed).
//
// LAYERED (shadow maps, SPREADLIGHT_SHADOW_LAYERS=together): every layer of
// a map (cascades, spots, a point light's faces, a scrolled cascade's
// strips) in one chain: the layer is the triangle kernel's workgroup_id.z,
// each layer's camera and first word come from `cameras` and `layer_words`,
// and all layers' big triangles share one tile list (an entry names its
// layer). Each layer's words get the same atomics as a raster of that layer
// alone, so the depth is the same bit for bit.
#import spreadlight::camera::Camera
#import spreadlight::mesh_fetch::{instances, mesh_position, triangle_vertex, view_right, view_up}

// One draw: a mesh's triangles for a run of instances.
struct Batch {
    first_instance: u32,
    triangles: u32,
    instance_count: u32,
    first_global: u32,
    // The mesh's bounding sphere (centre, radius) before an instance's
    // transform; radius < 0: none (particles).
    sphere: vec4<f32>,
}

// Draws rasterized in one dispatch (compute_raster.rs: those that share a
// pipeline), a thread per triangle, one draw's threads after another's: a
// dispatch a draw made a thousand small glTF meshes a thousand dispatches,
// each waiting for the one before it.
const RUN_BATCHES: u32 = 256u;
struct Run {
    batches: array<Batch, RUN_BATCHES>,
    // The run's first thread for each batch, ascending, four to a vector (a
    // uniform array's elements are 16 bytes apart).
    first_threads: array<vec4<u32>, 64>,
    // x: batches in the run.
    count: vec4<u32>,
}

// A tile of a big triangle: instance, triangle, global id, tile x | tile y << 16
// (LAYERED: tile x | tile y << 8 | layer << 16; a shadow map's side, at
// most 8192 texels, is at most 256 tiles).
struct TileEntry {
    instance: u32,
    triangle: u32,
    global_id: u32,
    tile: u32,
}

#ifdef LAYERED
@group(0) @binding(8) var<storage, read> cameras: array<Camera>;
// Where each layer's words start in `visibility`.
@group(0) @binding(9) var<storage, read> layer_words: array<u32>;
// What the rasterizer reads of a camera: a layer's copy is these 36 floats
// (the whole `Camera` is 104), under the name the single view's uniform has.
struct LayerCamera {
    view: mat4x4<f32>,
    view_projection: mat4x4<f32>,
    size: vec4<f32>,
}

// The layer a thread rasterizes for: its camera, its first word, its index.
var<private> camera: LayerCamera;
var<private> first_word: u32;
var<private> layer: u32;

fn enter_layer(index: u32) {
    layer = index;
    camera = LayerCamera(cameras[index].view, cameras[index].view_projection, cameras[index].size);
    first_word = layer_words[index];
}
#else
@group(0) @binding(0) var<uniform> camera: Camera;
#endif
#ifdef DEPTH_ONLY
@group(0) @binding(4) var<storage, read_write> visibility: array<atomic<u32>>;
#else
@group(0) @binding(4) var<storage, read_write> visibility: array<atomic<u64>>;
#endif
@group(0) @binding(5) var<storage, read_write> tiles: array<TileEntry>;
// x: tile entries written, y: the list's capacity, z: giant triangles queued, w unused.
@group(0) @binding(6) var<storage, read_write> tile_count: array<atomic<u32>, 4>;
@group(0) @binding(7) var<uniform> run: Run;

const TILE: u32 = 32u;
const SMALL_AREA: f32 = 256.0;
// Tiles above which a triangle is queued whole; GIANTS of them at most (the
// list's last GIANTS entries), beyond that tile by tile as before.
const GIANT_TILES: u32 = 64u;
const GIANTS: u32 = 64u;

// A triangle made ready to rasterize: up to two screen-space triangles (a
// near-clipped triangle is a quad), each vertex (x, y in pixels, depth).
struct Setup {
    count: u32,
    a: array<vec3<f32>, 4>,
    lo: vec2<f32>,
    hi: vec2<f32>,
}

fn clip_position(instance: u32, triangle: u32, corner: u32) -> vec4<f32> {
#ifdef MESHES_ONLY
    let position = mesh_position(instance, triangle, corner);
    return camera.view_projection * instances[instance].model * vec4<f32>(position, 1.0);
#else
    let v = triangle_vertex(instance, triangle, corner, view_right(camera.view), view_up(camera.view));
    return camera.view_projection * instances[instance].model * vec4<f32>(v.position_u.xyz, 1.0);
#endif
}

fn to_screen(c: vec4<f32>) -> vec3<f32> {
    let ndc = c.xyz / c.w;
    return vec3<f32>((ndc.x * 0.5 + 0.5) * camera.size.x, (0.5 - ndc.y * 0.5) * camera.size.y, ndc.z);
}

fn cross2(a: vec2<f32>, b: vec2<f32>) -> f32 {
    return a.x * b.y - a.y * b.x;
}

// Clip against the near plane, cull back faces, project. count 0: nothing to draw.
// In reversed-Z clip space the near plane is z = w; in front of it, w - z >= 0.
fn near_distance(c: vec4<f32>) -> f32 {
    return c.w - c.z;
}

fn setup(instance: u32, triangle: u32) -> Setup {
    var s: Setup;
    s.count = 0u;
    var c = array<vec4<f32>, 3>(clip_position(instance, triangle, 0u), clip_position(instance, triangle, 1u), clip_position(instance, triangle, 2u));
    // Sutherland-Hodgman against the near plane: at most 4 vertices out.
    var poly: array<vec4<f32>, 4>;
    var n = 0u;
    for (var i = 0u; i < 3u; i++) {
        let p = c[i];
        let q = c[(i + 1u) % 3u];
        let p_in = near_distance(p) >= 0.0;
        let q_in = near_distance(q) >= 0.0;
        if (p_in) {
            poly[n] = p;
            n++;
        }
        if (p_in != q_in) {
            let t = near_distance(p) / (near_distance(p) - near_distance(q));
            poly[n] = mix(p, q, t);
            n++;
        }
    }
    if (n < 3u) {
        return s;
    }
    // Back faces: counter-clockwise is front in NDC (y up).
    let n0 = poly[0].xy / poly[0].w;
    let n1 = poly[1].xy / poly[1].w;
    let n2 = poly[2].xy / poly[2].w;
    let winding = cross2(n1 - n0, n2 - n0);
#ifdef TWO_SIDED
    // Shadow maps: both faces cast (an open mesh, a plane seen from behind).
    // A back face is turned around, so the rasterizer sees it front-facing.
    if (winding == 0.0) {
        return s;
    }
    if (winding < 0.0) {
        var flipped: array<vec4<f32>, 4>;
        for (var i = 0u; i < n; i++) {
            flipped[i] = poly[n - 1u - i];
        }
        poly = flipped;
    }
#else
    // A mirroring transform (negative determinant) turns the winding around.
    let m = instances[instance].model;
    let mirrored = determinant(mat3x3<f32>(m[0].xyz, m[1].xyz, m[2].xyz)) < 0.0;
    if (select(winding, -winding, mirrored) <= 0.0) {
        return s;
    }
#endif
    s.lo = vec2<f32>(1e30);
    s.hi = vec2<f32>(-1e30);
    for (var i = 0u; i < n; i++) {
        let v = to_screen(poly[i]);
        // A corner that is NaN or infinite (a broken mesh or transform)
        // draws nothing: it would otherwise loop over made-up bounds and
        // write made-up depths.
        if (!all(abs(v) < vec3<f32>(1e30))) {
            s.count = 0u;
            return s;
        }
        s.a[i] = v;
        s.lo = min(s.lo, v.xy);
        s.hi = max(s.hi, v.xy);
    }
    s.count = n - 2u;
    return s;
}

#ifndef DEPTH_ONLY
fn pack(depth: f32, id: u32) -> u64 {
    return (u64(bitcast<u32>(depth)) << 32u) | u64(id + 1u);
}
#endif

// Cover one pixel with triangle (a, b, c) in screen space (clockwise there, as y points down).
fn shade(x: u32, y: u32, a: vec3<f32>, b: vec3<f32>, c: vec3<f32>, id: u32) {
    let p = vec2<f32>(f32(x) + 0.5, f32(y) + 0.5);
    let area = cross2(b.xy - a.xy, c.xy - a.xy);
    if (area == 0.0) {
        return;
    }
    // Inclusive edges: a pixel on a shared edge may be covered twice, never missed;
    // atomicMax makes the double cover harmless.
    let w0 = cross2(c.xy - b.xy, p - b.xy) / area;
    let w1 = cross2(a.xy - c.xy, p - c.xy) / area;
    let w2 = cross2(b.xy - a.xy, p - a.xy) / area;
    if (w0 < 0.0 || w1 < 0.0 || w2 < 0.0) {
        return;
    }
    let depth = w0 * a.z + w1 * b.z + w2 * c.z;
    // Written so that NaN fails it too.
    if (!(depth >= 0.0 && depth <= 1.0)) {
        return;
    }
    let width = u32(camera.size.x);
#ifdef LAYERED
    let word = first_word + y * width + x;
#else
    let word = y * width + x;
#endif
#ifdef DEPTH_ONLY
    // Without the sign bit: -0.0 is the far plane, not the nearest depth.
    atomicMax(&visibility[word], bitcast<u32>(depth) & 0x7fffffffu);
#else
    atomicMax(&visibility[word], pack(depth, id));
#endif
}

fn shade_rect(s: Setup, id: u32, lo: vec2<u32>, hi: vec2<u32>, lane: u32, lanes: u32) {
    let w = hi.x - lo.x;
    let total = w * (hi.y - lo.y);
    for (var k = lane; k < total; k += lanes) {
        let x = lo.x + k % w;
        let y = lo.y + k / w;
        shade(x, y, s.a[0], s.a[1], s.a[2], id);
        if (s.count == 2u) {
            shade(x, y, s.a[0], s.a[2], s.a[3], id);
        }
    }
}

// The pixel rectangle of a setup's bounds, clamped to the target.
fn pixel_bounds(s: Setup) -> array<vec2<u32>, 2> {
    let size = camera.size.xy;
    let lo = clamp(floor(s.lo), vec2<f32>(0.0), size);
    let hi = clamp(ceil(s.hi) + 1.0, vec2<f32>(0.0), size);
    return array<vec2<u32>, 2>(vec2<u32>(lo), vec2<u32>(hi));
}

// Whether an instance of a mesh bounded by `sphere` may cover a pixel of the
// view: false only where the sphere, moved by the instance's transform, lies
// wholly outside one of the view's four side planes. Such an instance's
// triangles cover no pixel (their parts in front of the eye lie outside that
// plane, and what lies behind it is clipped), so leaving it before its
// triangles are fetched changes no word; a thin strip of a scrolled shadow
// cascade, or a camera that sees part of a crowd, rejects most instances
// here, a warp of one instance at a time. Kept: particles (no sphere), a
// transform that is not affine, and anything not finite (the triangle's own
// setup decides).
fn may_cover(sphere: vec4<f32>, instance: u32) -> bool {
    if (!(sphere.w >= 0.0)) {
        return true;
    }
    let model = instances[instance].model;
    if (any(vec4<f32>(model[0].w, model[1].w, model[2].w, model[3].w) != vec4<f32>(0.0, 0.0, 0.0, 1.0))) {
        return true;
    }
    let stretch = max(max(dot(model[0].xyz, model[0].xyz), dot(model[1].xyz, model[1].xyz)), dot(model[2].xyz, model[2].xyz));
    // A thousandth wider, against rounding in the planes.
    let radius = sphere.w * sqrt(stretch) * 1.001 + 1e-6;
    let m = camera.view_projection;
    let clip = m * (model * vec4<f32>(sphere.xyz, 1.0));
    // The side planes w + x, w - x, w + y, w - y: their values at the centre,
    // and their normals' lengths, which scale a world distance to them.
    let x = vec3<f32>(m[0].x, m[1].x, m[2].x);
    let y = vec3<f32>(m[0].y, m[1].y, m[2].y);
    let w = vec3<f32>(m[0].w, m[1].w, m[2].w);
    let value = vec4<f32>(clip.w + clip.x, clip.w - clip.x, clip.w + clip.y, clip.w - clip.y);
    let reach = radius * vec4<f32>(length(w + x), length(w - x), length(w + y), length(w - y));
    return !any(value < -reach);
}

fn first_thread(batch: u32) -> u32 {
    return run.first_threads[batch / 4u][batch % 4u];
}

// The run's batch holding `thread`: the last whose first thread is not past
// it (the first's is 0). A workgroup's 64 threads lie in one batch or a few,
// so its lanes read the same entries.
fn batch_of(thread: u32) -> u32 {
    var lo = 0u;
    var hi = run.count.x;
    while (hi - lo > 1u) {
        let mid = (lo + hi) / 2u;
        if (first_thread(mid) <= thread) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    return lo;
}

@compute @workgroup_size(64)
fn raster_triangles(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
#ifdef LAYERED
    enter_layer(gid.z);
#endif
    let thread = gid.x + gid.y * groups.x * 64u;
    let index = batch_of(thread);
    let batch = run.batches[index];
    let local = thread - first_thread(index);
    if (local >= batch.triangles * batch.instance_count) {
        return;
    }
    let instance = batch.first_instance + local / batch.triangles;
    if (!may_cover(batch.sphere, instance)) {
        return;
    }
    let triangle = local % batch.triangles;
    let id = batch.first_global + local;
    let s = setup(instance, triangle);
    if (s.count == 0u) {
        return;
    }
    let bounds = pixel_bounds(s);
    let lo = bounds[0];
    let hi = bounds[1];
    if (lo.x >= hi.x || lo.y >= hi.y) {
        return;
    }
    let area = f32(hi.x - lo.x) * f32(hi.y - lo.y);
    if (area <= SMALL_AREA) {
        shade_rect(s, id, lo, hi, 0u, 1u);
        return;
    }
    // Big: hand its tiles to raster_tiles.
    let span = tile_span(bounds);
    let count = span[1].x * span[1].y;
    let capacity = atomicLoad(&tile_count[1]);
    if (count > GIANT_TILES) {
        let giant = atomicAdd(&tile_count[2], 1u);
        if (giant < GIANTS && giant < capacity) {
            tiles[capacity - 1u - giant] = TileEntry(instance, triangle, id, tile_word(vec2<u32>(0u)));
            return;
        }
    }
    let entries = capacity - min(GIANTS, capacity);
    let first = atomicAdd(&tile_count[0], count);
    for (var k = 0u; k < count && first + k < entries; k++) {
        let t = tile_at(span, k);
        tiles[first + k] = TileEntry(instance, triangle, id, tile_word(t));
    }
}

// The tiles a pixel rectangle (`pixel_bounds`) touches: the first, and how
// many across and down.
fn tile_span(bounds: array<vec2<u32>, 2>) -> array<vec2<u32>, 2> {
    let first = bounds[0] / TILE;
    return array<vec2<u32>, 2>(first, (bounds[1] + TILE - 1u) / TILE - first);
}

// A tile entry's `tile` word (and, LAYERED, its layer).
fn tile_word(t: vec2<u32>) -> u32 {
#ifdef LAYERED
    return t.x | (t.y << 8u) | (layer << 16u);
#else
    return t.x | (t.y << 16u);
#endif
}

// The tile a `tile_word` names (LAYERED: entering its layer too).
fn entry_tile(word: u32) -> vec2<u32> {
#ifdef LAYERED
    enter_layer(word >> 16u);
    return vec2<u32>(word & 0xffu, (word >> 8u) & 0xffu);
#else
    return vec2<u32>(word & 0xffffu, word >> 16u);
#endif
}

// Tile `k` of a span, row by row.
fn tile_at(span: array<vec2<u32>, 2>, k: u32) -> vec2<u32> {
    return span[0] + vec2<u32>(k % span[1].x, k / span[1].x);
}

// The part of a setup's `bounds` in tile `tile` (in tiles), shared by the
// workgroup's lanes.
fn shade_tile(s: Setup, id: u32, bounds: array<vec2<u32>, 2>, tile: vec2<u32>, lane: u32) {
    let corner = tile * TILE;
    let lo = max(bounds[0], corner);
    let hi = min(bounds[1], corner + TILE);
    if (lo.x < hi.x && lo.y < hi.y) {
        shade_rect(s, id, lo, hi, lane, 64u);
    }
}

// One workgroup per tile entry (striding when there are more than
// workgroups), then every workgroup its share of each giant's tiles.
@compute @workgroup_size(64)
fn raster_tiles(@builtin(workgroup_id) wid: vec3<u32>, @builtin(local_invocation_index) lane: u32, @builtin(num_workgroups) groups: vec3<u32>) {
    let capacity = atomicLoad(&tile_count[1]);
    let giants = min(min(atomicLoad(&tile_count[2]), GIANTS), capacity);
    for (var g = 0u; g < giants; g++) {
        let entry = tiles[capacity - 1u - g];
        // The giant's layer (LAYERED); its tile word holds no tile.
        _ = entry_tile(entry.tile);
        let s = setup(entry.instance, entry.triangle);
        if (s.count == 0u) {
            continue;
        }
        let bounds = pixel_bounds(s);
        let span = tile_span(bounds);
        for (var t = wid.x; t < span[1].x * span[1].y; t += groups.x) {
            shade_tile(s, entry.global_id, bounds, tile_at(span, t), lane);
        }
    }
    let count = min(atomicLoad(&tile_count[0]), capacity - min(GIANTS, capacity));
    for (var e = wid.x; e < count; e += groups.x) {
        let entry = tiles[e];
        let tile = entry_tile(entry.tile);
        let s = setup(entry.instance, entry.triangle);
        if (s.count == 0u) {
            continue;
        }
        shade_tile(s, entry.global_id, pixel_bounds(s), tile, lane);
    }
}
