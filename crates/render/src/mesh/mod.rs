//! Meshes on the CPU side: the vertex streams every renderer path consumes
//! ([`MeshData`]), their bounds ([`Aabb`]), the checks a mesh must pass before
//! it is uploaded ([`MeshData::validate`]), and where meshes come from:
//! [`primitives`] (box, sphere, grid, cylinder, torus), and what deforms a
//! mesh ([`deform`]: skins and morph targets, which `spreadlight-gltf`
//! imports and `geometry::skinning` applies).
//!
//! Pure data and loading, no wgpu: everything here is testable anywhere.
//!
//! Conventions, shared with glTF so imported and generated meshes agree:
//! right-handed, +Y up, counter-clockwise front faces, texture coordinates
//! with the origin at the top-left of the image (v grows downwards), and
//! tangents whose `w` gives the bitangent as `cross(normal, tangent.xyz) * w`.

pub mod deform;
mod generate;
pub mod primitives;

use glam::{Mat4, Vec3};
use thiserror::Error;

pub use generate::{Shading, flat_normals, smooth_normals};
pub use primitives::{
    BoxParams, CylinderParams, GridParams, SphereParams, TorusParams, box_mesh, cylinder, grid,
    plane, sphere, torus,
};

/// An axis-aligned bounding box. An empty set of points has [`Aabb::ZERO`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Aabb {
    pub min: Vec3,
    pub max: Vec3,
}

impl Default for Aabb {
    fn default() -> Self {
        Self::ZERO
    }
}

impl Aabb {
    /// The box of nothing: a point at the origin, so it stays finite.
    pub const ZERO: Aabb = Aabb {
        min: Vec3::ZERO,
        max: Vec3::ZERO,
    };

    /// The smallest box holding every point, or [`Aabb::ZERO`] if there are none.
    pub fn from_points(points: impl IntoIterator<Item = Vec3>) -> Aabb {
        let mut points = points.into_iter();
        let Some(first) = points.next() else {
            return Aabb::ZERO;
        };
        points.fold(
            Aabb {
                min: first,
                max: first,
            },
            |b, p| Aabb {
                min: b.min.min(p),
                max: b.max.max(p),
            },
        )
    }

    /// The smallest box holding both.
    pub fn union(self, other: Aabb) -> Aabb {
        Aabb {
            min: self.min.min(other.min),
            max: self.max.max(other.max),
        }
    }

    pub fn center(self) -> Vec3 {
        (self.min + self.max) * 0.5
    }

    pub fn size(self) -> Vec3 {
        self.max - self.min
    }

    /// The eight corners, in an order fixed by the bits of the index (x, y, z).
    pub fn corners(self) -> [Vec3; 8] {
        std::array::from_fn(|i| {
            Vec3::new(
                if i & 1 == 0 { self.min.x } else { self.max.x },
                if i & 2 == 0 { self.min.y } else { self.max.y },
                if i & 4 == 0 { self.min.z } else { self.max.z },
            )
        })
    }

    /// The box around this box's corners after an affine transform (may be
    /// looser than the box of the transformed mesh, never tighter).
    ///
    /// Arvo's form: per column the smaller and the larger of its products
    /// with the box's two ends, summed in `transform_point3`'s order. Rounded
    /// addition is monotonic, so this is the box of the eight transformed
    /// corners bit for bit, at a third of the work (a skinned herd bounds
    /// thousands of joint boxes a frame).
    pub fn transformed(self, transform: Mat4) -> Aabb {
        let ends = |axis: glam::Vec4, lo: f32, hi: f32| {
            let (a, b) = (axis.truncate() * lo, axis.truncate() * hi);
            (a.min(b), a.max(b))
        };
        let (x_min, x_max) = ends(transform.x_axis, self.min.x, self.max.x);
        let (y_min, y_max) = ends(transform.y_axis, self.min.y, self.max.y);
        let (z_min, z_max) = ends(transform.z_axis, self.min.z, self.max.z);
        let w = transform.w_axis.truncate();
        Aabb {
            min: w + (z_min + (y_min + x_min)),
            max: w + (z_max + (y_max + x_max)),
        }
    }

