//! `Displace`: each mesh's vertices moved along their normals by a height
//! texture at their UVs, normals recomputed, on the GPU
//! (`render::geometry::displace`).

use spreadlight_graph::spread::{cycled, slice_count};
use spreadlight_graph::{EvalContext, In, Node, NodeDef, NodeError, Out, Registry, Res};
use spreadlight_render::TextureRef;
use spreadlight_render::geometry::{DisplaceParams, displace};
use spreadlight_render::mesh_arena::GpuMesh;

use super::continuity::{Continuity, signature, with_identity};
use super::height::{height_texture, identity};
use crate::gpu::renderer;
use crate::lighting::require_finite;
use crate::post::texture_input;

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
        .with_pins_node(|p| {
            let pins = DisplacePins {
                mesh: super::mesh_input(p),
                texture: texture_input(p, "Texture"),
                amount: p.input("Amount", 0.1f32),
                midlevel: p.input("Midlevel", 0.0f32),
                out: super::mesh_output(p, "Mesh"),
            };
            move || Displace {
                pins,
                continuity: Continuity::default(),
            }
        }),
    );
}

#[derive(Clone, Copy)]
struct DisplacePins {
    mesh: In<Res<GpuMesh>>,
    texture: In<Res<TextureRef>>,
    amount: In<f32>,
    midlevel: In<f32>,
    out: Out<Res<GpuMesh>>,
}

struct Displace {
    pins: DisplacePins,
    continuity: Continuity,
}

impl Node for Displace {
    fn evaluate(&mut self, cx: &mut EvalContext<'_>) -> Result<(), NodeError> {
        let pins = self.pins;
        let meshes = cx.resources(pins.mesh)?;
        let Some(texture) = height_texture(cx, pins.texture)? else {
            return Err(cx.error(pins.texture, "connect a height texture (a FileTexture)"));
        };
        require_finite(cx, pins.amount)?;
        require_finite(cx, pins.midlevel)?;
        let amounts = cx.get(pins.amount)?.to_vec();
        let midlevels = cx.get(pins.midlevel)?.to_vec();
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
        cx.put_resources(pins.out, out);
        Ok(())
    }
}
