//! `Extrude`: every face of each mesh raised into a prism along its normal
//! on the GPU (`render::geometry::extrude`), the amount per face from a
//! spread, optionally scaled by a texture at the face's UV.

use spreadlight_graph::{
    EvalContext, Node, NodeDef, NodeError, PinType, Registry, ResourceKind, Spread,
};
use spreadlight_render::geometry::extrude;
use spreadlight_render::mesh_arena::GpuMesh;

use super::continuity::{Continuity, signature, with_identity};
use super::height::{height_texture, identity};
use crate::gpu::{renderer, resource_spread, resources};

pub fn register(r: &mut Registry) {
    r.add(
        NodeDef::new(
            "Extrude",
            super::CATEGORY,
            "Raises every face of each mesh along its face normal into a prism (a cap and three side walls, \
             flat-shaded; a closed mesh stays closed): face i by Amount slice i (cycled). Caps keep the UVs, walls \
             take their edge's. With a Texture (a FileTexture; sRGB off for data), each face's amount is also \
             multiplied by the texture's red channel at the face's centroid UV. Runs on the GPU; animated amounts \
             give previous positions for Velocity From Geometry.",
        )
        .input_spread("Mesh", super::MESH, Spread::Resource(ResourceKind::Mesh, vec![]))
        .input("Amount", 0.1f32)
        .input_spread(
            "Texture",
            PinType::Resource(ResourceKind::Texture),
            Spread::Resource(ResourceKind::Texture, vec![]),
        )
        .output_typed("Mesh", PinType::Resource(ResourceKind::Mesh))
        .construct(Extrude::default),
    );
}

#[derive(Default)]
struct Extrude {
    continuity: Continuity,
}

impl Node for Extrude {
    fn evaluate(&mut self, cx: &mut EvalContext<'_>) -> Result<(), NodeError> {
        let meshes = resources::<GpuMesh>(cx, 0)?;
        let amounts = cx.slices::<f32>(1)?.to_vec();
        let texture = height_texture(cx, 2)?;
        if amounts.is_empty() {
            cx.set_output(0, resource_spread::<GpuMesh>(ResourceKind::Mesh, vec![]));
            return Ok(());
        }
        let signatures = meshes
            .iter()
            .map(|m| with_identity(signature(Some(m), &amounts), identity(texture.as_ref())))
            .collect();
        let renderer = renderer(cx)?;
        let out = self.continuity.run(cx, signatures, |i, previous| {
            extrude(
                &renderer,
                &meshes[i],
                previous,
                &amounts,
                texture.as_ref().and_then(|t| t.recipe.static_texture()),
            )
        })?;
        cx.set_output(0, resource_spread(ResourceKind::Mesh, out));
        Ok(())
    }
}
