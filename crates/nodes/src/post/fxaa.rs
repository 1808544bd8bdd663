//! `FXAA`: fast approximate anti-aliasing, texture in, texture out. Best
//! after `Tonemap` (its edge test reads luma); Quality sets how far it
//! follows an edge.

use spreadlight_graph::{Choices, NodeDef, Registry};
use spreadlight_render::post::{Fxaa, FxaaQuality};

use super::{float, set_texture, texture, texture_input, texture_output};
use crate::gpu::renderer;

pub static QUALITY: Choices<FxaaQuality> = Choices::new(
    "FXAA Quality",
    &["Low", "Medium", "High"],
    &[FxaaQuality::Low, FxaaQuality::Medium, FxaaQuality::High],
);

pub fn register(r: &mut Registry) {
    r.add(
        NodeDef::new(
            "FXAA",
            "Post",
            "Fast approximate anti-aliasing: smooths aliased edges found by luma contrast. Quality: Low (4 edge-search \
             steps), Medium (8), High (12, the finest contrast threshold). Subpixel 0..1: how much detail smaller than a \
             pixel is softened (0.75 is FXAA's default).",
        )
        .with_pins(|p| {
            let texture_in = texture_input(p, "Texture");
            let quality = p.input_choice("Quality", &QUALITY, FxaaQuality::High);
            let subpixel = p.input("Subpixel", 0.75f32);
            let out = texture_output(p, "Texture");
            move |cx| {
                let renderer = renderer(cx)?;
                let source = texture(cx, texture_in)?;
                let quality = cx.choice(quality)?;
                let subpixel = float(cx, subpixel, 0.75, false)?;
                let fxaa = Fxaa::new(&renderer, Some(cx.node_id.0), source, quality, subpixel);
                set_texture(cx, out, fxaa.texture());
                Ok(())
            }
        }),
    );
}
