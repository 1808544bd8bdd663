// A particle as it lives in the mesh arena: one 64-byte record (the arena's
// vertex size) per particle, after one header record, so every pass that
// pulls meshes from the arena can draw particles straight from their state
// (shaders/lib/mesh_fetch.wgsl) and the simulation (shaders/particles/
// simulate.wgsl) steps them in place. Matches `Particle` in
// crates/render/src/particles/mod.rs.
#define_import_path spreadlight::particle

#import spreadlight::mesh::Vertex

struct Particle {
    position: vec3<f32>,
    age: f32,
    velocity: vec3<f32>,
    lifetime: f32,
    previous: vec3<f32>,
    alive: u32,
}

fn unpack_particle(r: Vertex) -> Particle {
    return Particle(r.position_u.xyz, r.position_u.w, r.normal_v.xyz, r.normal_v.w, r.tangent.xyz, bitcast<u32>(r.tangent.w));
}

fn pack_particle(p: Particle) -> Vertex {
    return Vertex(
        vec4<f32>(p.position, p.age),
        vec4<f32>(p.velocity, p.lifetime),
        vec4<f32>(p.previous, bitcast<f32>(p.alive)),
        vec4<f32>(0.0),
    );
}

// The header record of a particle system's draw (written by
// crates/render/src/particles/draw.rs):
//   position_u (bits): shape (0 sprites, 1 copies of a mesh), the shape's
//                      first index, base vertex and triangles;
//   normal_v:          size (sprite half size or shape scale), shrink with age (0 or 1).
struct ParticleHeader {
    shape: u32,
    first_index: u32,
    base_vertex: u32,
    triangles: u32,
    size: f32,
    shrink: f32,
}

fn unpack_header(r: Vertex) -> ParticleHeader {
    let bits = bitcast<vec4<u32>>(r.position_u);
    return ParticleHeader(bits.x, bits.y, bits.z, bits.w, r.normal_v.x, r.normal_v.y);
}

// How big a particle is drawn: 0 when dead (its triangles collapse to a
// point and draw nothing), shrinking to 0 over its life when asked.
fn particle_scale(p: Particle, h: ParticleHeader) -> f32 {
    if (p.alive == 0u) {
        return 0.0;
    }
    let t = clamp(p.age / max(p.lifetime, 1e-6), 0.0, 1.0);
    return h.size * mix(1.0, 1.0 - t, h.shrink);
}
