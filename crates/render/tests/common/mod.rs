//! Shape checks shared by the geometry tests.

use std::collections::HashMap;

use spreadlight_render::mesh_arena::GpuVertex;

/// A position quantized to 1e-4 (vertices split for seams share it).
pub fn key(vertices: &[GpuVertex], i: u32) -> [i64; 3] {
    let p = vertices[i as usize].position_u;
    [p[0], p[1], p[2]].map(|x| (x * 1e4).round() as i64)
}

/// Undirected edges by quantized end positions, with how often each is used
/// a→b minus b→a (0 everywhere on a closed oriented surface).
pub fn edge_balance(vertices: &[GpuVertex], indices: &[u32]) -> HashMap<([i64; 3], [i64; 3]), i64> {
    let mut edges: HashMap<([i64; 3], [i64; 3]), i64> = HashMap::new();
    for t in indices.chunks(3) {
        for k in 0..3 {
            let (a, b) = (key(vertices, t[k]), key(vertices, t[(k + 1) % 3]));
            if a == b {
                continue;
            }
            let (lo, hi, d) = if a < b { (a, b, 1) } else { (b, a, -1) };
            *edges.entry((lo, hi)).or_default() += d;
        }
    }
    edges
}

/// Directed edges by quantized end positions: a closed oriented surface
/// has every edge once in each direction (as many times a→b as b→a).
pub fn open_edges(vertices: &[GpuVertex], indices: &[u32]) -> usize {
    edge_balance(vertices, indices)
        .values()
        .filter(|&&n| n != 0)
        .count()
}
