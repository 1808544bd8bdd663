// Clustered light assignment (Olsson et al. 2012; Dagon's clustered shading):
// the view frustum is cut into froxels (screen tiles x exponential depth
// slices) and every light is listed in each froxel its sphere may touch.
// Light-centric and exact: count per froxel, prefix-sum into offsets, then
// fill the index list. No per-froxel cap: 100,000 lights in one froxel fit.
//
// OCCUPIED (lit transparency's forward lists, post/transparency.wgsl): only
// the froxels that the transparent fragments marked get lists, so the grid
// can be sliced thin (ClusterGrid::FORWARD_SLICES) without listing lights in
// the empty space between layers; and the first slice runs from the eye,
// the last to infinity, so that no fragment the camera draws lies outside
// its froxel's box (a camera whose far plane is not where the grid thinks).
#import spreadlight::camera::Camera
#import spreadlight::lights::cutoff_range

// Matches `GpuLight` in crates/render/src/lighting/mod.rs.
struct Light {
    // xyz world position, w range (suns: 0)
    position_range: vec4<f32>,
    // rgb colour * luminous intensity (cd) or illuminance (lux)
    intensity: vec4<f32>,
    // xyz unit direction the light travels, w cos(outer cone angle)
    direction: vec4<f32>,
    // x cos(inner cone angle)
    cone: vec4<f32>,
}

struct Grid {
    // tiles x, tiles y, slices, light count
    dims: vec4<u32>,
    // near, far, log(far / near), tile size in pixels
    depth: vec4<f32>,
    // x: the light cutoff (lights.wgsl's cutoff_range; 0: none)
    falloff: vec4<f32>,
}

@group(0) @binding(0) var<uniform> camera: Camera;
@group(0) @binding(1) var<uniform> grid: Grid;
@group(0) @binding(2) var<storage, read> lights: array<Light>;
// View-space position (xyz) and range (w) per light, for shading.
@group(0) @binding(3) var<storage, read_write> view_lights: array<vec4<f32>>;
@group(0) @binding(4) var<storage, read_write> counts: array<atomic<u32>>;
@group(0) @binding(5) var<storage, read_write> offsets: array<u32>;
@group(0) @binding(6) var<storage, read_write> indices: array<u32>;
// x: total entries, y: capacity, z: overflowed entries
@group(0) @binding(7) var<storage, read_write> totals: array<atomic<u32>, 4>;
#ifdef OCCUPIED
// Non-zero where a transparent fragment lies (post/transparency.wgsl's `mark_froxels`).
@group(0) @binding(8) var<storage, read> occupied: array<u32>;
#endif
#ifdef MERGED
// Light Merge (crates/render/src/lighting/light_merge.rs): per light, the
// world centroid of its merged cube (xyz) and the merge distance (w): w > 0
// a member, shaded only at pixels nearer than w to the centroid; w < 0 the
// cube's merged light, shaded only at the others; 0 a light shaded wherever
// it reaches. A froxel lists the side any of its points may be on
// (`in_band`); the shade decides per pixel with the view-space bands this
// writes.
@group(0) @binding(9) var<storage, read> bands: array<vec4<f32>>;
@group(0) @binding(10) var<storage, read_write> view_bands: array<vec4<f32>>;
#endif

fn slice_of(depth: f32) -> i32 {
    return i32(floor(log(max(depth, grid.depth.x) / grid.depth.x) / grid.depth.z * f32(grid.dims.z)));
}

