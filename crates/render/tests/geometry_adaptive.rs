//! The geometry passes whose output depends on their input's shape, on a
//! real (software) GPU: adaptive Tessellate (closed stays closed, every
//! triangle within Max Area, area and UVs kept), Displace by a known texture
//! (heights and recomputed normals), Decimate (ratio, borders, seams), and
//! Bezier splines through their anchors.

use crate::common;

use glam::{Mat2, Vec2, Vec3, Vec4};
use spreadlight_render::geometry::analytic::icosahedron;
use spreadlight_render::geometry::tessellate::segment_length;
use spreadlight_render::geometry::{
    Curve, DecimateParams, DisplaceParams, Sweep, curve_point, decimate, displace, read_mesh,
    spline, tessellate,
};
use spreadlight_render::mesh::MeshData;
use spreadlight_render::mesh::primitives::{BoxParams, GridParams, box_mesh, grid};
use spreadlight_render::mesh_arena::GpuVertex;
use spreadlight_render::renderer::test_renderer;
use spreadlight_render::texture::GpuTexture;

use common::{edge_balance, open_edges};

fn position(v: &GpuVertex) -> Vec3 {
    Vec3::from_slice(&v.position_u)
}

fn area(vertices: &[GpuVertex], t: &[u32]) -> f32 {
    let p = |k: usize| position(&vertices[t[k] as usize]);
    0.5 * (p(1) - p(0)).cross(p(2) - p(0)).length()
}

fn total_area(vertices: &[GpuVertex], indices: &[u32]) -> f32 {
    indices.chunks(3).map(|t| area(vertices, t)).sum()
}

/// A unit icosahedron with one vertex pulled out, so triangles of many sizes meet.
fn lumpy() -> MeshData {
    let mut m = icosahedron();
    m.positions[0] = (Vec3::from(m.positions[0]) * 2.5).into();
    m.recompute_bounds();
    m
}

#[test]
fn tessellate_keeps_closed_meshes_closed_and_every_triangle_within_max_area() {
    let renderer = test_renderer();
    let boxy = box_mesh(BoxParams {
        size: Vec3::new(4.0, 1.0, 0.5),
        segments: 1,
    });
    for (name, data, max_area) in [
        ("box (split vertices at its edges)", boxy, 0.05f32),
        ("lumpy icosahedron", lumpy(), 0.02),
        ("lumpy icosahedron, coarse", lumpy(), 0.2),
    ] {
        let input = renderer.meshes.upload(&renderer.gpu, &data).unwrap();
        let (v_in, i_in) = read_mesh(&renderer, &input).unwrap();
        assert_eq!(open_edges(&v_in, &i_in), 0, "{name}: the input is closed");
        let out = tessellate(&renderer, &input, None, max_area, 64).expect("tessellate");
        let (v, i) = read_mesh(&renderer, &out).unwrap();
        assert!(
            i.len() > i_in.len() * 4,
            "{name}: it split ({} triangles)",
            i.len() / 3
        );
        assert_eq!(open_edges(&v, &i), 0, "{name}: no cracks");
        let largest = i.chunks(3).map(|t| area(&v, t)).fold(0.0f32, f32::max);
        assert!(
            largest <= max_area * 1.0001,
            "{name}: a triangle of {largest} > {max_area}"
        );
        // Every edge of a real triangle is at most the segment length (plus the snap's slack on one side).
        let (a_in, a_out) = (total_area(&v_in, &i_in), total_area(&v, &i));
        assert!(
            (a_out - a_in).abs() < a_in * 1e-4,
            "{name}: area {a_in} became {a_out}"
        );
        for t in i.chunks(3) {
            if area(&v, t) < 1e-9 {
                continue;
            }
            let p = |k: usize| position(&v[t[k] as usize]);
            let face = (p(1) - p(0)).cross(p(2) - p(0)).normalize();
            for &k in t {
                let n = Vec3::from_slice(&v[k as usize].normal_v);
                assert!((n.length() - 1.0).abs() < 1e-4, "{name}: unit normals");
                // No triangle turned over (the box's normals are its faces').
                assert!(face.dot(n) > 0.0, "{name}: triangle {t:?} flipped");
                let tangent = Vec3::from_slice(&v[k as usize].tangent);
                assert!(tangent.dot(n).abs() < 1e-4);
            }
        }
        assert!(
            v.iter()
                .all(|x| x.previous_position[..3] == x.position_u[..3])
        );
    }
}

