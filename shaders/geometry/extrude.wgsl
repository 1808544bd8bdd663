// Extrude: every triangle becomes a prism along its face normal: a cap
// raised by the face's amount and three side walls, flat-shaded (15
// vertices, 7 triangles a face; the original face is replaced by the
// prism, so a closed mesh stays closed). Amount per face: `amounts`,
// cycled. Caps keep the input's UVs and tangents; walls take the edge's
// UVs at both heights and a tangent along the edge. With TEXTURE, a face's
// amount is also scaled by the texture's red channel at its centroid's UV.
#import spreadlight::geometry::{job, invocation, indices, source_vertex, write_vertex, unit_or}
#import spreadlight::mesh::Vertex

@group(0) @binding(4) var<storage, read> amounts: array<f32>;
#ifdef TEXTURE
@group(0) @binding(5) var height: texture_2d<f32>;
@group(0) @binding(6) var height_sampler: sampler;
#endif

// Local indices of one prism: the cap, then two triangles per wall.
const LOCAL: array<u32, 21> = array<u32, 21>(
    0u, 1u, 2u,
    3u, 4u, 5u, 3u, 5u, 6u,
    7u, 8u, 9u, 7u, 9u, 10u,
    11u, 12u, 13u, 11u, 13u, 14u,
);

fn corner(face: u32, k: u32) -> Vertex {
    return source_vertex(indices[job.src_index + face * 3u + k]);
}

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = invocation(id, groups);
    if (i < job.index_count) {
        indices[job.dst_index + i] = (i / 21u) * 15u + LOCAL[i % 21u];
    }
    if (i >= job.vertex_count) {
        return;
    }
    let face = i / 15u;
    let k = i % 15u;
    let v = array<Vertex, 3>(corner(face, 0u), corner(face, 1u), corner(face, 2u));
    let p0 = v[0].position_u.xyz;
    let p1 = v[1].position_u.xyz;
    let p2 = v[2].position_u.xyz;
    let n = unit_or(cross(p1 - p0, p2 - p0), unit_or(v[0].normal_v.xyz, vec3<f32>(0.0, 1.0, 0.0)));
    var h = amounts[face % arrayLength(&amounts)];
#ifdef TEXTURE
    let centroid_uv = (vec2<f32>(v[0].position_u.w, v[0].normal_v.w) + vec2<f32>(v[1].position_u.w, v[1].normal_v.w)
        + vec2<f32>(v[2].position_u.w, v[2].normal_v.w)) / 3.0;
    h *= textureSampleLevel(height, height_sampler, centroid_uv, 0.0).r;
#endif
    if (!(abs(h) < 3.0e38)) {
        h = 0.0;
    }
    let lift = n * h;
    let id_of_face = v[0].previous_position.w;
    if (k < 3u) {
        let c = v[k];
        write_vertex(i, c.position_u.xyz + lift, n, vec2<f32>(c.position_u.w, c.normal_v.w), c.tangent, id_of_face);
        return;
    }
    let e = (k - 3u) / 4u;
    let c = (k - 3u) % 4u;
    let a = v[e];
    let b = v[(e + 1u) % 3u];
    let edge = b.position_u.xyz - a.position_u.xyz;
    // Outward for a counter-clockwise face raised along +n.
    let wall = unit_or(cross(edge, n) * sign(h + 1e-30), n);
    let from_b = c == 1u || c == 2u;
    let raised = c >= 2u;
    var corner_vertex = a;
    if (from_b) {
        corner_vertex = b;
    }
    var position = corner_vertex.position_u.xyz;
    if (raised) {
        position += lift;
    }
    let uv = vec2<f32>(corner_vertex.position_u.w, corner_vertex.normal_v.w);
    write_vertex(i, position, wall, uv, vec4<f32>(unit_or(edge, vec3<f32>(1.0, 0.0, 0.0)), 1.0), id_of_face);
}
