//! `GBufferView`: one G-buffer channel as a texture, for looking at.

use spreadlight_graph::{Choices, NodeDef, NodeError, Registry};
use spreadlight_render::gbuffer::{Channel, GBufferView};

use crate::gpu::renderer;
use crate::post::{gbuffer_input, set_texture, texture_output};

pub static CHANNEL: Choices<Channel> = Choices::new(
    "G-Buffer Channel",
    &[
        "Albedo",
        "Normals",
        "Velocity",
        "UV",
        "Depth",
        "Material ID",
        "Object ID",
    ],
    &Channel::ALL,
);

pub fn register(r: &mut Registry) {
    r.add(
        NodeDef::new(
            "GBufferView",
            super::CATEGORY,
            "Shows one G-buffer channel: albedo, normals (as 0.5 + 0.5 n), velocity (scaled), UV, depth (as \
             1 / (1 + distance)), material or object ids (a colour per id). It reads only its channel's target.",
        )
        .with_pins(|p| {
            let g_buffer = gbuffer_input(p);
            let channel = p.input_choice("Channel", &CHANNEL, Channel::Albedo);
            let scale = p.input("Velocity Scale", 20.0f32);
            let out = texture_output(p, "Texture");
            move |cx| {
                let renderer = renderer(cx)?;
                let gbuffers = cx.resources(g_buffer)?;
                let channel = cx.choice(channel)?;
                let scale = cx.first(scale, 1.0)?;
                let Some(gbuffer) = gbuffers.into_iter().next() else {
                    return Err(NodeError::Other("no G-buffer connected".to_owned()));
                };
                let view = GBufferView::new(&renderer, Some(cx.node_id.0), gbuffer, channel, scale);
                set_texture(cx, out, view.texture());
                Ok(())
            }
        }),
    );
}