#[test]
fn tessellate_leaves_small_triangles_alone_and_interpolates_uvs() {
    let renderer = test_renderer();
    let data = grid(GridParams {
        size: Vec2::splat(2.0),
        resolution_x: 4,
        resolution_y: 4,
    });
    let input = renderer.meshes.upload(&renderer.gpu, &data).unwrap();
    // Triangles of 0.125 with edges of 0.5 and 0.71: a Max Area of 0.26 cuts no edge.
    assert!(segment_length(0.26) > 0.5f32.hypot(0.5));
    let same = tessellate(&renderer, &input, None, 0.26, 64).unwrap();
    assert_eq!(same.indices.len(), data.indices.len());
    let fine = tessellate(&renderer, &input, None, 0.01, 64).unwrap();
    let (v, i) = read_mesh(&renderer, &fine).unwrap();
    assert!(i.len() / 3 >= 32 * 13, "{} triangles", i.len() / 3);
    // The grid's UVs are an affine map of x and z: every new vertex must lie on it.
    let p = |k: usize| Vec2::new(data.positions[k][0], data.positions[k][2]);
    let uv = |k: usize| Vec2::from(data.uvs.as_ref().unwrap()[k]);
    let (o, a, b) = (0, 1, data.positions.len() - 1);
    let basis = Mat2::from_cols(p(a) - p(o), p(b) - p(o));
    let uvs = Mat2::from_cols(uv(a) - uv(o), uv(b) - uv(o));
    let map = uvs * basis.inverse();
    for x in &v {
        let expected = uv(o) + map * (Vec2::new(x.position_u[0], x.position_u[2]) - p(o));
        let got = Vec2::new(x.position_u[3], x.normal_v[3]);
        assert!(
            (got - expected).length() < 1e-5,
            "uv {got} where {expected}"
        );
    }
    // The level cap wins over the area.
    let capped = tessellate(&renderer, &input, None, 1e-6, 2).unwrap();
    assert_eq!(capped.indices.len(), data.indices.len() * 4);
    assert!(tessellate(&renderer, &input, None, 0.0, 4).is_err());
    assert!(tessellate(&renderer, &input, None, f32::NAN, 4).is_err());
}

/// A width x 1 texture whose red channel rises from 0 to 255 left to right.
fn ramp(renderer: &spreadlight_render::Renderer, width: u32) -> GpuTexture {
    let pixels: Vec<u8> = (0..width)
        .flat_map(|x| [(x * 255 / (width - 1)) as u8, 0, 0, 255])
        .collect();
    GpuTexture::from_rgba8(&renderer.gpu, width, 1, &pixels, false, "ramp")
}

#[test]
fn displace_moves_along_normals_by_the_texture_and_recomputes_normals() {
    let renderer = test_renderer();
    let data = grid(GridParams {
        size: Vec2::splat(2.0),
        resolution_x: 16,
        resolution_y: 16,
    });
    let input = renderer.meshes.upload(&renderer.gpu, &data).unwrap();
    let texture = ramp(&renderer, 256);
    let params = DisplaceParams {
        amount: 0.5,
        midlevel: 0.25,
    };
    let out = displace(&renderer, &input, None, &texture, params).expect("displace");
    let (v, i) = read_mesh(&renderer, &out).unwrap();
    assert_eq!(i, data.indices, "the topology is kept");
    // Texel x holds x / 255 at u = (x + 0.5) / 256: linear filtering gives
    // h(u) = (256 u - 0.5) / 255 between the first and last texel centres.
    let height = |u: f32| (256.0 * u - 0.5) / 255.0;
    let mut inner = Vec::new();
    for (k, x) in v.iter().enumerate() {
        let (p0, n0) = (Vec3::from(data.positions[k]), Vec3::from(data.normals[k]));
        let u = x.position_u[3];
        assert_eq!(
            [u, x.normal_v[3]],
            data.uvs.as_ref().unwrap()[k],
            "UVs kept"
        );
        if (0.05..=0.95).contains(&u) {
            let expected = p0 + n0 * (height(u) - 0.25) * 0.5;
            assert!(
                (position(x) - expected).length() < 2e-3,
                "vertex {k}: {} vs {expected}",
                position(x)
            );
            if (0.15..=0.85).contains(&u) && (0.15..=0.85).contains(&x.normal_v[3]) {
                inner.push(k);
            }
        }
    }
    assert!(inner.len() > 50);
    // Away from the ramp's ends the surface is a tilted plane: its normal
    // from three displaced vertices is every inner vertex's normal.
    let corner = |u: f32, w: f32| {
        v.iter()
            .min_by(|a, b| {
                let d = |x: &GpuVertex| {
                    (Vec2::new(x.position_u[3], x.normal_v[3]) - Vec2::new(u, w)).length()
                };
                d(a).total_cmp(&d(b))
            })
            .map(position)
            .unwrap()
    };
    let (a, b, c) = (corner(0.25, 0.25), corner(0.75, 0.25), corner(0.25, 0.75));
    let mut plane = (b - a).cross(c - a).normalize();
    if plane.dot(Vec3::from(data.normals[0])) < 0.0 {
        plane = -plane;
    }
    assert!(
        plane.dot(Vec3::from(data.normals[0])) < 0.99,
        "the ramp tilts the plane"
    );
    for k in inner {
        let n = Vec3::from_slice(&v[k].normal_v);
        assert!(
            (n - plane).length() < 2e-3,
            "vertex {k}: normal {n}, plane {plane}"
        );
        assert!(Vec3::from_slice(&v[k].tangent).dot(n).abs() < 1e-4);
    }
    assert!(
        displace(
            &renderer,
            &input,
            None,
            &texture,
            DisplaceParams {
                amount: f32::NAN,
                midlevel: 0.0
            }
        )
        .is_err()
    );
}

