//! `Spherize`: blends each mesh towards a sphere on the GPU
//! (`render::geometry::spherize`); animated pins give the mesh previous
//! positions, so `Velocity: From Geometry` sees the motion.

use glam::Vec3;
use spreadlight_graph::spread::{cycled, slice_count};
use spreadlight_graph::{
    EvalContext, Node, NodeDef, NodeError, PinType, Registry, ResourceKind, Spread,
};
use spreadlight_render::geometry::{SpherizeParams, spherize};
use spreadlight_render::mesh_arena::GpuMesh;

use super::continuity::{Continuity, signature};
use crate::gpu::{renderer, resource_spread, resources};

pub fn register(r: &mut Registry) {
    r.add(
        NodeDef::new(
            "Spherize",
            super::CATEGORY,
            "Blends each mesh towards a sphere of Radius around Center: Amount 0 leaves it, 1 puts every vertex on \
             the sphere. Normals and tangents follow the deformation exactly, UVs are kept. Runs on the GPU; the \
             output carries last frame's positions for Velocity From Geometry.",
        )
        .input_spread("Mesh", super::MESH, Spread::Resource(ResourceKind::Mesh, vec![]))
        .input("Amount", 1.0f32)
        .input("Radius", 0.5f32)
        .input("Center", Vec3::ZERO)
        .output_typed("Mesh", PinType::Resource(ResourceKind::Mesh))
        .construct(Spherize::default),
    );
}

#[derive(Default)]
struct Spherize {
    continuity: Continuity,
}

impl Node for Spherize {
    fn evaluate(&mut self, cx: &mut EvalContext<'_>) -> Result<(), NodeError> {
        let meshes = resources::<GpuMesh>(cx, 0)?;
        let amounts = cx.slices::<f32>(1)?.to_vec();
        let radii = cx.slices::<f32>(2)?.to_vec();
        let centers = cx.slices::<Vec3>(3)?.to_vec();
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
        cx.set_output(0, resource_spread(ResourceKind::Mesh, out));
        Ok(())
    }
}
