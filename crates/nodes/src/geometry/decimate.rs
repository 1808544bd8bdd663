//! `Decimate`: edge collapse to a share of the triangles, keeping UV seams
//! and borders (`render::geometry::decimate`, meshoptimizer on the CPU).

use spreadlight_graph::{
    EvalContext, Node, NodeDef, NodeError, PinType, Registry, ResourceKind, Spread,
};
use spreadlight_render::geometry::{DecimateParams, decimate};
use spreadlight_render::mesh_arena::GpuMesh;

use crate::gpu::{renderer, resource_spread, resources};

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
        .input_spread("Mesh", super::MESH, Spread::Resource(ResourceKind::Mesh, vec![]))
        .input("Ratio", 0.5f32)
        .input("Lock Border", true)
        .output_typed("Mesh", PinType::Resource(ResourceKind::Mesh))
        .construct(|| Decimate),
    );
}

struct Decimate;

impl Node for Decimate {
    fn evaluate(&mut self, cx: &mut EvalContext<'_>) -> Result<(), NodeError> {
        let meshes = resources::<GpuMesh>(cx, 0)?;
        let ratio = cx.slices::<f32>(1)?.first().copied().unwrap_or(0.5);
        let lock_border = cx.slices::<bool>(2)?.first().copied().unwrap_or(true);
        if !(0.0..=1.0).contains(&ratio) {
            return Err(cx.input_error(1, format!("{ratio} is not within 0..1")));
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
        cx.set_output(0, resource_spread(ResourceKind::Mesh, out));
        Ok(())
    }
}