#[test]
fn decimate_hits_its_ratio_keeps_borders_and_seams_and_passes_motion_through() {
    let renderer = test_renderer();
    let plane = grid(GridParams {
        size: Vec2::splat(2.0),
        resolution_x: 16,
        resolution_y: 16,
    });
    // Every vertex moved by 0.1 along x since last frame.
    let previous: Vec<[f32; 4]> = plane
        .positions
        .iter()
        .map(|p| [p[0] - 0.1, p[1], p[2], 3.0])
        .collect();
    let input = renderer
        .meshes
        .upload_with_previous(&renderer.gpu, &plane, &previous)
        .unwrap();
    let (v_in, i_in) = read_mesh(&renderer, &input).unwrap();
    let border = |v: &[GpuVertex], i: &[u32]| {
        let mut edges: Vec<_> = edge_balance(v, i)
            .into_iter()
            .filter(|(_, n)| *n != 0)
            .map(|(e, _)| e)
            .collect();
        edges.sort();
        edges
    };
    let out = decimate(
        &renderer,
        &input,
        DecimateParams {
            ratio: 0.25,
            lock_border: true,
        },
    )
    .unwrap();
    let (v, i) = read_mesh(&renderer, &out).unwrap();
    let ratio = i.len() as f32 / i_in.len() as f32;
    assert!(
        (ratio - 0.25).abs() <= 0.03,
        "kept {ratio} of the triangles"
    );
    assert_eq!(
        border(&v, &i),
        border(&v_in, &i_in),
        "every border edge kept"
    );
    assert!(
        (total_area(&v, &i) - total_area(&v_in, &i_in)).abs() < 1e-4,
        "a flat grid keeps its area"
    );
    for x in &v {
        assert_eq!(
            x.previous_position[0],
            x.position_u[0] - 0.1,
            "motion passes through"
        );
        assert_eq!(x.previous_position[3], 3.0, "geometry ids pass through");
    }
    // A box's edges are seams (split vertices): both sides collapse alike, no cracks.
    let boxy = box_mesh(BoxParams {
        size: Vec3::ONE,
        segments: 6,
    });
    let input = renderer.meshes.upload(&renderer.gpu, &boxy).unwrap();
    for target in [0.5f32, 0.2] {
        let out = decimate(
            &renderer,
            &input,
            DecimateParams {
                ratio: target,
                lock_border: false,
            },
        )
        .unwrap();
        let (v, i) = read_mesh(&renderer, &out).unwrap();
        let ratio = i.len() as f32 / boxy.indices.len() as f32;
        assert!(
            (ratio - target).abs() <= 0.03,
            "box at {target}: kept {ratio}"
        );
        assert_eq!(open_edges(&v, &i), 0, "box at {target}: closed");
    }
    assert!(
        decimate(
            &renderer,
            &input,
            DecimateParams {
                ratio: 1.5,
                lock_border: true
            }
        )
        .is_err()
    );
}

