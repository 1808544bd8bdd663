//! `Tonemap`: exposure and an operator, HDR to display-referred 0..1.

use spreadlight_graph::{EnumDef, NodeDef, PinType, Registry, ResourceKind, Spread};
use spreadlight_render::TextureRef;
use spreadlight_render::post::{AdaptedExposure, Tonemap};
use spreadlight_render::reference::tonemap::TONEMAP_NAMES;

use crate::gpu::{renderer, resource_spread, resources};

pub static OPERATOR: EnumDef = EnumDef {
    name: "Tonemap Operator",
    options: &TONEMAP_NAMES,
};

pub fn register(r: &mut Registry) {
    r.add(
        NodeDef::new(
            "Tonemap",
            "Post",
            "HDR to display: multiplies by Exposure, then applies the operator (Emeshe's set plus ACES and AgX). \
             Parameter is the white point of Reinhard Modified and the maximum luminance of Drago and Logarithmic. \
             With Eye Adaptation connected (EyeAdaptation's Luminance), the exposure is Exposure * Key / adapted luminance; \
             unconnected, it is fixed.",
        )
        .input_spread("Texture", PinType::Resource(ResourceKind::Texture), Spread::Resource(ResourceKind::Texture, vec![]))
        .input_enum("Operator", &OPERATOR, "ACES")
        .input("Exposure", 1.0f32)
        .input("Parameter", 4.0f32)
        .input_spread("Eye Adaptation", PinType::Resource(ResourceKind::Texture), Spread::Resource(ResourceKind::Texture, vec![]))
        .input("Key", 0.18f32)
        .output_typed("Texture", PinType::Resource(ResourceKind::Texture))
        .evaluate(|cx| {
            let renderer = renderer(cx)?;
            let source = resources::<TextureRef>(cx, 0)?.into_iter().next().ok_or_else(|| cx.input_error(0, "no texture connected"))?;
            let name = cx.enum_slices(1)?.first().cloned().unwrap_or_default();
            let operator = OPERATOR.index_of(&name).ok_or_else(|| cx.input_error(1, format!("unknown operator `{name}`")))? as u32;
            let exposure = cx.slices::<f32>(2)?.first().copied().unwrap_or(1.0);
            if !exposure.is_finite() {
                return Err(cx.input_error(2, "is NaN or infinite"));
            }
            let param = cx.slices::<f32>(3)?.first().copied().unwrap_or(4.0);
            let adaptation = match resources::<TextureRef>(cx, 4)?.into_iter().next() {
                Some(luminance) => {
                    let key = cx.slices::<f32>(5)?.first().copied().unwrap_or(0.18);
                    if !key.is_finite() || key < 0.0 {
                        return Err(cx.input_error(5, "must be finite and not negative"));
                    }
                    Some(AdaptedExposure { luminance: (*luminance).clone(), key })
                }
                None => None,
            };
            let tonemap = Tonemap::with_adaptation(&renderer, Some(cx.node_id.0), (*source).clone(), operator, exposure, param, adaptation);
            cx.set_output(0, resource_spread::<TextureRef>(ResourceKind::Texture, vec![std::sync::Arc::new(tonemap.texture())]));
            Ok(())
        }),
    );
}