// The froxel range a light may touch: (x0, y0, z0) .. (x1, y1, z1) inclusive; x0 > x1 when none.
fn froxels(light: vec4<f32>) -> array<vec3<i32>, 2> {
    let none = array<vec3<i32>, 2>(vec3<i32>(1), vec3<i32>(0));
    let center = light.xyz;
    let radius = light.w;
    let depth = -center.z;
    if (radius <= 0.0) {
        return none;
    }
#ifdef OCCUPIED
    // The end slices are unbounded: only a light wholly behind the eye is out.
    if (depth + radius < 0.0) {
        return none;
    }
#else
    if (depth + radius < grid.depth.x || depth - radius > grid.depth.y) {
        return none;
    }
#endif
    let dims = vec3<i32>(grid.dims.xyz);
    let z0 = clamp(slice_of(depth - radius), 0, dims.z - 1);
    let z1 = clamp(slice_of(depth + radius), 0, dims.z - 1);
    var lo = vec2<f32>(1.0);
    var hi = vec2<f32>(-1.0);
    if (depth - radius <= grid.depth.x) {
        // The sphere reaches the camera: every tile.
        lo = vec2<f32>(-1.0);
        hi = vec2<f32>(1.0);
    } else {
        for (var k = 0u; k < 8u; k++) {
            let corner = center + radius * vec3<f32>(
                select(-1.0, 1.0, (k & 1u) != 0u),
                select(-1.0, 1.0, (k & 2u) != 0u),
                select(-1.0, 1.0, (k & 4u) != 0u),
            );
            let clip = camera.projection * vec4<f32>(corner, 1.0);
            let ndc = clip.xy / clip.w;
            lo = min(lo, ndc);
            hi = max(hi, ndc);
        }
    }
    if (hi.x < -1.0 || lo.x > 1.0 || hi.y < -1.0 || lo.y > 1.0) {
        return none;
    }
    // NDC to pixels (y down) to tiles; the last tile may hang over the edge.
    let to_tiles = camera.size.xy / grid.depth.w;
    let x0 = clamp(i32(floor((lo.x * 0.5 + 0.5) * to_tiles.x)), 0, dims.x - 1);
    let x1 = clamp(i32(floor((hi.x * 0.5 + 0.5) * to_tiles.x)), 0, dims.x - 1);
    let y0 = clamp(i32(floor((0.5 - hi.y * 0.5) * to_tiles.y)), 0, dims.y - 1);
    let y1 = clamp(i32(floor((0.5 - lo.y * 0.5) * to_tiles.y)), 0, dims.y - 1);
    return array<vec3<i32>, 2>(vec3<i32>(x0, y0, z0), vec3<i32>(x1, y1, z1));
}

fn slice_depth(z: i32) -> f32 {
    return grid.depth.x * exp(grid.depth.z * f32(z) / f32(grid.dims.z));
}

// The slices' near depths (slice_depth), made once per workgroup: the
// froxel tests of count and fill read them instead of two exponentials each.
// ClusterGrid's slice counts (clusters.rs) stay within MAX_SLICES.
const MAX_SLICES: u32 = 128u;
var<workgroup> slice_depths: array<f32, 129>;

// Every lane calls it, before any returns (a barrier).
fn load_slice_depths(lane: u32) {
    let slices = min(grid.dims.z, MAX_SLICES);
    for (var z = lane; z <= slices; z += 64u) {
        var depth = slice_depth(i32(z));
#ifdef OCCUPIED
        // The first slice from the eye, the last to (almost) infinity: a
        // fragment nearer or further than the grid is clamped into them.
        if (z == 0u) {
            depth = 0.0;
        } else if (z == slices) {
            depth = 1e30;
        }
#endif
        slice_depths[z] = depth;
    }
    workgroupBarrier();
}

// Froxel `k` of a box `extent` froxels wide from `first` (x fastest): two
// integer divisions instead of four.
fn froxel_at(first: vec3<i32>, extent: vec3<i32>, k: u32) -> vec3<i32> {
    let row = k / u32(extent.x);
    let layer = row / u32(extent.y);
    let x = k - row * u32(extent.x);
    let y = row - layer * u32(extent.y);
    return first + vec3<i32>(i32(x), i32(y), i32(layer));
}

// Froxel (x, y, z)'s view-space bounding box: its low and high corners.
fn froxel_box(x: i32, y: i32, z: i32) -> array<vec3<f32>, 2> {
    let slice = u32(clamp(z, 0, i32(MAX_SLICES) - 1));
    let d0 = slice_depths[slice];
    let d1 = slice_depths[slice + 1u];
    let to_ndc = grid.depth.w * camera.size.zw * 2.0;
    let n_lo = vec2<f32>(f32(x), f32(y)) * to_ndc;
    let n_hi = n_lo + to_ndc;
    // Tile edges in NDC (x right, y up) from pixel tiles (y down).
    let ndc_x = vec2<f32>(n_lo.x - 1.0, n_hi.x - 1.0);
    let ndc_y = vec2<f32>(1.0 - n_hi.y, 1.0 - n_lo.y);
    let sx = 1.0 / camera.projection[0][0];
    let sy = 1.0 / camera.projection[1][1];
    let xs = vec4<f32>(ndc_x.x * d0, ndc_x.x * d1, ndc_x.y * d0, ndc_x.y * d1) * sx;
    let ys = vec4<f32>(ndc_y.x * d0, ndc_y.x * d1, ndc_y.y * d0, ndc_y.y * d1) * sy;
    let lo = vec3<f32>(min(min(xs.x, xs.y), min(xs.z, xs.w)), min(min(ys.x, ys.y), min(ys.z, ys.w)), -d1);
    let hi = vec3<f32>(max(max(xs.x, xs.y), max(xs.z, xs.w)), max(max(ys.x, ys.y), max(ys.z, ys.w)), -d0);
    return array<vec3<f32>, 2>(lo, hi);
}

