//! `FXAA`: fast approximate anti-aliasing, texture in, texture out. Best
//! after `Tonemap` (its edge test reads luma); Quality sets how far it
//! follows an edge.

use spreadlight_graph::{EnumDef, NodeDef, PinType, Registry, ResourceKind, Spread};
use spreadlight_render::TextureRef;
use spreadlight_render::post::{Fxaa, FxaaQuality};

use crate::gpu::{renderer, resource_spread, resources};

pub static QUALITY: EnumDef = EnumDef {
    name: "FXAA Quality",
    options: &["Low", "Medium", "High"],
};

pub fn register(r: &mut Registry) {
    r.add(
        NodeDef::new(
            "FXAA",
            "Post",
            "Fast approximate anti-aliasing: smooths aliased edges found by luma contrast. Quality: Low (4 edge-search \
             steps), Medium (8), High (12, the finest contrast threshold). Subpixel 0..1: how much detail smaller than a \
             pixel is softened (0.75 is FXAA's default).",
        )
        .input_spread("Texture", PinType::Resource(ResourceKind::Texture), Spread::Resource(ResourceKind::Texture, vec![]))
        .input_enum("Quality", &QUALITY, "High")
        .input("Subpixel", 0.75f32)
        .output_typed("Texture", PinType::Resource(ResourceKind::Texture))
        .evaluate(|cx| {
            let renderer = renderer(cx)?;
            let source = resources::<TextureRef>(cx, 0)?
                .into_iter()
                .next()
                .ok_or_else(|| cx.input_error(0, "no texture connected"))?;
            let quality = match cx.enum_slices(1)?.first().map(String::as_str) {
                Some("Low") => FxaaQuality::Low,
                Some("Medium") => FxaaQuality::Medium,
                _ => FxaaQuality::High,
            };
            let subpixel = cx.slices::<f32>(2)?.first().copied().unwrap_or(0.75);
            if !subpixel.is_finite() {
                return Err(cx.input_error(2, "is NaN or infinite"));
            }
            let fxaa = Fxaa::new(&renderer, Some(cx.node_id.0), (*source).clone(), quality, subpixel);
            cx.set_output(0, resource_spread::<TextureRef>(ResourceKind::Texture, vec![std::sync::Arc::new(fxaa.texture())]));
            Ok(())
        }),
    );
}
