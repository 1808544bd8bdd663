//! `Box`, `Sphere`, `Grid`, `Plane`, `Cylinder`, `Torus`: one mesh per slice
//! of their parameters. Re-made only when a parameter changes (the runtime
//! reuses unchanged nodes), so a static primitive is uploaded once.

use glam::{Vec2, Vec3};
use spreadlight_graph::spread::{map2, map3, map4};
use spreadlight_graph::{EvalContext, NodeDef, NodeError, PinType, Registry, ResourceKind};
use spreadlight_render::mesh::MeshData;
use spreadlight_render::mesh::primitives::{
    BoxParams, CylinderParams, GridParams, SphereParams, TorusParams, box_mesh, cylinder, grid,
    sphere, torus,
};
use spreadlight_render::mesh_arena::GpuMesh;

use crate::gpu::{renderer, resource_spread};

const CATEGORY: &str = "Geometry";
const MESH: PinType = PinType::Resource(ResourceKind::Mesh);

pub fn register(r: &mut Registry) {
    r.add(
        NodeDef::new(
            "Box",
            CATEGORY,
            "A box centred at the origin, flat-shaded faces subdivided Segments times.",
        )
        .input("Size", Vec3::ONE)
        .input("Segments", 1i64)
        .output_typed("Mesh", MESH)
        .evaluate(|cx| {
            let meshes = map2(cx.slices::<Vec3>(0)?, cx.slices::<i64>(1)?, |size, seg| {
                box_mesh(BoxParams {
                    size: *size,
                    segments: count(*seg),
                })
            });
            upload(cx, meshes)
        }),
    );
    r.add(
        NodeDef::new(
            "Sphere",
            CATEGORY,
            "A UV sphere centred at the origin: Sectors around Y, Stacks pole to pole.",
        )
        .input("Radius", 0.5f32)
        .input("Sectors", 32i64)
        .input("Stacks", 16i64)
        .output_typed("Mesh", MESH)
        .evaluate(|cx| {
            let meshes = map3(
                cx.slices::<f32>(0)?,
                cx.slices::<i64>(1)?,
                cx.slices::<i64>(2)?,
                |r, se, st| {
                    sphere(SphereParams {
                        radius: *r,
                        sectors: count(*se),
                        stacks: count(*st),
                    })
                },
            );
            upload(cx, meshes)
        }),
    );
    r.add(
        NodeDef::new(
            "Grid",
            CATEGORY,
            "A plane in XZ facing +Y, centred at the origin, Resolution X by Y cells.",
        )
        .input("Size", Vec2::ONE)
        .input("Resolution X", 10i64)
        .input("Resolution Y", 10i64)
        .output_typed("Mesh", MESH)
        .evaluate(|cx| {
            let meshes = map3(
                cx.slices::<Vec2>(0)?,
                cx.slices::<i64>(1)?,
                cx.slices::<i64>(2)?,
                |s, x, y| {
                    grid(GridParams {
                        size: *s,
                        resolution_x: count(*x),
                        resolution_y: count(*y),
                    })
                },
            );
            upload(cx, meshes)
        }),
    );
    r.add(
        NodeDef::new(
            "Plane",
            CATEGORY,
            "A single-quad plane in XZ facing +Y (a Grid of 1x1 cells), scaled by Size.",
        )
        .input("Size", Vec2::ONE)
        .output_typed("Mesh", MESH)
        .evaluate(|cx| {
            let meshes = cx
                .slices::<Vec2>(0)?
                .iter()
                .map(|s| {
                    grid(GridParams {
                        size: *s,
                        resolution_x: 1,
                        resolution_y: 1,
                    })
                })
                .collect();
            upload(cx, meshes)
        }),
    );
    r.add(
        NodeDef::new(
            "Cylinder",
            CATEGORY,
            "A cylinder along Y centred at the origin, with optional caps.",
        )
        .input("Radius", 0.5f32)
        .input("Height", 1.0f32)
        .input("Sectors", 32i64)
        .input("Caps", true)
        .output_typed("Mesh", MESH)
        .evaluate(|cx| {
            let meshes = map4(
                cx.slices::<f32>(0)?,
                cx.slices::<f32>(1)?,
                cx.slices::<i64>(2)?,
                cx.slices::<bool>(3)?,
                |r, h, s, caps| {
                    cylinder(CylinderParams {
                        radius: *r,
                        height: *h,
                        sectors: count(*s),
                        caps: *caps,
                    })
                },
            );
            upload(cx, meshes)
        }),
    );
    r.add(
        NodeDef::new("Torus", CATEGORY, "A torus around Y in the XZ plane.")
            .input("Major Radius", 0.5f32)
            .input("Minor Radius", 0.2f32)
            .input("Major Segments", 32i64)
            .input("Minor Segments", 16i64)
            .output_typed("Mesh", MESH)
            .evaluate(|cx| {
                let meshes = map4(
                    cx.slices::<f32>(0)?,
                    cx.slices::<f32>(1)?,
                    cx.slices::<i64>(2)?,
                    cx.slices::<i64>(3)?,
                    |a, b, s, t| {
                        torus(TorusParams {
                            major_radius: *a,
                            minor_radius: *b,
                            major_segments: count(*s),
                            minor_segments: count(*t),
                        })
                    },
                );
                upload(cx, meshes)
            }),
    );
}

/// Segment counts from an Int pin: the generators clamp too small values themselves.
fn count(v: i64) -> u32 {
    v.clamp(0, 4096) as u32
}

fn upload(cx: &mut EvalContext<'_>, meshes: Vec<MeshData>) -> Result<(), NodeError> {
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
    cx.set_output(
        0,
        resource_spread::<GpuMesh>(ResourceKind::Mesh, gpu_meshes),
    );
    Ok(())
}
