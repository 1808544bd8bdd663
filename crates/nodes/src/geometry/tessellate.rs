//! `Tessellate`: area-adaptive, crack-free subdivision on the GPU
//! (`render::geometry::tessellate`): triangles over Max Area are split until
//! none is larger; shared edges are cut alike, so closed meshes stay closed.

use spreadlight_graph::{EvalContext, In, Node, NodeDef, NodeError, Out, Registry, Res};
use spreadlight_render::geometry::tessellate;
use spreadlight_render::geometry::tessellate::MAX_LEVEL;
use spreadlight_render::mesh_arena::GpuMesh;

use super::continuity::{Continuity, signature};
use crate::gpu::renderer;

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
        .with_pins_node(|p| {
            let mesh = super::mesh_input(p);
            let max_area = p.input("Max Area", 0.05f32);
            let max_level = p.input("Max Level", 16i64);
            let out = super::mesh_output(p, "Mesh");
            move || Tessellate {
                mesh,
                max_area,
                max_level,
                out,
                continuity: Continuity::default(),
            }
        }),
    );
}

struct Tessellate {
    mesh: In<Res<GpuMesh>>,
    max_area: In<f32>,
    max_level: In<i64>,
    out: Out<Res<GpuMesh>>,
    continuity: Continuity,
}

impl Node for Tessellate {
    fn evaluate(&mut self, cx: &mut EvalContext<'_>) -> Result<(), NodeError> {
        let meshes = cx.resources(self.mesh)?;
        let max_area = cx.first(self.max_area, 0.05)?;
        let level = cx.first(self.max_level, 16)?;
        if !(max_area.is_finite() && max_area > 0.0) {
            return Err(cx.error(self.max_area, format!("{max_area} is not a positive area")));
        }
        if !(1..=i64::from(MAX_LEVEL)).contains(&level) {
            return Err(cx.error(
                self.max_level,
                format!("{level} is not within 1..{MAX_LEVEL}"),
            ));
        }
        let signatures = meshes
            .iter()
            .map(|m| signature(Some(m), &[max_area, level as f32]))
            .collect();
        let renderer = renderer(cx)?;
        let out = self.continuity.run(cx, signatures, |i, previous| {
            tessellate(&renderer, &meshes[i], previous, max_area, level as u32)
        })?;
        cx.put_resources(self.out, out);
        Ok(())
    }
}
