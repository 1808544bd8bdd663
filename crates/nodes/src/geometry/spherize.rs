//! `Spherize`: blends each mesh towards a sphere on the GPU
//! (`render::geometry::spherize`); animated pins give the mesh previous
//! positions, so `Velocity: From Geometry` sees the motion.

use glam::Vec3;
use spreadlight_graph::spread::{cycled, slice_count};
use spreadlight_graph::{EvalContext, In, Node, NodeDef, NodeError, Out, Registry, Res};
use spreadlight_render::geometry::{SpherizeParams, spherize};
use spreadlight_render::mesh_arena::GpuMesh;

use super::continuity::{Continuity, signature};
use crate::gpu::renderer;

pub fn register(r: &mut Registry) {
    r.add(
        NodeDef::new(
            "Spherize",
            super::CATEGORY,
            "Blends each mesh towards a sphere of Radius around Center: Amount 0 leaves it, 1 puts every vertex on \
             the sphere. Normals and tangents follow the deformation exactly, UVs are kept. Runs on the GPU; the \
             output carries last frame's positions for Velocity From Geometry.",
        )
        .with_pins_node(|p| {
            let mesh = super::mesh_input(p);
            let amount = p.input("Amount", 1.0f32);
            let radius = p.input("Radius", 0.5f32);
            let center = p.input("Center", Vec3::ZERO);
            let out = super::mesh_output(p, "Mesh");
            move || Spherize {
                mesh,
                amount,
                radius,
                center,
                out,
                continuity: Continuity::default(),
            }
        }),
    );
}

struct Spherize {
    mesh: In<Res<GpuMesh>>,
    amount: In<f32>,
    radius: In<f32>,
    center: In<Vec3>,
    out: Out<Res<GpuMesh>>,
    continuity: Continuity,
}

impl Node for Spherize {
    fn evaluate(&mut self, cx: &mut EvalContext<'_>) -> Result<(), NodeError> {
        let meshes = cx.resources(self.mesh)?;
        let amounts = cx.get(self.amount)?.to_vec();
        let radii = cx.get(self.radius)?.to_vec();
        let centers = cx.get(self.center)?.to_vec();
        let n = slice_count([meshes.len(), amounts.len(), radii.len(), centers.len()]);
        let slices: Vec<_> = cycled(&meshes, n)
            .zip(cycled(&amounts, n))
            .zip(cycled(&radii, n))
            .zip(cycled(&centers, n))
            .map(|(((m, a), r), c)| {
                (
                    m.clone(),
                    SpherizeParams {
                        center: *c,
                        radius: *r,
                        amount: *a,
                    },
                )
            })
            .collect();
        let signatures = slices
            .iter()
            .map(|(m, p)| {
                signature(
                    Some(m),
                    &[p.amount, p.radius, p.center.x, p.center.y, p.center.z],
                )
            })
            .collect();
        let renderer = renderer(cx)?;
        let out = self.continuity.run(cx, signatures, |i, previous| {
            spherize(&renderer, &slices[i].0, previous, slices[i].1)
        })?;
        cx.put_resources(self.out, out);
        Ok(())
    }
}
