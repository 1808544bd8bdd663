//! Generated meshes: box, UV sphere, grid (and plane), cylinder, torus.
//!
//! Each is a pure function of a params struct whose `Default` is the vvvv
//! unit: a box of size 1, a sphere of radius 0.5, a 1 x 1 grid, all centred
//! at the origin. Every mesh has unit outward normals, UVs in [0, 1] laid so
//! that a texture reads upright from outside (u to the right, v down, as in
//! glTF), MikkTSpace tangents, and counter-clockwise front faces.
//!
//! Parameters are clamped, never rejected, so a node feeding them can not
//! make a broken mesh: a negative size or radius counts by its absolute
//! value, a non-finite one is 0, and lengths are capped at [`MAX_EXTENT`];
//! segment counts are raised to the fewest that make a closed shape and
//! capped at [`MAX_SEGMENTS`]. Zero sizes give a collapsed but valid mesh.

use std::f32::consts::{PI, TAU};

use glam::{Vec2, Vec3};

use super::{Aabb, MeshData, generate};

/// The largest length a generator uses; larger ones are clamped to it, so
/// squared lengths inside MikkTSpace stay finite.
pub const MAX_EXTENT: f32 = 1.0e15;

/// The most segments along any one direction of a generated mesh (a
/// 1024 x 1024 grid is about a million vertices).
pub const MAX_SEGMENTS: u32 = 1024;

/// A length as the generators use it: absolute, finite, at most [`MAX_EXTENT`].
fn extent(x: f32) -> f32 {
    if x.is_finite() {
        x.abs().min(MAX_EXTENT)
    } else {
        0.0
    }
}

fn segments(n: u32, min: u32) -> u32 {
    n.clamp(min, MAX_SEGMENTS)
}

/// A box centred at the origin; each face is its own `segments` x `segments`
/// grid with the face's normal (flat shading, 24 vertices at 1 segment).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BoxParams {
    pub size: Vec3,
    pub segments: u32,
}

impl Default for BoxParams {
    fn default() -> Self {
        Self {
            size: Vec3::ONE,
            segments: 1,
        }
    }
}

/// A UV sphere centred at the origin: `sectors` around Y, `stacks` from pole
/// to pole. The poles get one vertex per sector, at the middle of the
/// sector's u, so no triangle is degenerate in position or UV.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SphereParams {
    pub radius: f32,
    pub sectors: u32,
    pub stacks: u32,
}

impl Default for SphereParams {
    fn default() -> Self {
        Self {
            radius: 0.5,
            sectors: 32,
            stacks: 16,
        }
    }
}

/// A plane in XZ facing +Y, centred at the origin, `resolution_x` x
/// `resolution_y` cells (along X and Z). u follows +X, v follows +Z.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GridParams {
    pub size: Vec2,
    pub resolution_x: u32,
    pub resolution_y: u32,
}

impl Default for GridParams {
    fn default() -> Self {
        Self {
            size: Vec2::ONE,
            resolution_x: 10,
            resolution_y: 10,
        }
    }
}

/// A cylinder along Y centred at the origin, smooth sides, optional flat caps.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CylinderParams {
    pub radius: f32,
    pub height: f32,
    pub sectors: u32,
    pub caps: bool,
}

impl Default for CylinderParams {
    fn default() -> Self {
        Self {
            radius: 0.5,
            height: 1.0,
            sectors: 32,
            caps: true,
        }
    }
}

/// A torus around Y in the XZ plane. u runs along the ring
/// (`major_segments`), v around the tube (`minor_segments`). A minor radius
/// larger than the major one gives a self-intersecting (spindle) torus,
/// still with finite normals.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TorusParams {
    pub major_radius: f32,
    pub minor_radius: f32,
    pub major_segments: u32,
    pub minor_segments: u32,
}

impl Default for TorusParams {
    fn default() -> Self {
        Self {
            major_radius: 0.5,
            minor_radius: 0.15,
            major_segments: 32,
            minor_segments: 16,
        }
    }
}

/// Vertex streams being filled, turned into a [`MeshData`] with tangents at the end.
#[derive(Default)]
struct Builder {
    positions: Vec<[f32; 3]>,
    normals: Vec<[f32; 3]>,
    uvs: Vec<[f32; 2]>,
    indices: Vec<u32>,
}

