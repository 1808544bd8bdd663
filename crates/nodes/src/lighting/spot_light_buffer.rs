//! `SpotLightBuffer`: uploads the spot lights that `AddLight (Spot)` nodes
//! gathered, with the texture array their Texture IDs index (Emeshe's
//! Texture2DArray of projected textures; `FileTexture (Array)` makes one).

use spreadlight_graph::{NodeDef, PinType, Registry, ResourceKind, Spread};
use spreadlight_render::TextureRef;
use spreadlight_render::lighting::{LightBuffer, SpotLight};

use super::add_light::LightList;
use crate::gpu::{renderer, resource_spread, resources};

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
        .input_spread("Lights", PinType::Resource(kind), Spread::Resource(kind, Vec::new()))
        .input_spread(
            "Textures",
            PinType::Resource(ResourceKind::Texture),
            Spread::Resource(ResourceKind::Texture, Vec::new()),
        )
        .output_typed("Lights", PinType::Resource(ResourceKind::LightWorld))
        .output::<i64>("Count")
        .evaluate(|cx| {
            let renderer = renderer(cx)?;
            let list = LightList::<SpotLight>::gather(cx, 0)?;
            let textures = resources::<TextureRef>(cx, 1)?;
            if textures.len() > 1 {
                return Err(cx.input_error(
                    1,
                    format!("takes one texture array, got {} textures: join them with FileTexture (Array)", textures.len()),
                ));
            }
            let textures = textures.first().map(|t| (**t).clone());
            let buffer = LightBuffer::spots_of(&renderer, Some(cx.node_id.0), &list.lights, textures).map_err(|e| {
                // Name the light by its ID, as the patch does.
                let id = match &e {
                    spreadlight_render::lighting::SpotError::View { index }
                    | spreadlight_render::lighting::SpotError::Projection { index } => &list.ids[*index],
                };
                cx.input_error(0, format!("light `{id}`: {e}"))
            })?;
            cx.set_output(0, resource_spread(ResourceKind::LightWorld, vec![buffer]));
            cx.set_output(1, Spread::Int(vec![list.lights.len() as i64]));
            Ok(())
        }),
    );
}
