//! `Extrude`: every face of each mesh raised into a prism along its normal
//! on the GPU (`render::geometry::extrude`), the amount per face from a
//! spread, optionally scaled by a texture at the face's UV.

use spreadlight_graph::{EvalContext, In, Node, NodeDef, NodeError, Out, Registry, Res};
use spreadlight_render::TextureRef;
use spreadlight_render::geometry::extrude;
use spreadlight_render::mesh_arena::GpuMesh;

use super::continuity::{Continuity, signature, with_identity};
use super::height::{height_texture, identity};
use crate::gpu::renderer;
use crate::post::texture_input;

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
        .with_pins_node(|p| {
            let pins = ExtrudePins {
                mesh: super::mesh_input(p),
                amount: p.input("Amount", 0.1f32),
                texture: texture_input(p, "Texture"),
                out: super::mesh_output(p, "Mesh"),
            };
            move || Extrude {
                pins,
                continuity: Continuity::default(),
            }
        }),
    );
}

#[derive(Clone, Copy)]
struct ExtrudePins {
    mesh: In<Res<GpuMesh>>,
    amount: In<f32>,
    texture: In<Res<TextureRef>>,
    out: Out<Res<GpuMesh>>,
}

struct Extrude {
    pins: ExtrudePins,
    continuity: Continuity,
}

impl Node for Extrude {
    fn evaluate(&mut self, cx: &mut EvalContext<'_>) -> Result<(), NodeError> {
        let pins = self.pins;
        let meshes = cx.resources(pins.mesh)?;
        let amounts = cx.get(pins.amount)?.to_vec();
        let texture = height_texture(cx, pins.texture)?;
        if amounts.is_empty() {
            cx.put_resources(pins.out, Vec::new());
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
        cx.put_resources(pins.out, out);
        Ok(())
    }
}