impl Builder {
    fn vertex(&mut self, position: Vec3, normal: Vec3, uv: Vec2) -> u32 {
        let index = self.positions.len() as u32;
        self.positions.push(position.to_array());
        self.normals.push(normal.to_array());
        self.uvs.push(uv.to_array());
        index
    }

    /// A (nu + 1) x (nv + 1) sheet of vertices from `surface(u, v) ->
    /// (position, normal)`, with UV = (u, v). The surface must be laid out
    /// like an upright image seen from the front: u to the right, v down,
    /// which makes `dP/du x dP/dv` point away from the viewer, against the
    /// normal; the triangles below are counter-clockwise for that layout.
    fn sheet(&mut self, nu: u32, nv: u32, surface: impl Fn(f32, f32) -> (Vec3, Vec3)) {
        let base = self.positions.len() as u32;
        for j in 0..=nv {
            for i in 0..=nu {
                let (u, v) = (i as f32 / nu as f32, j as f32 / nv as f32);
                let (p, n) = surface(u, v);
                self.vertex(p, n, Vec2::new(u, v));
            }
        }
        let at = |i: u32, j: u32| base + j * (nu + 1) + i;
        for j in 0..nv {
            for i in 0..nu {
                let (a, b, c, d) = (at(i, j), at(i, j + 1), at(i + 1, j + 1), at(i + 1, j));
                self.indices.extend([a, b, c, a, c, d]);
            }
        }
    }

    fn finish(self) -> MeshData {
        let tangents =
            generate::mikktspace_tangents(&self.positions, &self.normals, &self.uvs, &self.indices);
        let bounds = Aabb::from_points(self.positions.iter().map(|&p| Vec3::from(p)));
        MeshData {
            positions: self.positions,
            normals: self.normals,
            uvs: Some(self.uvs),
            tangents: Some(tangents),
            uvs1: None,
            colors: None,
            indices: self.indices,
            bounds,
        }
    }
}

/// The outward direction at angle `phi` around Y: -Z at 0, then turning
/// counter-clockwise seen from above (-X, +Z, +X), so that on any side seen
/// from outside a growing angle moves to the right and the u seam is at the back.
fn around_y(phi: f32) -> Vec3 {
    Vec3::new(-phi.sin(), 0.0, -phi.cos())
}

/// A box; see [`BoxParams`].
pub fn box_mesh(params: BoxParams) -> MeshData {
    let size = params.size.to_array().map(extent);
    let size = Vec3::from(size);
    let n = segments(params.segments, 1);
    // (normal, right): right x normal is "down" on the face, so u/v read
    // upright from outside; the top reads upright with -Z away from the viewer.
    let faces = [
        (Vec3::Z, Vec3::X),
        (Vec3::NEG_Z, Vec3::NEG_X),
        (Vec3::X, Vec3::NEG_Z),
        (Vec3::NEG_X, Vec3::Z),
        (Vec3::Y, Vec3::X),
        (Vec3::NEG_Y, Vec3::X),
    ];
    let mut b = Builder::default();
    for (normal, right) in faces {
        let down = right.cross(normal);
        b.sheet(n, n, |u, v| {
            let p = normal * 0.5 + right * (u - 0.5) + down * (v - 0.5);
            (p * size, normal)
        });
    }
    b.finish()
}

