//! Streams made from other streams: normals from triangles (smooth or flat)
//! and tangents from normals and UVs (MikkTSpace). Everything here is total:
//! degenerate triangles get a fallback direction, never NaN.

use bevy_mikktspace::{Geometry, TangentSpace};
use glam::Vec3;

use super::{MeshData, MeshError};

/// How to make normals for a mesh that has none.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Shading {
    /// One normal per vertex, the area-weighted average of its triangles'.
    #[default]
    Smooth,
    /// One normal per triangle; vertices are unshared so each triangle keeps its own.
    /// This is what glTF asks for when a primitive has no normals.
    Flat,
}

/// The normal given to a vertex or triangle with no area to take one from.
const FALLBACK_NORMAL: [f32; 3] = [0.0, 1.0, 0.0];

/// The counter-clockwise normal of a triangle, scaled by twice its area.
fn face_normal(positions: &[[f32; 3]], tri: &[u32]) -> Vec3 {
    let p = |k: usize| {
        tri.get(k)
            .and_then(|&i| positions.get(i as usize))
            .map_or(Vec3::ZERO, |&p| Vec3::from(p))
    };
    let (a, b, c) = (p(0), p(1), p(2));
    (b - a).cross(c - a)
}

fn unit_or_fallback(n: Vec3) -> [f32; 3] {
    n.try_normalize().map_or(FALLBACK_NORMAL, |v| v.to_array())
}

/// Area-weighted vertex normals for an indexed triangle list. Indices out of
/// range are ignored; vertices on no triangle get +Y.
pub fn smooth_normals(positions: &[[f32; 3]], indices: &[u32]) -> Vec<[f32; 3]> {
    let mut sums = vec![Vec3::ZERO; positions.len()];
    for tri in indices.chunks_exact(3) {
        let n = face_normal(positions, tri);
        for &i in tri {
            if let Some(sum) = sums.get_mut(i as usize) {
                *sum += n;
            }
        }
    }
    sums.into_iter().map(unit_or_fallback).collect()
}

/// One normal per triangle (+Y for triangles without area).
pub fn flat_normals(positions: &[[f32; 3]], indices: &[u32]) -> Vec<[f32; 3]> {
    indices
        .chunks_exact(3)
        .map(|tri| unit_or_fallback(face_normal(positions, tri)))
        .collect()
}

/// `stream[indices[k]]` for every k: gives each triangle corner its own
/// vertex. Callers check the indices first; a stray one reads a default.
fn unweld<T: Copy + Default>(stream: &[T], indices: &[u32]) -> Vec<T> {
    indices
        .iter()
        .map(|&i| stream.get(i as usize).copied().unwrap_or_default())
        .collect()
}

impl MeshData {
    /// A mesh from positions, optional UVs and a triangle list: makes normals
    /// (see [`Shading`]), and tangents when there are UVs.
    pub fn from_triangles(
        positions: Vec<[f32; 3]>,
        uvs: Option<Vec<[f32; 2]>>,
        indices: Vec<u32>,
        shading: Shading,
    ) -> Result<MeshData, MeshError> {
        // Structure first, so unwelding below cannot miss an index.
        let mut mesh = MeshData {
            normals: vec![[0.0; 3]; positions.len()],
            positions,
            uvs,
            tangents: None,
            uvs1: None,
            colors: None,
            indices,
            bounds: super::Aabb::ZERO,
        };
        mesh.check_structure()?;
        match shading {
            Shading::Smooth => mesh.normals = smooth_normals(&mesh.positions, &mesh.indices),
            Shading::Flat => {
                let normals = flat_normals(&mesh.positions, &mesh.indices);
                mesh.normals = normals.iter().flat_map(|&n| [n; 3]).collect();
                mesh.positions = unweld(&mesh.positions, &mesh.indices);
                mesh.uvs = mesh.uvs.as_deref().map(|uvs| unweld(uvs, &mesh.indices));
                mesh.uvs1 = mesh.uvs1.as_deref().map(|uvs| unweld(uvs, &mesh.indices));
                mesh.colors = mesh.colors.as_deref().map(|c| unweld(c, &mesh.indices));
                mesh.indices = (0..mesh.indices.len() as u32).collect();
            }
        }
        mesh.recompute_bounds();
        if mesh.uvs.is_some() {
            mesh.generate_tangents()?;
        }
        mesh.validate()?;
        Ok(mesh)
    }
}

/// The MikkTSpace view of an indexed triangle list. Reads go through `get`
/// so that a malformed mesh gives zeros, never a panic.
struct Mikk<'a> {
    positions: &'a [[f32; 3]],
    normals: &'a [[f32; 3]],
    uvs: &'a [[f32; 2]],
    indices: &'a [u32],
    tangents: Vec<Option<[f32; 4]>>,
}

impl Mikk<'_> {
    fn vertex(&self, face: usize, vert: usize) -> usize {
        self.indices
            .get(face * 3 + vert)
            .map_or(usize::MAX, |&i| i as usize)
    }
}

