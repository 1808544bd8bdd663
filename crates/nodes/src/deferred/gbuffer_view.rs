//! `GBufferView`: one G-buffer channel as a texture, for looking at.

use spreadlight_graph::{EnumDef, NodeDef, NodeError, PinType, Registry, ResourceKind, Spread};
use spreadlight_render::TextureRef;
use spreadlight_render::gbuffer::{Channel, GBuffer, GBufferView};

use crate::gpu::{renderer, resource_spread, resources};

pub static CHANNEL: EnumDef = EnumDef {
    name: "G-Buffer Channel",
    options: &[
        "Albedo",
        "Normals",
        "Velocity",
        "UV",
        "Depth",
        "Material ID",
        "Object ID",
    ],
};

pub fn register(r: &mut Registry) {
    r.add(
        NodeDef::new(
            "GBufferView",
            super::CATEGORY,
            "Shows one G-buffer channel: albedo, normals (as 0.5 + 0.5 n), velocity (scaled), UV, depth (as \
             1 / (1 + distance)), material or object ids (a colour per id). It reads only its channel's target.",
        )
        .input_spread("G-Buffer", PinType::Resource(ResourceKind::GBuffer), Spread::Resource(ResourceKind::GBuffer, vec![]))
        .input_enum("Channel", &CHANNEL, "Albedo")
        .input("Velocity Scale", 20.0f32)
        .output_typed("Texture", PinType::Resource(ResourceKind::Texture))
        .evaluate(|cx| {
            let renderer = renderer(cx)?;
            let gbuffers = resources::<GBuffer>(cx, 0)?;
            let channel_name = cx.enum_slices(1)?.first().cloned().unwrap_or_default();
            let channel = Channel::ALL
                .into_iter()
                .find(|c| c.name() == channel_name)
                .ok_or_else(|| cx.input_error(1, format!("unknown channel `{channel_name}`")))?;
            let scale = cx.slices::<f32>(2)?.first().copied().unwrap_or(1.0);
            let Some(gbuffer) = gbuffers.into_iter().next() else {
                return Err(NodeError::Other("no G-buffer connected".to_owned()));
            };
            let view = GBufferView::new(&renderer, Some(cx.node_id.0), gbuffer, channel, scale);
            cx.set_output(0, resource_spread::<TextureRef>(ResourceKind::Texture, vec![std::sync::Arc::new(view.texture())]));
            Ok(())
        }),
    );
}
