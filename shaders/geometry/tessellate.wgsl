// Tessellate: area-adaptive, crack-free subdivision (crates/render/src/geometry/tessellate.rs).
//
// Every edge is cut into k = ceil(length / L) equal segments, L = sqrt(2 x Max
// Area); k depends on the edge's two end positions alone (taken in a fixed
// order), so the two triangles sharing an edge cut it at the same points,
// even across UV seams where the vertices are duplicated: no T-junctions, no
// cracks. A triangle becomes a grid of level n (n² triangles) with
// n = max(k of its edges, ceil(area / (min k x Max Area))); the grid's points
// on an edge snap to that edge's k cut points (the two triangles' grids may
// differ; the cut points do not). Snapping leaves zero-area triangles where
// grid points meet (drawn as nothing) and keeps every triangle at most Max
// Area: grid triangles have edges of at most L, and a triangle along an
// edge spans at most one cut segment with its apex one grid row in.
//
// Three stages (one shader, a feature each, as the CPU runs them):
// COUNT: each triangle's level and its vertex and triangle counts, scanned
//   inside its workgroup of 64 (exclusive offsets) with the group's total;
// SUMS: one workgroup scans the group totals (and writes the grand total,
//   read back to size the output mesh);
// write (no feature): each triangle writes its grid at its offset.
#import spreadlight::geometry::{job, invocation, indices, vertices, source_vertex, write_vertex, unit_or, orthogonal_tangent}
#import spreadlight::mesh::Vertex

struct Params {
    max_area: f32,
    // sqrt(2 x max_area): the longest edge segment.
    segment: f32,
    max_level: u32,
    // Workgroups of the COUNT stage (SUMS scans this many totals).
    blocks: u32,
}

@group(0) @binding(3) var<uniform> params: Params;
// Per input triangle: its level (COUNT writes, write reads).
@group(0) @binding(4) var<storage, read_write> levels: array<u32>;
// Per input triangle: (vertices, triangles) before it within its workgroup.
@group(0) @binding(5) var<storage, read_write> offsets: array<vec2<u32>>;
// Per workgroup: its total (COUNT), then (SUMS) the totals before it; entry `blocks`: the grand total.
@group(0) @binding(6) var<storage, read_write> blocks: array<vec2<u32>>;

var<workgroup> scratch: array<vec2<u32>, 64>;

fn corner_index(face: u32, k: u32) -> u32 {
    return indices[job.src_index + face * 3u + k];
}

fn corner(face: u32, k: u32) -> Vertex {
    return source_vertex(corner_index(face, k));
}

// Whether p comes before q (lexicographic): the fixed order of an edge's ends.
fn before(p: vec3<f32>, q: vec3<f32>) -> bool {
    if (p.x != q.x) {
        return p.x < q.x;
    }
    if (p.y != q.y) {
        return p.y < q.y;
    }
    return p.z < q.z;
}

// Segments of the edge p-q: the same whichever way round it is asked.
fn edge_segments(p: vec3<f32>, q: vec3<f32>) -> u32 {
    var lo = p;
    var hi = q;
    if (before(q, p)) {
        lo = q;
        hi = p;
    }
    let d = hi - lo;
    let k = ceil(sqrt(dot(d, d)) / params.segment);
    // NaN or huge: as fine as allowed.
    if (!(k < f32(params.max_level))) {
        return params.max_level;
    }
    return max(u32(k), 1u);
}

// The level of the triangle p0 p1 p2 and its three edges' segments (ab, bc, ca).
fn level_of(p0: vec3<f32>, p1: vec3<f32>, p2: vec3<f32>) -> vec4<u32> {
    let kab = edge_segments(p0, p1);
    let kbc = edge_segments(p1, p2);
    let kca = edge_segments(p2, p0);
    let area = 0.5 * length(cross(p1 - p0, p2 - p0));
    let kmin = min(kab, min(kbc, kca));
    var n = max(kab, max(kbc, kca));
    let by_area = ceil(area / (f32(kmin) * params.max_area));
    if (!(by_area < f32(params.max_level))) {
        n = params.max_level;
    } else {
        n = max(n, u32(by_area));
    }
    return vec4<u32>(min(n, params.max_level), kab, kbc, kca);
}

// Vertices and triangles of a level-n grid.
fn counts(n: u32) -> vec2<u32> {
    return vec2<u32>((n + 1u) * (n + 2u) / 2u, n * n);
}

// Inclusive scan of `scratch` by the 64 invocations of a workgroup (Hillis-Steele).
fn scan_scratch(l: u32) {
    for (var step = 1u; step < 64u; step = step * 2u) {
        workgroupBarrier();
        var add = vec2<u32>(0u);
        if (l >= step) {
            add = scratch[l - step];
        }
        workgroupBarrier();
        scratch[l] += add;
    }
    workgroupBarrier();
}

