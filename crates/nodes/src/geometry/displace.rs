//! `Displace`: each mesh's vertices moved along their normals by a height
//! texture at their UVs, normals recomputed, on the GPU
//! (`render::geometry::displace`).

use spreadlight_graph::spread::{cycled, slice_count};
use spreadlight_graph::{
    EvalContext, Node, NodeDef, NodeError, PinType, Registry, ResourceKind, Spread,
};
use spreadlight_render::geometry::{DisplaceParams, displace};
use spreadlight_render::mesh_arena::GpuMesh;

use super::continuity::{Continuity, signature, with_identity};
use super::height::{height_texture, identity};
use crate::gpu::{renderer, resource_spread, resources};

pub fn register(r: &mut Registry) {
    r.add(
        NodeDef::new(
            "Displace",
            super::CATEGORY,
            "Moves every vertex of each mesh along its normal by (height - Midlevel) x Amount, height the Texture's \
             red channel (0..1 for image files; switch sRGB off on the FileTexture) at the vertex's UV, sampled \
             linearly and repeating. Normals are then recomputed from the moved surface (angle-weighted over the \
             triangles sharing each vertex; split vertices keep their sides apart) and tangents follow. Amount and \
             Midlevel cycle over the meshes; any finite value. Tessellate first for detail finer than the mesh. \
             Runs on the GPU; the Texture must exist before the frame (FileTexture).",
        )
        .input_spread("Mesh", super::MESH, Spread::Resource(ResourceKind::Mesh, vec![]))
        .input_spread(
            "Texture",
            PinType::Resource(ResourceKind::Texture),
            Spread::Resource(ResourceKind::Texture, vec![]),
        )
        .input("Amount", 0.1f32)
        .input("Midlevel", 0.0f32)
        .output_typed("Mesh", PinType::Resource(ResourceKind::Mesh))
        .construct(Displace::default),
    );
}

#[derive(Default)]
struct Displace {
    continuity: Continuity,
}

impl Node for Displace {
    fn evaluate(&mut self, cx: &mut EvalContext<'_>) -> Result<(), NodeError> {
        let meshes = resources::<GpuMesh>(cx, 0)?;
        let Some(texture) = height_texture(cx, 1)? else {
            return Err(cx.input_error(1, "connect a height texture (a FileTexture)"));
        };
        let amounts = cx.slices::<f32>(2)?.to_vec();
        let midlevels = cx.slices::<f32>(3)?.to_vec();
        for (pin, values) in [(2, &amounts), (3, &midlevels)] {
            if let Some(i) = values.iter().position(|v| !v.is_finite()) {
                return Err(cx.input_error(pin, format!("slice {i} is NaN or infinite")));
            }
        }
        let n = if meshes.is_empty() {
            0
        } else {
            slice_count([meshes.len(), amounts.len(), midlevels.len()])
        };
        let slices: Vec<_> = cycled(&meshes, n)
            .zip(cycled(&amounts, n).zip(cycled(&midlevels, n)))
            .map(|(m, (a, mid))| {
                (
                    m.clone(),
                    DisplaceParams {
                        amount: *a,
                        midlevel: *mid,
                    },
                )
            })
            .collect();
        let id = identity(Some(&texture));
        let signatures = slices
            .iter()
            .map(|(m, p)| with_identity(signature(Some(m), &[p.amount, p.midlevel]), id))
            .collect();
        let renderer = renderer(cx)?;
        let height = texture
            .recipe
            .static_texture()
            .expect("height_texture checked it");
        let out = self.continuity.run(cx, signatures, |i, previous| {
            displace(&renderer, &slices[i].0, previous, height, slices[i].1)
        })?;
        cx.set_output(0, resource_spread(ResourceKind::Mesh, out));
        Ok(())
    }
}
