//! `Tonemap`: exposure and an operator, HDR to display-referred 0..1.

use std::sync::Arc;

use spreadlight_graph::{Choices, NodeDef, Registry, ResourceKind};
use spreadlight_render::TextureRef;
use spreadlight_render::post::tonemap::TonemapOperator;
use spreadlight_render::post::{AdaptedExposure, Tonemap};

use crate::gpu::renderer;

pub static OPERATOR: Choices<TonemapOperator> = Choices::new(
    "Tonemap Operator",
    &TonemapOperator::NAMES,
    &TonemapOperator::ALL,
);

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
        .with_pins(|p| {
            let texture = p.input_resource::<TextureRef>("Texture", ResourceKind::Texture);
            let operator = p.input_choice("Operator", &OPERATOR, TonemapOperator::Aces);
            let exposure = p.input("Exposure", 1.0f32);
            let parameter = p.input("Parameter", 4.0f32);
            let eye_adaptation = p.input_resource::<TextureRef>("Eye Adaptation", ResourceKind::Texture);
            let key = p.input("Key", 0.18f32);
            let out = p.output_resource::<TextureRef>("Texture", ResourceKind::Texture);
            move |cx| {
                let renderer = renderer(cx)?;
                let source = cx
                    .resources(texture)?
                    .into_iter()
                    .next()
                    .ok_or_else(|| cx.error(texture, "no texture connected"))?;
                let operator = cx.choice(operator)?;
                let exposure_value = cx.first(exposure, 1.0)?;
                if !exposure_value.is_finite() {
                    return Err(cx.error(exposure, "is NaN or infinite"));
                }
                let param = cx.first(parameter, 4.0)?;
                let adaptation = match cx.resources(eye_adaptation)?.into_iter().next() {
                    Some(luminance) => {
                        let key_value = cx.first(key, 0.18)?;
                        if !key_value.is_finite() || key_value < 0.0 {
                            return Err(cx.error(key, "must be finite and not negative"));
                        }
                        Some(AdaptedExposure {
                            luminance: (*luminance).clone(),
                            key: key_value,
                        })
                    }
                    None => None,
                };
                let tonemap = Tonemap::with_adaptation(
                    &renderer,
                    Some(cx.node_id.0),
                    (*source).clone(),
                    operator,
                    exposure_value,
                    param,
                    adaptation,
                );
                cx.put_resources(out, vec![Arc::new(tonemap.texture())]);
                Ok(())
            }
        }),
    );
}