impl Geometry for Mikk<'_> {
    fn num_faces(&self) -> usize {
        self.indices.len() / 3
    }

    fn num_vertices_of_face(&self, _face: usize) -> usize {
        3
    }

    fn position(&self, face: usize, vert: usize) -> [f32; 3] {
        let v = self.vertex(face, vert);
        self.positions.get(v).copied().unwrap_or_default()
    }

    fn normal(&self, face: usize, vert: usize) -> [f32; 3] {
        let v = self.vertex(face, vert);
        self.normals.get(v).copied().unwrap_or_default()
    }

    fn tex_coord(&self, face: usize, vert: usize) -> [f32; 2] {
        let v = self.vertex(face, vert);
        self.uvs.get(v).copied().unwrap_or_default()
    }

    fn set_tangent(&mut self, tangent_space: Option<TangentSpace>, face: usize, vert: usize) {
        let v = self.vertex(face, vert);
        if let (Some(ts), Some(slot)) = (tangent_space, self.tangents.get_mut(v)) {
            *slot = Some(ts.tangent_encoded());
        }
    }
}

/// MikkTSpace tangents for an indexed triangle list, made safe to use: each
/// is re-orthogonalised to its vertex's normal and normalised, and a vertex
/// without one gets any unit vector perpendicular to its normal.
///
/// MikkTSpace assumes v grows upwards (OpenGL, Blender); our UVs grow
/// downwards like glTF's, so its handedness is negated. That is what makes
/// `cross(normal, tangent) * w` point to decreasing v, the +Y ("green up")
/// direction of glTF normal maps; three.js does the same for glTF.
pub(crate) fn mikktspace_tangents(
    positions: &[[f32; 3]],
    normals: &[[f32; 3]],
    uvs: &[[f32; 2]],
    indices: &[u32],
) -> Vec<[f32; 4]> {
    let mut mikk = Mikk {
        positions,
        normals,
        uvs,
        indices,
        tangents: vec![None; positions.len()],
    };
    // The error type has no variants: generation cannot fail.
    let _ = bevy_mikktspace::generate_tangents(&mut mikk);
    mikk.tangents
        .iter()
        .enumerate()
        .map(|(v, tangent)| {
            let n = normals
                .get(v)
                .and_then(|&n| Vec3::from(n).try_normalize())
                .unwrap_or(Vec3::Y);
            let (t, w) = tangent.map_or((Vec3::ZERO, 1.0), |[x, y, z, w]| {
                (Vec3::new(x, y, z), if w < 0.0 { 1.0 } else { -1.0 })
            });
            let t = (t - n * n.dot(t))
                .try_normalize()
                .unwrap_or_else(|| n.any_orthonormal_vector());
            [t.x, t.y, t.z, w]
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn smooth_normals_average_and_fall_back() {
        // Two triangles folded along the x axis, plus an unused vertex.
        let positions = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
            [5.0, 5.0, 5.0],
        ];
        let n = smooth_normals(&positions, &[0, 1, 2, 0, 3, 1]);
        assert_eq!(n[2], [0.0, 0.0, 1.0]);
        assert_eq!(n[3], [0.0, 1.0, 0.0]);
        let shared = Vec3::from(n[0]);
        assert!((shared - Vec3::new(0.0, 1.0, 1.0).normalize()).length() < 1e-6);
        assert_eq!(n[4], FALLBACK_NORMAL);
        // Out-of-range indices are skipped, not a panic.
        assert_eq!(smooth_normals(&positions, &[0, 1, 99]).len(), 5);
    }

    #[test]
    fn flat_shading_unwelds() {
        let positions = vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
        ];
        let uvs = Some(vec![[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0]]);
        let m = MeshData::from_triangles(positions, uvs, vec![0, 1, 2, 0, 3, 1], Shading::Flat)
            .unwrap();
        assert_eq!(m.vertex_count(), 6);
        assert_eq!(m.indices, vec![0, 1, 2, 3, 4, 5]);
        assert_eq!(&m.normals[..3], &[[0.0, 0.0, 1.0]; 3]);
        assert_eq!(&m.normals[3..], &[[0.0, 1.0, 0.0]; 3]);
        assert_eq!(m.tangents.as_ref().map(Vec::len), Some(6));
        assert_eq!(m.validate(), Ok(()));

        let bad = MeshData::from_triangles(vec![[0.0; 3]], None, vec![0, 0, 1], Shading::Flat);
        assert!(matches!(bad, Err(MeshError::IndexOutOfRange { .. })));
    }

    #[test]
    fn degenerate_triangles_get_perpendicular_unit_tangents() {
        // All three corners at one point, all UVs equal: MikkTSpace has nothing to go on.
        let positions = vec![[1.0, 2.0, 3.0]; 3];
        let mut m = MeshData::from_triangles(
            positions,
            Some(vec![[0.5, 0.5]; 3]),
            vec![0, 1, 2],
            Shading::Smooth,
        )
        .unwrap();
        m.generate_tangents().unwrap();
        for (t, n) in m.tangents.as_ref().unwrap().iter().zip(&m.normals) {
            let t3 = Vec3::new(t[0], t[1], t[2]);
            assert!((t3.length() - 1.0).abs() < 1e-5);
            assert!(t3.dot(Vec3::from(*n)).abs() < 1e-5);
            assert!(t[3] == 1.0 || t[3] == -1.0);
        }
    }
}
