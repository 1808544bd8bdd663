// The arena's extra stream (the second UV set and the vertex colour,
// `GpuVertexExtra` in crates/render/src/mesh_arena.rs) for the passes that
// read it: binding 12 of group 0, and a triangle corner's extras. Imported
// only by the permutations that need it (VERTEX_EXTRAS, ALPHA_MASK), so
// the others bind nothing more.
#define_import_path spreadlight::vertex_extras

#import spreadlight::mesh::{Vertex, VertexExtra, default_extra}
#import spreadlight::mesh_fetch::{triangle_vertex_index, NO_VERTEX}

@group(0) @binding(12) var<storage, read> extras: array<VertexExtra>;

// The extras of corner `corner` of triangle `triangle` of `instance`,
// whose vertex is `v`: stored ones, or for a procedural mesh (particles,
// whose corners are made, not stored) its first UV set and white.
fn corner_extra(instance: u32, triangle: u32, corner: u32, v: Vertex) -> VertexExtra {
    let index = triangle_vertex_index(instance, triangle, corner);
    if (index == NO_VERTEX) {
        return default_extra(v);
    }
    return extras[index];
}