    pub fn is_finite(self) -> bool {
        self.min.is_finite() && self.max.is_finite()
    }
}

/// Why a mesh cannot be used as it is.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum MeshError {
    #[error("the {stream} stream has {len} entries, but the mesh has {vertices} positions")]
    StreamLength {
        stream: &'static str,
        len: usize,
        vertices: usize,
    },
    #[error("{count} indices is not a whole number of triangles (a multiple of 3)")]
    IndexCount { count: usize },
    #[error("index {at} is {index}, but the mesh has only {vertices} vertices")]
    IndexOutOfRange {
        at: usize,
        index: u32,
        vertices: usize,
    },
    #[error("{stream}[{at}] is not a finite number")]
    NotFinite { stream: &'static str, at: usize },
    #[error(
        "the bounds ({min:?} to {max:?}) are not the bounds of the positions; call recompute_bounds"
    )]
    StaleBounds { min: Vec3, max: Vec3 },
    #[error("tangents need texture coordinates, and this mesh has none")]
    NoUvs,
}

/// One mesh as the renderer consumes it: indexed triangles with per-vertex streams.
#[derive(Debug, Clone, PartialEq)]
pub struct MeshData {
    pub positions: Vec<[f32; 3]>,
    /// Always present: importers and generators make them when the source has none.
    pub normals: Vec<[f32; 3]>,
    /// `None` when the source has no texture coordinates.
    pub uvs: Option<Vec<[f32; 2]>>,
    /// xyz and handedness `w` = ±1 (bitangent = `cross(normal, xyz) * w`).
    /// Generated with MikkTSpace when there are UVs and the source has none.
    pub tangents: Option<Vec<[f32; 4]>>,
    /// A second UV set (glTF's TEXCOORD_1), for maps whose `texCoord` is 1.
    pub uvs1: Option<Vec<[f32; 2]>>,
    /// Linear RGBA vertex colours (glTF's COLOR_0), multiplying the base colour.
    pub colors: Option<Vec<[f32; 4]>>,
    /// Triangle list, counter-clockwise front faces.
    pub indices: Vec<u32>,
    /// Min/max of `positions`.
    pub bounds: Aabb,
}

