//! `EyeAdaptation`: the average luminance of an HDR texture, adapted over time.

use spreadlight_graph::{NodeDef, Registry};
use spreadlight_render::post::{AdaptationSettings, EyeAdaptation};

use super::{set_texture, texture, texture_input, texture_output};
use crate::gpu::renderer;

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
        .time_dependent()
        .stateful()
        .with_pins(|p| {
            let texture_in = texture_input(p, "Texture");
            let speed_up = p.input("Speed Up", defaults.speed_up);
            let speed_down = p.input("Speed Down", defaults.speed_down);
            let minimum = p.input("Minimum", defaults.min_luminance);
            let maximum = p.input("Maximum", defaults.max_luminance);
            let out = texture_output(p, "Luminance");
            move |cx| {
                let renderer = renderer(cx)?;
                let source = texture(cx, texture_in)?;
                let mut values = [0.0f32; 4];
                for (value, pin) in values.iter_mut().zip([speed_up, speed_down, minimum, maximum]) {
                    let v = cx.first(pin, 0.0)?;
                    if !v.is_finite() {
                        return Err(cx.error(pin, "is NaN or infinite"));
                    }
                    if v < 0.0 {
                        return Err(cx.error(pin, "is negative"));
                    }
                    *value = v;
                }
                let [speed_up, speed_down, min_luminance, max_luminance] = values;
                if max_luminance < min_luminance {
                    return Err(cx.error(maximum, "is below Minimum"));
                }
                let settings = AdaptationSettings { speed_up, speed_down, min_luminance, max_luminance };
                let adaptation = EyeAdaptation::new(&renderer, Some(cx.node_id.0), source, settings, cx.clock.delta);
                set_texture(cx, out, adaptation.texture());
                Ok(())
            }
        }),
    );
}
