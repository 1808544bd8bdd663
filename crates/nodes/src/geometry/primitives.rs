//! `Box`, `Sphere`, `Grid`, `Plane`, `Cylinder`, `Torus`: one mesh per slice
//! of their parameters. Re-made only when a parameter changes (the runtime
//! reuses unchanged nodes), so a static primitive is uploaded once.

use glam::{Vec2, Vec3};
use spreadlight_graph::spread::{map2, map3, map4};
use spreadlight_graph::{EvalContext, NodeDef, NodeError, Out, Registry, Res};
use spreadlight_render::mesh::MeshData;
use spreadlight_render::mesh::primitives::{
    BoxParams, CylinderParams, GridParams, SphereParams, TorusParams, box_mesh, cylinder, grid,
    sphere, torus,
};
use spreadlight_render::mesh_arena::GpuMesh;

use super::{CATEGORY, mesh_output};
use crate::gpu::renderer;

pub fn register(r: &mut Registry) {
    r.add(
        NodeDef::new(
            "Box",
            CATEGORY,
            "A box centred at the origin, flat-shaded faces subdivided Segments times.",
        )
        .with_pins(|p| {
            let size = p.input("Size", Vec3::ONE);
            let segments = p.input("Segments", 1i64);
            let out = mesh_output(p, "Mesh");
            move |cx| {
                let meshes = map2(cx.get(size)?, cx.get(segments)?, |size, seg| {
                    box_mesh(BoxParams {
                        size: *size,
                        segments: count(*seg),
                    })
                });
                upload(cx, out, meshes)
            }
        }),
    );
    r.add(
        NodeDef::new(
            "Sphere",
            CATEGORY,
            "A UV sphere centred at the origin: Sectors around Y, Stacks pole to pole.",
        )
        .with_pins(|p| {
            let radius = p.input("Radius", 0.5f32);
            let sectors = p.input("Sectors", 32i64);
            let stacks = p.input("Stacks", 16i64);
            let out = mesh_output(p, "Mesh");
            move |cx| {
                let meshes = map3(
                    cx.get(radius)?,
                    cx.get(sectors)?,
                    cx.get(stacks)?,
                    |r, se, st| {
                        sphere(SphereParams {
                            radius: *r,
                            sectors: count(*se),
                            stacks: count(*st),
                        })
                    },
                );
                upload(cx, out, meshes)
            }
        }),
    );
    r.add(
        NodeDef::new(
            "Grid",
            CATEGORY,
            "A plane in XZ facing +Y, centred at the origin, Resolution X by Y cells.",
        )
        .with_pins(|p| {
            let size = p.input("Size", Vec2::ONE);
            let resolution_x = p.input("Resolution X", 10i64);
            let resolution_y = p.input("Resolution Y", 10i64);
            let out = mesh_output(p, "Mesh");
            move |cx| {
                let meshes = map3(
                    cx.get(size)?,
                    cx.get(resolution_x)?,
                    cx.get(resolution_y)?,
                    |s, x, y| {
                        grid(GridParams {
                            size: *s,
                            resolution_x: count(*x),
                            resolution_y: count(*y),
                        })
                    },
                );
                upload(cx, out, meshes)
            }
        }),
    );
    r.add(
        NodeDef::new(
            "Plane",
            CATEGORY,
            "A single-quad plane in XZ facing +Y (a Grid of 1x1 cells), scaled by Size.",
        )
        .with_pins(|p| {
            let size = p.input("Size", Vec2::ONE);
            let out = mesh_output(p, "Mesh");
            move |cx| {
                let meshes = cx
                    .get(size)?
                    .iter()
                    .map(|s| {
                        grid(GridParams {
                            size: *s,
                            resolution_x: 1,
                            resolution_y: 1,
                        })
                    })
                    .collect();
                upload(cx, out, meshes)
            }
        }),
    );
    r.add(
        NodeDef::new(
            "Cylinder",
            CATEGORY,
            "A cylinder along Y centred at the origin, with optional caps.",
        )
        .with_pins(|p| {
            let radius = p.input("Radius", 0.5f32);
            let height = p.input("Height", 1.0f32);
            let sectors = p.input("Sectors", 32i64);
            let caps = p.input("Caps", true);
            let out = mesh_output(p, "Mesh");
            move |cx| {
                let meshes = map4(
                    cx.get(radius)?,
                    cx.get(height)?,
                    cx.get(sectors)?,
                    cx.get(caps)?,
                    |r, h, s, caps| {
                        cylinder(CylinderParams {
                            radius: *r,
                            height: *h,
                            sectors: count(*s),
                            caps: *caps,
                        })
                    },
                );
                upload(cx, out, meshes)
            }
        }),
    );
    r.add(
        NodeDef::new("Torus", CATEGORY, "A torus around Y in the XZ plane.").with_pins(|p| {
            let major_radius = p.input("Major Radius", 0.5f32);
            let minor_radius = p.input("Minor Radius", 0.2f32);
            let major_segments = p.input("Major Segments", 32i64);
            let minor_segments = p.input("Minor Segments", 16i64);
            let out = mesh_output(p, "Mesh");
            move |cx| {
                let meshes = map4(
                    cx.get(major_radius)?,
                    cx.get(minor_radius)?,
                    cx.get(major_segments)?,
                    cx.get(minor_segments)?,
                    |a, b, s, t| {
                        torus(TorusParams {
                            major_radius: *a,
                            minor_radius: *b,
                            major_segments: count(*s),
                            minor_segments: count(*t),
                        })
                    },
                );
                upload(cx, out, meshes)
            }
        }),
    );
}

/// Segment counts from an Int pin: the generators clamp too small values themselves.
fn count(v: i64) -> u32 {
    v.clamp(0, 4096) as u32
}

fn upload(
    cx: &mut EvalContext<'_>,
    out: Out<Res<GpuMesh>>,
    meshes: Vec<MeshData>,
) -> Result<(), NodeError> {
    let renderer = renderer(cx)?;
    let gpu_meshes = meshes
        .iter()
        .map(|m| {
            renderer
                .meshes
                .upload(&renderer.gpu, m)
                .map_err(|e| NodeError::Other(e.to_string()))
        })
        .collect::<Result<Vec<_>, _>>()?;
    cx.put_resources(out, gpu_meshes);
    Ok(())
}