impl MeshData {
    /// A mesh from complete streams; computes the bounds and validates.
    pub fn new(
        positions: Vec<[f32; 3]>,
        normals: Vec<[f32; 3]>,
        uvs: Option<Vec<[f32; 2]>>,
        tangents: Option<Vec<[f32; 4]>>,
        indices: Vec<u32>,
    ) -> Result<MeshData, MeshError> {
        let mut mesh = MeshData {
            positions,
            normals,
            uvs,
            tangents,
            uvs1: None,
            colors: None,
            indices,
            bounds: Aabb::ZERO,
        };
        mesh.recompute_bounds();
        mesh.validate()?;
        Ok(mesh)
    }

    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }

    pub fn triangle_count(&self) -> usize {
        self.indices.len() / 3
    }

    /// Sets `bounds` from `positions`; call after editing positions.
    pub fn recompute_bounds(&mut self) {
        self.bounds = Aabb::from_points(self.positions.iter().map(|&p| Vec3::from(p)));
    }

    /// Checks what the GPU side relies on: every stream has one entry per
    /// position, indices form whole triangles and stay in range, every number
    /// is finite, and `bounds` are the bounds of the positions.
    pub fn validate(&self) -> Result<(), MeshError> {
        self.check_structure()?;
        check_finite("positions", self.positions.iter().map(|v| v.as_slice()))?;
        check_finite("normals", self.normals.iter().map(|v| v.as_slice()))?;
        if let Some(uvs) = &self.uvs {
            check_finite("uvs", uvs.iter().map(|v| v.as_slice()))?;
        }
        if let Some(tangents) = &self.tangents {
            check_finite("tangents", tangents.iter().map(|v| v.as_slice()))?;
        }
        if let Some(uvs1) = &self.uvs1 {
            check_finite("uvs1", uvs1.iter().map(|v| v.as_slice()))?;
        }
        if let Some(colors) = &self.colors {
            check_finite("colors", colors.iter().map(|v| v.as_slice()))?;
        }
        if !self.bounds.is_finite() {
            return Err(MeshError::NotFinite {
                stream: "bounds",
                at: 0,
            });
        }
        let actual = Aabb::from_points(self.positions.iter().map(|&p| Vec3::from(p)));
        if actual != self.bounds {
            return Err(MeshError::StaleBounds {
                min: self.bounds.min,
                max: self.bounds.max,
            });
        }
        Ok(())
    }

    /// Stream lengths and indices: what must hold before any stream is
    /// indexed through `indices`.
    fn check_structure(&self) -> Result<(), MeshError> {
        let vertices = self.positions.len();
        let lengths = [
            ("normals", Some(self.normals.len())),
            ("uvs", self.uvs.as_ref().map(Vec::len)),
            ("tangents", self.tangents.as_ref().map(Vec::len)),
            ("uvs1", self.uvs1.as_ref().map(Vec::len)),
            ("colors", self.colors.as_ref().map(Vec::len)),
        ];
        for (stream, len) in lengths {
            if let Some(len) = len
                && len != vertices
            {
                return Err(MeshError::StreamLength {
                    stream,
                    len,
                    vertices,
                });
            }
        }
        if !self.indices.len().is_multiple_of(3) {
            return Err(MeshError::IndexCount {
                count: self.indices.len(),
            });
        }
        if let Some((at, &index)) = self
            .indices
            .iter()
            .enumerate()
            .find(|&(_, &i)| i as usize >= vertices)
        {
            return Err(MeshError::IndexOutOfRange {
                at,
                index,
                vertices,
            });
        }
        Ok(())
    }

    /// Replaces `tangents` with MikkTSpace tangents from the positions,
    /// normals and UVs. Fails without UVs, or when the streams do not fit
    /// together (see [`MeshData::validate`]). Vertices MikkTSpace leaves
    /// without a tangent (degenerate triangles) get any unit vector
    /// perpendicular to their normal, so the result is never NaN.
    pub fn generate_tangents(&mut self) -> Result<(), MeshError> {
        let Some(uvs) = &self.uvs else {
            return Err(MeshError::NoUvs);
        };
        self.check_structure()?;
        // MikkTSpace sorts and welds by value; keep NaN out of it.
        check_finite("positions", self.positions.iter().map(|v| v.as_slice()))?;
        check_finite("normals", self.normals.iter().map(|v| v.as_slice()))?;
        check_finite("uvs", uvs.iter().map(|v| v.as_slice()))?;
        self.tangents = Some(generate::mikktspace_tangents(
            &self.positions,
            &self.normals,
            uvs,
            &self.indices,
        ));
        Ok(())
    }
}

