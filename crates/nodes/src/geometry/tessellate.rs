//! `Tessellate`: area-adaptive, crack-free subdivision on the GPU
//! (`render::geometry::tessellate`): triangles over Max Area are split until
//! none is larger; shared edges are cut alike, so closed meshes stay closed.

use spreadlight_graph::{
    EvalContext, Node, NodeDef, NodeError, PinType, Registry, ResourceKind, Spread,
};
use spreadlight_render::geometry::tessellate;
use spreadlight_render::geometry::tessellate::MAX_LEVEL;
use spreadlight_render::mesh_arena::GpuMesh;

use super::continuity::{Continuity, signature};
use crate::gpu::{renderer, resource_spread, resources};

pub fn register(r: &mut Registry) {
    r.add(
        NodeDef::new(
            "Tessellate",
            super::CATEGORY,
            "Adaptive subdivision: every triangle whose area exceeds Max Area (> 0, in the mesh's units²) is split \
             into a grid until no triangle is larger, small ones stay whole. Each edge is cut into equal pieces of \
             at most sqrt(2 x Max Area) by a rule of its two end positions alone, so neighbours agree: no cracks, a \
             closed mesh stays closed (across UV seams too). Max Level (1..64) caps the pieces an edge. Flat: \
             positions stay in their triangles; normals, UVs and tangents interpolated. Zero-area triangles fill in \
             where a finer triangle meets a coarser edge (they draw nothing). Runs on the GPU; reads back one \
             number (the output's size) per run.",
        )
        .input_spread("Mesh", super::MESH, Spread::Resource(ResourceKind::Mesh, vec![]))
        .input("Max Area", 0.05f32)
        .input("Max Level", 16i64)
        .output_typed("Mesh", PinType::Resource(ResourceKind::Mesh))
        .construct(Tessellate::default),
    );
}

#[derive(Default)]
struct Tessellate {
    continuity: Continuity,
}

impl Node for Tessellate {
    fn evaluate(&mut self, cx: &mut EvalContext<'_>) -> Result<(), NodeError> {
        let meshes = resources::<GpuMesh>(cx, 0)?;
        let max_area = cx.slices::<f32>(1)?.first().copied().unwrap_or(0.05);
        let level = cx.slices::<i64>(2)?.first().copied().unwrap_or(16);
        if !(max_area.is_finite() && max_area > 0.0) {
            return Err(cx.input_error(1, format!("{max_area} is not a positive area")));
        }
        if !(1..=i64::from(MAX_LEVEL)).contains(&level) {
            return Err(cx.input_error(2, format!("{level} is not within 1..{MAX_LEVEL}")));
        }
        let signatures = meshes
            .iter()
            .map(|m| signature(Some(m), &[max_area, level as f32]))
            .collect();
        let renderer = renderer(cx)?;
        let out = self.continuity.run(cx, signatures, |i, previous| {
            tessellate(&renderer, &meshes[i], previous, max_area, level as u32)
        })?;
        cx.set_output(0, resource_spread(ResourceKind::Mesh, out));
        Ok(())
    }
}