#ifdef COUNT
@compute @workgroup_size(64)
fn main(
    @builtin(global_invocation_id) id: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_index) l: u32,
    @builtin(workgroup_id) wg: vec3<u32>,
) {
    let face = invocation(id, groups);
    let faces = job.src_index_count / 3u;
    var mine = vec2<u32>(0u);
    if (face < faces) {
        let n = level_of(corner(face, 0u).position_u.xyz, corner(face, 1u).position_u.xyz, corner(face, 2u).position_u.xyz).x;
        levels[face] = n;
        mine = counts(n);
    }
    scratch[l] = mine;
    scan_scratch(l);
    if (face < faces) {
        offsets[face] = scratch[l] - mine;
    }
    let block = wg.x + wg.y * groups.x;
    if (l == 63u && block < params.blocks) {
        blocks[block] = scratch[63];
    }
}
#else
#ifdef SUMS
@compute @workgroup_size(64)
fn main(@builtin(local_invocation_index) l: u32) {
    // Each invocation scans a run of consecutive totals.
    let per = (params.blocks + 63u) / 64u;
    let first = min(l * per, params.blocks);
    let end = min(first + per, params.blocks);
    var sum = vec2<u32>(0u);
    for (var b = first; b < end; b++) {
        sum += blocks[b];
    }
    scratch[l] = sum;
    scan_scratch(l);
    var running = scratch[l] - sum;
    for (var b = first; b < end; b++) {
        let total = blocks[b];
        blocks[b] = running;
        running += total;
    }
    if (l == 63u) {
        blocks[params.blocks] = scratch[63];
    }
}
#else
// Grid point (row r, column c) of a level-n face: barycentrics
// (1 - (c + r) / n, c / n, r / n); first vertex of row r:
fn row_start(r: u32, n: u32) -> u32 {
    return r * (n + 1u) - r * (r - 1u) / 2u * select(0u, 1u, r > 0u);
}

// The cut point of edge p->q (k segments) nearest to grid step j of n, as
// (position, parameter from p). The position is computed from the edge's
// ends in their fixed order, so both triangles get the same bits.
fn snap(p: vec3<f32>, q: vec3<f32>, k: u32, j: u32, n: u32) -> vec4<f32> {
    let cut = (2u * j * k + n) / (2u * n);
    let t = f32(cut) / f32(k);
    if (before(q, p)) {
        return vec4<f32>(q + (p - q) * (f32(k - cut) / f32(k)), t);
    }
    return vec4<f32>(p + (q - p) * t, t);
}

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let face = invocation(id, groups);
    if (face >= job.src_index_count / 3u) {
        return;
    }
    let base = offsets[face] + blocks[face / 64u];
    let a = corner(face, 0u);
    let b = corner(face, 1u);
    let c = corner(face, 2u);
    let pa = a.position_u.xyz;
    let pb = b.position_u.xyz;
    let pc = c.position_u.xyz;
    let lv = level_of(pa, pb, pc);
    let n = levels[face];
    let kab = lv.y;
    let kbc = lv.z;
    let kca = lv.w;
    let na = unit_or(a.normal_v.xyz, vec3<f32>(0.0, 1.0, 0.0));
    let nb = unit_or(b.normal_v.xyz, na);
    let nc = unit_or(c.normal_v.xyz, na);
    let id_of_face = a.previous_position.w;
    for (var r = 0u; r <= n; r++) {
        for (var col = 0u; col <= n - r; col++) {
            var w = vec3<f32>(f32(n - r - col), f32(col), f32(r)) / f32(n);
            var position = pa * w.x + pb * w.y + pc * w.z;
            let corner_point = (r == 0u && (col == 0u || col == n)) || (r == n);
            if (corner_point) {
                // Exactly the input's corner.
                if (r == n) {
                    position = pc;
                } else if (col == 0u) {
                    position = pa;
                } else {
                    position = pb;
                }
            } else if (r == 0u) {
                let s = snap(pa, pb, kab, col, n);
                position = s.xyz;
                w = vec3<f32>(1.0 - s.w, s.w, 0.0);
            } else if (col == 0u) {
                // Edge c -> a: step n - r from c.
                let s = snap(pc, pa, kca, n - r, n);
                position = s.xyz;
                w = vec3<f32>(s.w, 0.0, 1.0 - s.w);
            } else if (r + col == n) {
                let s = snap(pb, pc, kbc, r, n);
                position = s.xyz;
                w = vec3<f32>(0.0, 1.0 - s.w, s.w);
            }
            let normal = unit_or(na * w.x + nb * w.y + nc * w.z, na);
            let uv = vec2<f32>(
                dot(w, vec3<f32>(a.position_u.w, b.position_u.w, c.position_u.w)),
                dot(w, vec3<f32>(a.normal_v.w, b.normal_v.w, c.normal_v.w)),
            );
            let tangent = orthogonal_tangent(a.tangent * w.x + b.tangent * w.y + c.tangent * w.z, normal);
            write_vertex(base.x + row_start(r, n) + col, position, normal, uv, tangent, id_of_face);
        }
    }
    // Row r holds 2 (n - r) - 1 triangles: up (c, c+1, c above) and down.
    var t = base.y * 3u;
    for (var r = 0u; r < n; r++) {
        let here = base.x + row_start(r, n);
        let next = base.x + row_start(r + 1u, n);
        for (var col = 0u; col < n - r; col++) {
            indices[job.dst_index + t] = here + col;
            indices[job.dst_index + t + 1u] = here + col + 1u;
            indices[job.dst_index + t + 2u] = next + col;
            t += 3u;
            if (col + 1u < n - r) {
                indices[job.dst_index + t] = here + col + 1u;
                indices[job.dst_index + t + 1u] = next + col + 1u;
                indices[job.dst_index + t + 2u] = next + col;
                t += 3u;
            }
        }
    }
}
#endif
#endif