// Whether a light's sphere touches a froxel: the sphere against the froxel's
// view-space bounding box (froxel_box). Cuts the corners of the
// screen-space box, which for big lights is most of it.
fn touches(light: vec4<f32>, froxel: array<vec3<f32>, 2>) -> bool {
    let offset = light.xyz - clamp(light.xyz, froxel[0], froxel[1]);
    return dot(offset, offset) <= light.w * light.w;
}

// Light `index`'s band (MERGED) in view space, as `transform` wrote it; a
// band of 0 (every light without MERGED) lists the light wherever it reaches.
fn band_of(index: u32) -> vec4<f32> {
#ifdef MERGED
    return view_bands[index];
#else
    return vec4<f32>(0.0);
#endif
}

// Whether a froxel may hold a pixel on the light's side of its band: a
// member's side is nearer than the distance to the centroid, the merged
// light's the rest, so a member is listed where the box's nearest point is
// near, the merged light where its farthest is not. A froxel across the
// band lists both; each pixel then takes one (cook_torrance.wgsl's
// `band_keeps`, the same comparison), so none gets both or neither.
//
// Both tests are a little generous (BAND_SLACK): a pixel at a slice's edge
// may lie a few ulps outside its froxel's box, and must still find its side
// listed. Listing more costs a test, never a wrong sum: the pixel decides.
const BAND_SLACK: f32 = 1e-3;

fn in_band(band: vec4<f32>, froxel: array<vec3<f32>, 2>) -> bool {
    if (band.w == 0.0) {
        return true;
    }
    let d2 = band.w * band.w;
    if (band.w > 0.0) {
        let nearest = band.xyz - clamp(band.xyz, froxel[0], froxel[1]);
        return dot(nearest, nearest) < d2 * (1.0 + BAND_SLACK);
    }
    let farthest = max(abs(band.xyz - froxel[0]), abs(froxel[1] - band.xyz));
    return dot(farthest, farthest) >= d2 * (1.0 - BAND_SLACK);
}

// Whether froxel `f` lists the light: its sphere touches the froxel's box,
// on the light's side of its band.
fn lists(light: vec4<f32>, band: vec4<f32>, f: vec3<i32>) -> bool {
    let froxel = froxel_box(f.x, f.y, f.z);
    return touches(light, froxel) && in_band(band, froxel);
}

fn cluster_index(x: i32, y: i32, z: i32) -> u32 {
    return u32((z * i32(grid.dims.y) + y) * i32(grid.dims.x) + x);
}

// Whether froxel `f` needs a list: always, but with OCCUPIED only where a
// transparent fragment lies (one load, before the sphere test).
fn wanted(f: vec3<i32>) -> bool {
#ifdef OCCUPIED
    return occupied[cluster_index(f.x, f.y, f.z)] != 0u;
#else
    return true;
#endif
}

// Every light to view space (the naive path uses this alone).
@compute @workgroup_size(64)
fn transform(@builtin(global_invocation_id) id: vec3<u32>) {
    if (id.x >= grid.dims.w) {
        return;
    }
    let light = lights[id.x];
    let view = camera.view * vec4<f32>(light.position_range.xyz, 1.0);
    // The range the cutoff leaves (the range itself without one): the
    // assignment lists and the walks shade the light only that far.
    view_lights[id.x] = vec4<f32>(view.xyz, cutoff_range(light.position_range.w, light.intensity.rgb, grid.falloff.x));
#ifdef MERGED
    let band = bands[id.x];
    view_bands[id.x] = select(vec4<f32>(0.0), vec4<f32>((camera.view * vec4<f32>(band.xyz, 1.0)).xyz, band.w), band.w != 0.0);
#endif
}

