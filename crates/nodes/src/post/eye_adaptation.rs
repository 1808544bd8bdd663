//! `EyeAdaptation`: the average luminance of an HDR texture, adapted over time.

use spreadlight_graph::{NodeDef, PinType, Registry, ResourceKind, Spread};
use spreadlight_render::TextureRef;
use spreadlight_render::post::{AdaptationSettings, EyeAdaptation};

use crate::gpu::{renderer, resource_spread, resources};

pub fn register(r: &mut Registry) {
    let defaults = AdaptationSettings::default();
    r.add(
        NodeDef::new(
            "EyeAdaptation",
            "Post",
            "The average luminance of an HDR texture (geometric mean; NaN and infinite pixels left out), adapted over time \
             like an eye: each frame it moves 1 - exp(-dt * Speed) of the way (in log luminance), Speed Up towards a brighter \
             and Speed Down towards a darker image, per second. The first frame (and after a cut) takes the measurement as it is. \
             Stays within Minimum..Maximum, so a black frame adapts to Minimum. Output: a 1x1 texture of the adapted luminance \
             (linear) for Tonemap's Eye Adaptation input.",
        )
        .input_spread("Texture", PinType::Resource(ResourceKind::Texture), Spread::Resource(ResourceKind::Texture, vec![]))
        .input("Speed Up", defaults.speed_up)
        .input("Speed Down", defaults.speed_down)
        .input("Minimum", defaults.min_luminance)
        .input("Maximum", defaults.max_luminance)
        .output_typed("Luminance", PinType::Resource(ResourceKind::Texture))
        .time_dependent()
        .stateful()
        .evaluate(|cx| {
            let renderer = renderer(cx)?;
            let source = resources::<TextureRef>(cx, 0)?.into_iter().next().ok_or_else(|| cx.input_error(0, "no texture connected"))?;
            let mut values = [0.0f32; 4];
            for (i, value) in values.iter_mut().enumerate() {
                let pin = i + 1;
                let v = cx.slices::<f32>(pin)?.first().copied().unwrap_or(0.0);
                if !v.is_finite() {
                    return Err(cx.input_error(pin, "is NaN or infinite"));
                }
                if v < 0.0 {
                    return Err(cx.input_error(pin, "is negative"));
                }
                *value = v;
            }
            let [speed_up, speed_down, min_luminance, max_luminance] = values;
            if max_luminance < min_luminance {
                return Err(cx.input_error(4, "is below Minimum"));
            }
            let settings = AdaptationSettings { speed_up, speed_down, min_luminance, max_luminance };
            let adaptation = EyeAdaptation::new(&renderer, Some(cx.node_id.0), (*source).clone(), settings, cx.clock.delta);
            cx.set_output(0, resource_spread::<TextureRef>(ResourceKind::Texture, vec![std::sync::Arc::new(adaptation.texture())]));
            Ok(())
        }),
    );
}
