//! `Level`: the RMS and peak of the last moments of sound.

use spreadlight_graph::{NodeDef, Registry};

use super::{CATEGORY, audio, audio_input};

pub fn register(r: &mut Registry) {
    r.add(
        NodeDef::new(
            "Level",
            CATEGORY,
            "The loudness of the last Window seconds of each Audio slice: RMS (the root mean \
             square, 0.707 for a full-scale sine) and Peak (the largest magnitude).",
        )
        .with_pins(|p| {
            let audio_in = audio_input(p);
            let window = p.input("Window", 0.05f32);
            p.range(0.001, 10.0);
            let rms_out = p.output::<f32>("RMS");
            let peak_out = p.output::<f32>("Peak");
            move |cx| {
                let sounds = audio(cx, audio_in)?;
                let seconds = f64::from(cx.first(window, 0.05)?.clamp(0.001, 10.0));
                let (mut rms, mut peak) = (Vec::new(), Vec::new());
                let mut samples = Vec::new();
                for w in &sounds {
                    w.last_into(w.samples_in(seconds), &mut samples);
                    let l = spreadlight_audio::level::level(&samples);
                    rms.push(l.rms);
                    peak.push(l.peak);
                }
                cx.put(rms_out, rms);
                cx.put(peak_out, peak);
                Ok(())
            }
        }),
    );
}