// A light's froxels are shared among the 64 lanes of each of its workgroups
// (z: how many a light gets): a big light near the camera can touch
// thousands, and one thread each would serialize them. A frame with few
// lights gives each many workgroups, so a handful of big spots does not
// leave the GPU idle while 64 lanes walk 16,000 froxels each.
const LANES: u32 = 64u;

fn light_of(wid: vec3<u32>) -> u32 {
    return wid.x + wid.y * 65535u;
}

@compute @workgroup_size(64)
fn count(
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_index) lane: u32,
) {
    load_slice_depths(lane);
    let index = light_of(wid);
    if (index >= grid.dims.w) {
        return;
    }
    let light = view_lights[index];
    let band = band_of(index);
    let range = froxels(light);
    let extent = max(range[1] - range[0] + 1, vec3<i32>(0));
    let total = u32(extent.x * extent.y * extent.z);
    for (var k = lane + wid.z * LANES; k < total; k += LANES * groups.z) {
        let f = froxel_at(range[0], extent, k);
        if (wanted(f) && lists(light, band, f)) {
            atomicAdd(&counts[cluster_index(f.x, f.y, f.z)], 1u);
        }
    }
}

var<workgroup> partial: array<u32, 256>;

// partial[0..lanes] made their running sums (inclusive), in place:
// Hillis-Steele, log2(lanes) steps. Every lane of the workgroup calls it
// (barriers), after a barrier that follows its own write.
fn running_sums(lane: u32, lanes: u32) {
    for (var step = 1u; step < lanes; step *= 2u) {
        var add = 0u;
        if (lane >= step) {
            add = partial[lane - step];
        }
        workgroupBarrier();
        partial[lane] += add;
        workgroupBarrier();
    }
}

// Exclusive prefix sum of the counts into offsets, then counts are reset to
// serve as fill cursors. One workgroup walks the froxels 1,024 at a time:
// each thread takes four neighbours (so the workgroup's loads are
// contiguous), the 256 sums are scanned in shared memory (8 steps), and the
// total carries on to the next 1,024. Each thread walking a run of its own
// (64 froxels at 1080p) made every load of a warp touch 32 cache lines, one
// after another: 0.07 ms on the H100 whatever the light count.
@compute @workgroup_size(256)
fn scan(@builtin(local_invocation_index) lane: u32) {
    let n = grid.dims.x * grid.dims.y * grid.dims.z;
    var carry = 0u;
    for (var base = 0u; base < n; base += 1024u) {
        var mine = array<u32, 4>(0u, 0u, 0u, 0u);
        var sum = 0u;
        for (var j = 0u; j < 4u; j++) {
            let i = base + lane * 4u + j;
            if (i < n) {
                mine[j] = atomicLoad(&counts[i]);
                sum += mine[j];
            }
        }
        partial[lane] = sum;
        workgroupBarrier();
        running_sums(lane, 256u);
        var running = carry + partial[lane] - sum;
        for (var j = 0u; j < 4u; j++) {
            let i = base + lane * 4u + j;
            if (i < n) {
                offsets[i] = running;
                running += mine[j];
                atomicStore(&counts[i], 0u);
            }
        }
        carry += partial[255];
        // Every thread has read partial[255] before the next round writes it.
        workgroupBarrier();
    }
    if (lane == 255u) {
        atomicStore(&totals[0], carry);
    }
}

@compute @workgroup_size(64)
fn fill(
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_index) lane: u32,
) {
    load_slice_depths(lane);
    let index = light_of(wid);
    if (index >= grid.dims.w) {
        return;
    }
    let capacity = atomicLoad(&totals[1]);
    let light = view_lights[index];
    let band = band_of(index);
    let range = froxels(light);
    let extent = max(range[1] - range[0] + 1, vec3<i32>(0));
    let total = u32(extent.x * extent.y * extent.z);
    for (var k = lane + wid.z * LANES; k < total; k += LANES * groups.z) {
        let f = froxel_at(range[0], extent, k);
        if (!wanted(f) || !lists(light, band, f)) {
            continue;
        }
        let c = cluster_index(f.x, f.y, f.z);
        let slot = offsets[c] + atomicAdd(&counts[c], 1u);
        if (slot < capacity) {
            indices[slot] = index;
        } else {
            atomicAdd(&totals[2], 1u);
        }
    }
}