#[test]
fn bezier_tubes_pass_through_their_anchors() {
    let renderer = test_renderer();
    // Two spans: anchors 0, 3 and 6, handles between.
    let points = [
        Vec3::ZERO,
        Vec3::new(0.5, 1.0, 0.0),
        Vec3::new(1.5, 1.0, 0.0),
        Vec3::new(2.0, 0.0, 0.0),
        Vec3::new(2.5, -1.0, 0.5),
        Vec3::new(3.0, -1.0, 1.0),
        Vec3::new(3.0, 0.0, 2.0),
    ];
    let radii = [0.1, 0.3, 0.3, 0.2, 0.5, 0.5, 0.15];
    let (segments, sides) = (6usize, 8usize);
    let tube = spline(
        &renderer,
        &points,
        &radii,
        Curve::Bezier,
        segments as u32,
        Sweep::Tube {
            sides: sides as u32,
        },
        None,
    )
    .expect("tube");
    let (v, _) = read_mesh(&renderer, &tube).unwrap();
    let rings = 2 * segments + 1;
    assert_eq!(v.len(), rings * (sides + 1));
    let controls: Vec<Vec4> = points.iter().zip(radii).map(|(p, r)| p.extend(r)).collect();
    for ring in 0..rings {
        let centre = v[ring * (sides + 1)..][..sides]
            .iter()
            .map(position)
            .sum::<Vec3>()
            / sides as f32;
        let (on_curve, _) = curve_point(&controls, Curve::Bezier, ring as f32 / segments as f32);
        assert!(
            (centre - on_curve.truncate()).length() < 1e-4,
            "ring {ring} on the CPU's curve"
        );
    }
    for (span_end, anchor) in [(0usize, 0usize), (1, 3), (2, 6)] {
        let ring = &v[span_end * segments * (sides + 1)..][..sides];
        let centre = ring.iter().map(position).sum::<Vec3>() / sides as f32;
        assert!(
            (centre - points[anchor]).length() < 1e-5,
            "through anchor {anchor}"
        );
        for x in ring {
            let r = (position(x) - points[anchor]).length();
            assert!((r - radii[anchor]).abs() < 1e-5, "anchor {anchor}'s radius");
        }
    }
    // The curve leaves an anchor towards its handle.
    let (_, d) = curve_point(&controls, Curve::Bezier, 0.0);
    assert!(
        d.truncate()
            .normalize()
            .dot((points[1] - points[0]).normalize())
            > 0.9999
    );
    let bad = spline(
        &renderer,
        &points[..5],
        &radii,
        Curve::Bezier,
        4,
        Sweep::Ribbon,
        None,
    );
    assert!(bad.unwrap_err().to_string().contains("3 k + 1"));
}

#[test]
fn extrude_scales_each_face_by_the_texture_at_its_centroid() {
    use spreadlight_render::geometry::extrude;
    let renderer = test_renderer();
    let data = grid(GridParams {
        size: Vec2::splat(2.0),
        resolution_x: 8,
        resolution_y: 8,
    });
    let input = renderer.meshes.upload(&renderer.gpu, &data).unwrap();
    let texture = ramp(&renderer, 256);
    let out = extrude(&renderer, &input, None, &[0.4], Some(&texture)).unwrap();
    let (v, i) = read_mesh(&renderer, &out).unwrap();
    assert_eq!(i.len(), data.indices.len() * 7, "a prism a face");
    let height = |u: f32| (256.0 * u - 0.5) / 255.0;
    let uvs = data.uvs.as_ref().unwrap();
    let mut checked = 0;
    for (f, t) in data.indices.chunks(3).enumerate() {
        let centroid_u = t.iter().map(|&k| uvs[k as usize][0]).sum::<f32>() / 3.0;
        let normal = Vec3::from(data.normals[t[0] as usize]);
        for (k, &corner) in t.iter().enumerate() {
            let cap = position(&v[f * 15 + k]);
            let lift = (cap - Vec3::from(data.positions[corner as usize])).dot(normal);
            assert!(
                (lift - 0.4 * height(centroid_u)).abs() < 2e-3,
                "face {f}: lifted {lift}, centroid u {centroid_u}"
            );
            checked += 1;
        }
    }
    assert_eq!(checked, data.indices.len());
}