fn check_finite<'a>(
    stream: &'static str,
    values: impl Iterator<Item = &'a [f32]>,
) -> Result<(), MeshError> {
    for (at, value) in values.enumerate() {
        if !value.iter().all(|x| x.is_finite()) {
            return Err(MeshError::NotFinite { stream, at });
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn quad() -> MeshData {
        MeshData::new(
            vec![
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [1.0, 1.0, 0.0],
                [0.0, 1.0, 0.0],
            ],
            vec![[0.0, 0.0, 1.0]; 4],
            Some(vec![[0.0, 1.0], [1.0, 1.0], [1.0, 0.0], [0.0, 0.0]]),
            None,
            vec![0, 1, 2, 0, 2, 3],
        )
        .unwrap()
    }

    #[test]
    fn a_transformed_box_is_the_box_of_its_transformed_corners_bit_for_bit() {
        // Rotations, negative and uneven scales, shears and far translations:
        // whatever the affine transform, the same bits as the eight corners.
        let mut seed = 0x9E37_79B9_u32;
        let mut next = move || {
            seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (seed >> 8) as f32 / (1 << 24) as f32 * 2.0 - 1.0
        };
        for _ in 0..2_000 {
            let mut m = Mat4::from_scale_rotation_translation(
                Vec3::new(next() * 3.0, next() * 0.01, next() * 300.0),
                glam::Quat::from_euler(glam::EulerRot::XYZ, next() * 4.0, next() * 4.0, next()),
                Vec3::new(next() * 1e4, next(), next() * 1e-3),
            );
            m.y_axis.x += next();
            let a = Vec3::new(next(), next() * 50.0, next() * 1e-4);
            let b = a + Vec3::new(next().abs(), next().abs() * 7.0, next().abs() * 1e5);
            let aabb = Aabb { min: a, max: b };
            let corners = Aabb::from_points(aabb.corners().map(|c| m.transform_point3(c)));
            assert_eq!(aabb.transformed(m), corners, "{m:?} {aabb:?}");
        }
    }

    #[test]
    fn new_computes_bounds_and_counts() {
        let m = quad();
        assert_eq!(m.vertex_count(), 4);
        assert_eq!(m.triangle_count(), 2);
        assert_eq!(m.bounds.min, Vec3::ZERO);
        assert_eq!(m.bounds.max, Vec3::new(1.0, 1.0, 0.0));
    }

    #[test]
    fn validate_names_each_problem() {
        let mut m = quad();
        m.normals.pop();
        assert_eq!(
            m.validate(),
            Err(MeshError::StreamLength {
                stream: "normals",
                len: 3,
                vertices: 4
            })
        );

        let mut m = quad();
        m.indices.push(0);
        assert_eq!(m.validate(), Err(MeshError::IndexCount { count: 7 }));

        let mut m = quad();
        m.indices[4] = 9;
        assert_eq!(
            m.validate(),
            Err(MeshError::IndexOutOfRange {
                at: 4,
                index: 9,
                vertices: 4
            })
        );

        let mut m = quad();
        m.uvs.as_mut().unwrap()[2][1] = f32::NAN;
        assert_eq!(
            m.validate(),
            Err(MeshError::NotFinite {
                stream: "uvs",
                at: 2
            })
        );

        let mut m = quad();
        m.positions[0][0] = -1.0;
        assert!(matches!(m.validate(), Err(MeshError::StaleBounds { .. })));
        m.recompute_bounds();
        assert_eq!(m.validate(), Ok(()));
        assert!(
            MeshError::IndexCount { count: 7 }
                .to_string()
                .contains("multiple of 3")
        );
    }

    #[test]
    fn generate_tangents_needs_uvs_and_a_sound_mesh() {
        let mut m = quad();
        m.uvs = None;
        assert_eq!(m.generate_tangents(), Err(MeshError::NoUvs));
        assert!(MeshError::NoUvs.to_string().contains("texture coordinates"));

        let mut m = quad();
        m.indices[0] = 100;
        assert!(matches!(
            m.generate_tangents(),
            Err(MeshError::IndexOutOfRange { .. })
        ));

        let mut m = quad();
        m.generate_tangents().unwrap();
        // u grows along +x, v grows along -y (image rows go down): tangent
        // +x, and the bitangent cross(n, t) * w points to -v, i.e. +y.
        for t in m.tangents.as_ref().unwrap() {
            assert!(
                (Vec3::new(t[0], t[1], t[2]) - Vec3::X).length() < 1e-5,
                "{t:?}"
            );
            assert_eq!(t[3], 1.0);
        }
        assert_eq!(m.validate(), Ok(()));
    }

    #[test]
    fn aabb_helpers() {
        assert_eq!(Aabb::from_points([]), Aabb::ZERO);
        let b = Aabb::from_points([Vec3::new(-1.0, 0.0, 2.0), Vec3::new(1.0, 3.0, -2.0)]);
        assert_eq!(b.center(), Vec3::new(0.0, 1.5, 0.0));
        assert_eq!(b.size(), Vec3::new(2.0, 3.0, 4.0));
        let moved = b.transformed(Mat4::from_translation(Vec3::X));
        assert_eq!(moved.min, Vec3::new(0.0, 0.0, -2.0));
        let u = b.union(Aabb {
            min: Vec3::splat(5.0),
            max: Vec3::splat(6.0),
        });
        assert_eq!(u.max, Vec3::splat(6.0));
    }
}