/// A UV sphere; see [`SphereParams`].
pub fn sphere(params: SphereParams) -> MeshData {
    let r = extent(params.radius);
    let sectors = segments(params.sectors, 3);
    let stacks = segments(params.stacks, 2);
    let mut b = Builder::default();
    let pole = |b: &mut Builder, y: f32, v: f32| {
        (0..sectors)
            .map(|i| {
                let u = (i as f32 + 0.5) / sectors as f32;
                b.vertex(
                    Vec3::new(0.0, y * r, 0.0),
                    Vec3::new(0.0, y, 0.0),
                    Vec2::new(u, v),
                )
            })
            .collect::<Vec<_>>()
    };
    let north = pole(&mut b, 1.0, 0.0);
    // Rings 1..stacks, each with a seam vertex at both u = 0 and u = 1.
    let ring_start = b.positions.len() as u32;
    for j in 1..stacks {
        let v = j as f32 / stacks as f32;
        let theta = v * PI;
        for i in 0..=sectors {
            let u = i as f32 / sectors as f32;
            let n = around_y(u * TAU) * theta.sin() + Vec3::Y * theta.cos();
            b.vertex(n * r, n, Vec2::new(u, v));
        }
    }
    let south = pole(&mut b, -1.0, 1.0);
    let ring = |j: u32, i: u32| ring_start + (j - 1) * (sectors + 1) + i;
    for i in 0..sectors {
        b.indices
            .extend([north[i as usize], ring(1, i), ring(1, i + 1)]);
        for j in 1..stacks - 1 {
            let (a, bb, c, d) = (
                ring(j, i),
                ring(j + 1, i),
                ring(j + 1, i + 1),
                ring(j, i + 1),
            );
            b.indices.extend([a, bb, c, a, c, d]);
        }
        let last = stacks - 1;
        b.indices
            .extend([ring(last, i), south[i as usize], ring(last, i + 1)]);
    }
    b.finish()
}

/// A grid in XZ facing +Y; see [`GridParams`].
pub fn grid(params: GridParams) -> MeshData {
    let (sx, sz) = (extent(params.size.x), extent(params.size.y));
    let mut b = Builder::default();
    b.sheet(
        segments(params.resolution_x, 1),
        segments(params.resolution_y, 1),
        |u, v| (Vec3::new((u - 0.5) * sx, 0.0, (v - 0.5) * sz), Vec3::Y),
    );
    b.finish()
}

/// A 1 x 1 plane in XZ facing +Y: a grid of one cell.
pub fn plane() -> MeshData {
    grid(GridParams {
        resolution_x: 1,
        resolution_y: 1,
        ..GridParams::default()
    })
}

/// A cylinder along Y; see [`CylinderParams`].
pub fn cylinder(params: CylinderParams) -> MeshData {
    let r = extent(params.radius);
    let h = extent(params.height);
    let sectors = segments(params.sectors, 3);
    let mut b = Builder::default();
    b.sheet(sectors, 1, |u, v| {
        let n = around_y(u * TAU);
        (n * r + Vec3::Y * (0.5 - v) * h, n)
    });
    if params.caps {
        for y in [1.0f32, -1.0] {
            let normal = Vec3::Y * y;
            // Planar UVs as seen from outside: from above, -Z is up; from
            // below, +Z is up.
            let uv = |d: Vec3| Vec2::new(0.5 + 0.5 * d.x, 0.5 + 0.5 * d.z * y);
            let center = b.vertex(normal * h * 0.5, normal, Vec2::splat(0.5));
            let rim: Vec<u32> = (0..sectors)
                .map(|i| {
                    let d = around_y(i as f32 / sectors as f32 * TAU);
                    b.vertex(d * r + normal * h * 0.5, normal, uv(d))
                })
                .collect();
            for i in 0..sectors as usize {
                let (p, q) = (rim[i], rim[(i + 1) % rim.len()]);
                // around_y turns counter-clockwise seen from above.
                b.indices.extend(if y > 0.0 {
                    [center, p, q]
                } else {
                    [center, q, p]
                });
            }
        }
    }
    b.finish()
}

