//! `SpotLightBuffer`: uploads the spot lights that `AddLight (Spot)` nodes
//! gathered, with the texture array their Texture IDs index (Emeshe's
//! Texture2DArray of projected textures; `FileTexture (Array)` makes one).

use spreadlight_graph::{NodeDef, Registry, ResourceKind};
use spreadlight_render::TextureRef;
use spreadlight_render::lighting::{LightBuffer, SpotLight};

use super::add_light::LightList;
use crate::gpu::renderer;

pub fn register(r: &mut Registry) {
    let kind = ResourceKind::SpotLights;
    r.add(
        NodeDef::new(
            "SpotLightBuffer",
            super::CATEGORY,
            "The spot lights from AddLight (Spot) nodes as one GPU buffer, uploaded when they change, \
             with the textures they project: a texture array (FileTexture (Array)) whose layers the \
             lights' Texture IDs pick, wrapping past its end. No texture: every spot is a round cone.",
        )
        .with_pins(|p| {
            let lights = LightList::<SpotLight>::input(p, kind);
            let textures = p.input_resource::<TextureRef>("Textures", ResourceKind::Texture);
            let out = p.output_resource::<LightBuffer>("Lights", ResourceKind::LightWorld);
            let count = p.output::<i64>("Count");
            move |cx| {
                let renderer = renderer(cx)?;
                let list = LightList::<SpotLight>::gather(cx, lights)?;
                let arrays = cx.resources(textures)?;
                if arrays.len() > 1 {
                    return Err(cx.error(
                        textures,
                        format!(
                            "takes one texture array, got {} textures: join them with FileTexture (Array)",
                            arrays.len()
                        ),
                    ));
                }
                let arrays = arrays.first().map(|t| (**t).clone());
                let buffer = LightBuffer::spots_of(&renderer, Some(cx.node_id.0), &list.lights, arrays).map_err(|e| {
                    // Name the light by its ID, as the patch does.
                    let id = match &e {
                        spreadlight_render::lighting::SpotError::View { index }
                        | spreadlight_render::lighting::SpotError::Projection { index } => &list.ids[*index],
                    };
                    cx.error(lights, format!("light `{id}`: {e}"))
                })?;
                cx.put_resources(out, vec![buffer]);
                cx.put(count, vec![list.lights.len() as i64]);
                Ok(())
            }
        }),
    );
}
