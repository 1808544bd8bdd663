//! Analytic surfaces that tessellation is measured against: a unit
//! icosahedron (the coarse mesh of a sphere, exact sphere normals) and the
//! distances from a point to the unit sphere and to a torus.

use glam::{Vec2, Vec3};

use crate::mesh::MeshData;

/// A unit icosahedron with shared vertices and the sphere's normals.
pub fn icosahedron() -> MeshData {
    let t = (1.0 + 5f32.sqrt()) / 2.0;
    let raw = [
        [-1.0, t, 0.0],
        [1.0, t, 0.0],
        [-1.0, -t, 0.0],
        [1.0, -t, 0.0],
        [0.0, -1.0, t],
        [0.0, 1.0, t],
        [0.0, -1.0, -t],
        [0.0, 1.0, -t],
        [t, 0.0, -1.0],
        [t, 0.0, 1.0],
        [-t, 0.0, -1.0],
        [-t, 0.0, 1.0],
    ];
    let positions: Vec<[f32; 3]> = raw
        .iter()
        .map(|p| Vec3::from(*p).normalize().into())
        .collect();
    let indices = vec![
        0, 11, 5, 0, 5, 1, 0, 1, 7, 0, 7, 10, 0, 10, 11, 1, 5, 9, 5, 11, 4, 11, 10, 2, 10, 7, 6, 7,
        1, 8, 3, 9, 4, 3, 4, 2, 3, 2, 6, 3, 6, 8, 3, 8, 9, 4, 9, 5, 2, 4, 11, 6, 2, 10, 8, 6, 7, 9,
        8, 1,
    ];
    let mut mesh = MeshData {
        normals: positions.clone(),
        positions,
        uvs: None,
        tangents: None,
        uvs1: None,
        colors: None,
        indices,
        bounds: crate::mesh::Aabb::ZERO,
    };
    mesh.recompute_bounds();
    mesh
}

/// Distance from `p` to the unit sphere at the origin.
pub fn sphere_distance(p: Vec3) -> f32 {
    (p.length() - 1.0).abs()
}

/// Distance from `p` to the torus around Y with these radii.
pub fn torus_distance(p: Vec3, major: f32, minor: f32) -> f32 {
    let ring = Vec2::new(p.x, p.z).length() - major;
    (Vec2::new(ring, p.y).length() - minor).abs()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_icosahedron_is_valid_and_on_the_unit_sphere() {
        let m = icosahedron();
        assert_eq!(m.validate(), Ok(()));
        assert_eq!((m.vertex_count(), m.triangle_count()), (12, 20));
        for p in &m.positions {
            assert!(sphere_distance(Vec3::from(*p)) < 1e-6);
        }
        // Counter-clockwise seen from outside: every face normal points away from the centre.
        for t in m.indices.chunks(3) {
            let p = |i: u32| Vec3::from(m.positions[i as usize]);
            let n = (p(t[1]) - p(t[0])).cross(p(t[2]) - p(t[0]));
            assert!(n.dot(p(t[0])) > 0.0);
        }
        assert!(torus_distance(Vec3::new(1.25, 0.0, 0.0), 1.0, 0.25) < 1e-6);
    }
}