// PACKED assignment (many lights, crates/render/src/lighting/clusters.rs
// `Assignment::Packed`): a workgroup takes 64 lights, a lane each, and its
// 64 lanes share all their (light, froxel) pairs, so no lane idles while a
// light of a few froxels is listed; z splits the pairs among workgroups as
// the per-light steps split a light's froxels. With a workgroup per light,
// 100,000 lights of a dozen froxels each left most of every workgroup's 64
// lanes without a froxel, and the assignment took 0.34 ms on the H200.
var<workgroup> packed_first: array<vec3<i32>, LANES>;
var<workgroup> packed_extent: array<vec3<i32>, LANES>;
var<workgroup> packed_light: array<vec4<f32>, LANES>;
var<workgroup> packed_band: array<vec4<f32>, LANES>;

// The light of `lane` in workgroup `wid`: workgroup g takes lights g,
// g + G, g + 2G... (G workgroups in all), not 64 in a row, so that no
// workgroup gets only the far-reaching lights a list ends with (Light
// Merge's merged lights, appended after the rest: 64 of those in a row made
// a few workgroups run long after the others had finished).
fn packed_index(wid: vec3<u32>, lane: u32) -> u32 {
    let group = light_of(wid);
    let groups = (grid.dims.w + LANES - 1u) / LANES;
    return select(0xffffffffu, group + lane * groups, group < groups);
}

// Lane `lane`'s light and its froxel box, shared; the workgroup's pairs
// counted. Every lane calls it (barriers).
fn pack_lights(wid: vec3<u32>, lane: u32) -> u32 {
    load_slice_depths(lane);
    let index = packed_index(wid, lane);
    var first = vec3<i32>(0);
    var extent = vec3<i32>(0);
    var light = vec4<f32>(0.0);
    var band = vec4<f32>(0.0);
    if (index < grid.dims.w) {
        light = view_lights[index];
        band = band_of(index);
        let range = froxels(light);
        first = range[0];
        extent = max(range[1] - range[0] + 1, vec3<i32>(0));
    }
    packed_first[lane] = first;
    packed_extent[lane] = extent;
    packed_light[lane] = light;
    packed_band[lane] = band;
    partial[lane] = u32(extent.x * extent.y * extent.z);
    workgroupBarrier();
    running_sums(lane, LANES);
    return partial[LANES - 1u];
}

// The lane (0..64) whose pairs hold pair `k`: the first whose running sum
// of froxel counts (`partial`, from `pack_lights`) passes it.
fn packed_owner(k: u32) -> u32 {
    var lo = 0u;
    var hi = LANES - 1u;
    while (lo < hi) {
        let mid = (lo + hi) / 2u;
        if (partial[mid] > k) {
            hi = mid;
        } else {
            lo = mid + 1u;
        }
    }
    return lo;
}

// Pair `k` of the workgroup: its lane (`owner`), its froxel, and whether
// the froxel lists the lane's light. count_packed and fill_packed both ask
// this, so they visit the same pairs and a fill never passes a count.
struct PackedPair {
    owner: u32,
    froxel: vec3<i32>,
    listed: bool,
}

fn packed_pair(k: u32) -> PackedPair {
    let owner = packed_owner(k);
    let before = select(0u, partial[max(owner, 1u) - 1u], owner > 0u);
    let f = froxel_at(packed_first[owner], packed_extent[owner], k - before);
    return PackedPair(owner, f, wanted(f) && lists(packed_light[owner], packed_band[owner], f));
}

@compute @workgroup_size(64)
fn count_packed(
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_index) lane: u32,
) {
    let pairs = pack_lights(wid, lane);
    for (var k = lane + wid.z * LANES; k < pairs; k += LANES * groups.z) {
        let pair = packed_pair(k);
        if (pair.listed) {
            atomicAdd(&counts[cluster_index(pair.froxel.x, pair.froxel.y, pair.froxel.z)], 1u);
        }
    }
}

@compute @workgroup_size(64)
fn fill_packed(
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_index) lane: u32,
) {
    let pairs = pack_lights(wid, lane);
    let capacity = atomicLoad(&totals[1]);
    for (var k = lane + wid.z * LANES; k < pairs; k += LANES * groups.z) {
        let pair = packed_pair(k);
        if (!pair.listed) {
            continue;
        }
        let c = cluster_index(pair.froxel.x, pair.froxel.y, pair.froxel.z);
        let slot = offsets[c] + atomicAdd(&counts[c], 1u);
        if (slot < capacity) {
            indices[slot] = packed_index(wid, pair.owner);
        } else {
            atomicAdd(&totals[2], 1u);
        }
    }
}