/// A torus around Y; see [`TorusParams`].
pub fn torus(params: TorusParams) -> MeshData {
    let big = extent(params.major_radius);
    let small = extent(params.minor_radius);
    let mut b = Builder::default();
    b.sheet(
        segments(params.major_segments, 3),
        segments(params.minor_segments, 3),
        |u, v| {
            let out = around_y(u * TAU);
            // v = 0 on top of the tube, then over the outside and down.
            let psi = PI * 0.5 - v * TAU;
            let n = out * psi.cos() + Vec3::Y * psi.sin();
            (out * big + n * small, n)
        },
    );
    b.finish()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every property the module doc promises, for one mesh.
    fn check(name: &str, m: &MeshData) {
        assert_eq!(m.validate(), Ok(()), "{name}");
        let uvs = m.uvs.as_ref().expect("uvs");
        let tangents = m.tangents.as_ref().expect("tangents");
        for (v, ((n, t), uv)) in m.normals.iter().zip(tangents).zip(uvs).enumerate() {
            let n = Vec3::from(*n);
            let t3 = Vec3::new(t[0], t[1], t[2]);
            assert!((n.length() - 1.0).abs() < 1e-5, "{name}: normal {v} {n}");
            assert!(
                (t3.length() - 1.0).abs() < 1e-4,
                "{name}: tangent {v} {t:?}"
            );
            assert!(t3.dot(n).abs() < 1e-4, "{name}: tangent {v} not orthogonal");
            assert!(t[3] == 1.0 || t[3] == -1.0, "{name}: handedness {v}");
            assert!(uv.iter().all(|c| (0.0..=1.0).contains(c)), "{name}: uv {v}");
        }
        let p = |i: u32| Vec3::from(m.positions[i as usize]);
        let scale = m.bounds.size().length().max(1e-6);
        for tri in m.indices.chunks_exact(3) {
            let cross = (p(tri[1]) - p(tri[0])).cross(p(tri[2]) - p(tri[0]));
            if cross.length() < 1e-6 * scale * scale {
                continue;
            }
            let normal: Vec3 = tri.iter().map(|&i| Vec3::from(m.normals[i as usize])).sum();
            assert!(
                cross.dot(normal) > 0.0,
                "{name}: triangle {tri:?} winds clockwise"
            );
        }
    }

    /// The tangent frame agrees with the UV layout: the tangent points along
    /// +u and the bitangent cross(n, t) * w along -v, on every triangle with
    /// area in both position and UV.
    fn check_frames(name: &str, m: &MeshData) {
        let (uvs, tangents) = (
            m.uvs.as_ref().expect("uvs"),
            m.tangents.as_ref().expect("t"),
        );
        for tri in m.indices.chunks_exact(3) {
            let [a, b, c] = [0, 1, 2].map(|k| tri[k] as usize);
            let (p0, p1, p2) = (m.positions[a], m.positions[b], m.positions[c]);
            let (e1, e2) = (
                Vec3::from(p1) - Vec3::from(p0),
                Vec3::from(p2) - Vec3::from(p0),
            );
            let (d1, d2) = (
                Vec2::from(uvs[b]) - Vec2::from(uvs[a]),
                Vec2::from(uvs[c]) - Vec2::from(uvs[a]),
            );
            let det = d1.x * d2.y - d2.x * d1.y;
            if det.abs() < 1e-9 || e1.cross(e2).length() < 1e-9 {
                continue;
            }
            let dpdu = (e1 * d2.y - e2 * d1.y) / det;
            let dpdv = (e2 * d1.x - e1 * d2.x) / det;
            for &v in &[a, b, c] {
                let t = tangents[v];
                let t3 = Vec3::new(t[0], t[1], t[2]);
                let bitangent = Vec3::from(m.normals[v]).cross(t3) * t[3];
                assert!(t3.dot(dpdu) > 0.0, "{name}: tangent against +u at {v}");
                assert!(bitangent.dot(dpdv) < 0.0, "{name}: bitangent not -v at {v}");
            }
        }
    }

    fn assert_bounds(name: &str, m: &MeshData, half: Vec3) {
        assert!(
            (m.bounds.min + half).abs().max_element() < 1e-5,
            "{name}: {:?}",
            m.bounds
        );
        assert!(
            (m.bounds.max - half).abs().max_element() < 1e-5,
            "{name}: {:?}",
            m.bounds
        );
    }

    #[test]
    fn box_defaults() {
        let m = box_mesh(BoxParams::default());
        check("box", &m);
        check_frames("box", &m);
        assert_eq!(m.vertex_count(), 24);
        assert_eq!(m.triangle_count(), 12);
        assert_bounds("box", &m, Vec3::splat(0.5));
        let m = box_mesh(BoxParams {
            size: Vec3::new(2.0, -4.0, 6.0),
            segments: 3,
        });
        check("box 3", &m);
        assert_eq!(m.vertex_count(), 6 * 16);
        assert_bounds("box 3", &m, Vec3::new(1.0, 2.0, 3.0));
    }

    #[test]
    fn sphere_benchmark_size() {
        let m = sphere(SphereParams {
            radius: 2.0,
            sectors: 32,
            stacks: 16,
        });
        check("sphere", &m);
        check_frames("sphere", &m);
        assert_eq!(m.triangle_count(), 2 * 32 * 15);
        assert_bounds("sphere", &m, Vec3::splat(2.0));
        for p in &m.positions {
            assert!((Vec3::from(*p).length() - 2.0).abs() < 1e-5);
        }
        // The poles: one vertex per sector, with a real tangent in the XZ plane.
        let tangents = m.tangents.as_ref().unwrap();
        for (p, t) in m.positions.iter().zip(tangents) {
            if p[1].abs() == 2.0 {
                assert!(t[1].abs() < 1e-5, "pole tangent {t:?}");
            }
        }
        check("sphere default", &sphere(SphereParams::default()));
    }

    #[test]
    fn grid_and_plane() {
        let m = grid(GridParams {
            size: Vec2::new(4.0, 2.0),
            resolution_x: 4,
            resolution_y: 2,
        });
        check("grid", &m);
        check_frames("grid", &m);
        assert_eq!(m.vertex_count(), 15);
        assert_eq!(m.triangle_count(), 16);
        assert_bounds("grid", &m, Vec3::new(2.0, 0.0, 1.0));
        assert!(m.normals.iter().all(|&n| n == [0.0, 1.0, 0.0]));
        for t in m.tangents.as_ref().unwrap() {
            assert!((Vec3::new(t[0], t[1], t[2]) - Vec3::X).length() < 1e-5);
            assert_eq!(t[3], 1.0, "grid tangents are +X, right-handed");
        }
        let p = plane();
        check("plane", &p);
        assert_eq!((p.vertex_count(), p.triangle_count()), (4, 2));
        check("grid default", &grid(GridParams::default()));
    }

    #[test]
    fn cylinder_with_and_without_caps() {
        let m = cylinder(CylinderParams::default());
        check("cylinder", &m);
        check_frames("cylinder", &m);
        assert_bounds("cylinder", &m, Vec3::new(0.5, 0.5, 0.5));
        let open = cylinder(CylinderParams {
            caps: false,
            ..CylinderParams::default()
        });
        check("open cylinder", &open);
        assert_eq!(open.triangle_count(), 64);
        assert_eq!(m.triangle_count(), 64 + 64);
    }

    #[test]
    fn torus_defaults() {
        let m = torus(TorusParams::default());
        check("torus", &m);
        check_frames("torus", &m);
        assert_bounds("torus", &m, Vec3::new(0.65, 0.15, 0.65));
    }

    #[test]
    fn absurd_parameters_are_clamped() {
        for x in [
            0.0,
            -3.0,
            f32::NAN,
            f32::INFINITY,
            f32::NEG_INFINITY,
            1e30,
            -1e-30,
        ] {
            let v = Vec3::splat(x);
            let meshes = [
                box_mesh(BoxParams {
                    size: v,
                    segments: 0,
                }),
                sphere(SphereParams {
                    radius: x,
                    sectors: 0,
                    stacks: 0,
                }),
                sphere(SphereParams {
                    radius: x,
                    sectors: 1,
                    stacks: 1,
                }),
                grid(GridParams {
                    size: Vec2::splat(x),
                    resolution_x: 0,
                    resolution_y: 0,
                }),
                cylinder(CylinderParams {
                    radius: x,
                    height: x,
                    sectors: 0,
                    caps: true,
                }),
                torus(TorusParams {
                    major_radius: x,
                    minor_radius: -x,
                    major_segments: 0,
                    minor_segments: 1,
                }),
            ];
            for m in &meshes {
                assert_eq!(m.validate(), Ok(()), "size {x}");
                assert!(m.triangle_count() > 0);
                for t in m.tangents.as_ref().unwrap() {
                    assert!((Vec3::new(t[0], t[1], t[2]).length() - 1.0).abs() < 1e-4);
                }
            }
        }
        let huge = grid(GridParams {
            size: Vec2::ONE,
            resolution_x: u32::MAX,
            resolution_y: 1,
        });
        assert_eq!(huge.triangle_count(), 2 * MAX_SEGMENTS as usize);
        // A negative radius is its absolute value.
        assert_eq!(
            sphere(SphereParams {
                radius: -1.0,
                ..SphereParams::default()
            }),
            sphere(SphereParams {
                radius: 1.0,
                ..SphereParams::default()
            })
        );
    }
}
