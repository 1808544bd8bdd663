//! `PN Triangles` and `Subdivide`: every triangle split Level times an
//! edge on the GPU (`render::geometry::pn_triangles`), on the curved
//! point-normal patch of its corners or flat in its plane.

use spreadlight_graph::{
    EvalContext, Node, NodeDef, NodeError, PinType, Registry, ResourceKind, Spread,
};
use spreadlight_render::geometry::pn_triangles;
use spreadlight_render::geometry::pn_triangles::MAX_LEVEL;
use spreadlight_render::mesh_arena::GpuMesh;

use super::continuity::{Continuity, signature};
use crate::gpu::{renderer, resource_spread, resources};

pub fn register(r: &mut Registry) {
    for (name, curved, help) in [
        (
            "PN Triangles",
            true,
            "Curved point-normal triangles (Vlachos 2001): every triangle split Level times an edge onto the cubic \
             patch its corners' positions and normals define; shared normals keep neighbours crack-free. Runs on \
             the GPU.",
        ),
        (
            "Subdivide",
            false,
            "Every triangle split Level times an edge in its own plane (uniform, not adaptive), normals, UVs and \
             tangents interpolated. Runs on the GPU.",
        ),
    ] {
        r.add(
            NodeDef::new(name, super::CATEGORY, help)
                .input_spread(
                    "Mesh",
                    super::MESH,
                    Spread::Resource(ResourceKind::Mesh, vec![]),
                )
                .input("Level", 3i64)
                .output_typed("Mesh", PinType::Resource(ResourceKind::Mesh))
                .construct(move || Tessellation {
                    curved,
                    continuity: Continuity::default(),
                }),
        );
    }
}

struct Tessellation {
    curved: bool,
    continuity: Continuity,
}

impl Node for Tessellation {
    fn evaluate(&mut self, cx: &mut EvalContext<'_>) -> Result<(), NodeError> {
        let meshes = resources::<GpuMesh>(cx, 0)?;
        let level = cx.slices::<i64>(1)?.first().copied().unwrap_or(1);
        if !(1..=i64::from(MAX_LEVEL)).contains(&level) {
            return Err(cx.input_error(1, format!("{level} is not within 1..{MAX_LEVEL}")));
        }
        let signatures = meshes
            .iter()
            .map(|m| signature(Some(m), &[level as f32]))
            .collect();
        let renderer = renderer(cx)?;
        let curved = self.curved;
        let out = self.continuity.run(cx, signatures, |i, previous| {
            pn_triangles(&renderer, &meshes[i], previous, level as u32, curved)
        })?;
        cx.set_output(0, resource_spread(ResourceKind::Mesh, out));
        Ok(())
    }
}
