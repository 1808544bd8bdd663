//! `CompositeLight`: the lit HDR image from CookTorrance's components.

use spreadlight_graph::{Color, NodeDef, PinType, Registry, ResourceKind, Spread};
use spreadlight_render::TextureRef;
use spreadlight_render::gbuffer::GBuffer;
use spreadlight_render::lighting::CompositeLight;

use crate::gpu::{renderer, resource_spread, resources};

pub fn register(r: &mut Registry) {
    let texture = || Spread::Resource(ResourceKind::Texture, vec![]);
    r.add(
        NodeDef::new(
            "CompositeLight",
            super::CATEGORY,
            "Adds CookTorrance's diffuse and specular and an ambient term (Ambient x albedo) into one HDR image.",
        )
        .input_spread("G-Buffer", PinType::Resource(ResourceKind::GBuffer), Spread::Resource(ResourceKind::GBuffer, vec![]))
        .input_spread("Diffuse", PinType::Resource(ResourceKind::Texture), texture())
        .input_spread("Specular", PinType::Resource(ResourceKind::Texture), texture())
        .input("Ambient", spreadlight_graph::Color::rgba(0.0, 0.0, 0.0, 1.0))
        .output_typed("Texture", PinType::Resource(ResourceKind::Texture))
        .evaluate(|cx| {
            let renderer = renderer(cx)?;
            let gbuffer = resources::<GBuffer>(cx, 0)?.into_iter().next().ok_or_else(|| cx.input_error(0, "no G-buffer connected"))?;
            let diffuse = resources::<TextureRef>(cx, 1)?.into_iter().next().ok_or_else(|| cx.input_error(1, "not connected"))?;
            let specular = resources::<TextureRef>(cx, 2)?.into_iter().next().ok_or_else(|| cx.input_error(2, "not connected"))?;
            let ambient: Color = cx.slices::<Color>(3)?.first().copied().unwrap_or(Color::BLACK);
            let composite = CompositeLight::new(
                &renderer,
                Some(cx.node_id.0),
                gbuffer,
                (*diffuse).clone(),
                (*specular).clone(),
                [ambient.r, ambient.g, ambient.b],
            );
            cx.set_output(0, resource_spread::<TextureRef>(ResourceKind::Texture, vec![std::sync::Arc::new(composite.texture())]));
            Ok(())
        }),
    );
}
