//! `PN Triangles` and `Subdivide`: every triangle split Level times an
//! edge on the GPU (`render::geometry::pn_triangles`), on the curved
//! point-normal patch of its corners or flat in its plane.

use spreadlight_graph::{EvalContext, In, Node, NodeDef, NodeError, Out, Registry, Res};
use spreadlight_render::geometry::pn_triangles;
use spreadlight_render::geometry::pn_triangles::MAX_LEVEL;
use spreadlight_render::mesh_arena::GpuMesh;

use super::continuity::{Continuity, signature};
use crate::gpu::renderer;

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
            NodeDef::new(name, super::CATEGORY, help).with_pins_node(|p| {
                let mesh = super::mesh_input(p);
                let level = p.input("Level", 3i64);
                let out = super::mesh_output(p, "Mesh");
                move || Tessellation {
                    mesh,
                    level,
                    out,
                    curved,
                    continuity: Continuity::default(),
                }
            }),
        );
    }
}

struct Tessellation {
    mesh: In<Res<GpuMesh>>,
    level: In<i64>,
    out: Out<Res<GpuMesh>>,
    curved: bool,
    continuity: Continuity,
}

impl Node for Tessellation {
    fn evaluate(&mut self, cx: &mut EvalContext<'_>) -> Result<(), NodeError> {
        let meshes = cx.resources(self.mesh)?;
        let level = cx.first(self.level, 1)?;
        if !(1..=i64::from(MAX_LEVEL)).contains(&level) {
            return Err(cx.error(self.level, format!("{level} is not within 1..{MAX_LEVEL}")));
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
        cx.put_resources(self.out, out);
        Ok(())
    }
}
