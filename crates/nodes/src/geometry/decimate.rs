//! `Decimate`: edge collapse to a share of the triangles, keeping UV seams
//! and borders (`render::geometry::decimate`, meshoptimizer on the CPU).

use spreadlight_graph::{EvalContext, In, Node, NodeDef, NodeError, Out, Registry, Res};
use spreadlight_render::geometry::{DecimateParams, decimate};
use spreadlight_render::mesh_arena::GpuMesh;

use crate::gpu::renderer;

pub fn register(r: &mut Registry) {
    r.add(
        NodeDef::new(
            "Decimate",
            super::CATEGORY,
            "Simplifies each mesh by edge collapse (meshoptimizer's quadric simplifier) to about Ratio (0..1) of its \
             triangles. UV seams and hard edges (vertices sharing a position) collapse together on both sides, so \
             they open no cracks; with Lock Border, vertices on open borders never move, so borders stay exactly \
             in place. Kept vertices keep everything they carry (normals, UVs, tangents, previous positions), so \
             an animated input's motion passes through. Fewer triangles than asked can't be had where locked \
             borders and seams leave nothing to collapse. Runs on the CPU (reads the mesh back, uploads the \
             result), only when its inputs change.",
        )
        .with_pins_node(|p| {
            let pins = Decimate {
                mesh: super::mesh_input(p),
                ratio: p.input("Ratio", 0.5f32),
                lock_border: p.input("Lock Border", true),
                out: super::mesh_output(p, "Mesh"),
            };
            move || pins
        }),
    );
}

#[derive(Clone, Copy)]
struct Decimate {
    mesh: In<Res<GpuMesh>>,
    ratio: In<f32>,
    lock_border: In<bool>,
    out: Out<Res<GpuMesh>>,
}

impl Node for Decimate {
    fn evaluate(&mut self, cx: &mut EvalContext<'_>) -> Result<(), NodeError> {
        let meshes = cx.resources(self.mesh)?;
        let ratio = cx.first(self.ratio, 0.5)?;
        let lock_border = cx.first(self.lock_border, true)?;
        if !(0.0..=1.0).contains(&ratio) {
            return Err(cx.error(self.ratio, format!("{ratio} is not within 0..1")));
        }
        let renderer = renderer(cx)?;
        let params = DecimateParams { ratio, lock_border };
        let out = meshes
            .iter()
            .enumerate()
            .map(|(i, m)| {
                decimate(&renderer, m, params)
                    .map_err(|e| NodeError::Other(format!("slice {i}: {e}")))
            })
            .collect::<Result<Vec<_>, _>>()?;
        cx.put_resources(self.out, out);
        Ok(())
    }
}
