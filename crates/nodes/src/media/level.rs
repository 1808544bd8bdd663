//! `Level`: the RMS and peak of the last moments of sound.

use spreadlight_graph::{NodeDef, Registry};

use super::{AUDIO, CATEGORY, audio, first_f32, no_audio};

pub fn register(r: &mut Registry) {
    r.add(
        NodeDef::new(
            "Level",
            CATEGORY,
            "The loudness of the last Window seconds of each Audio slice: RMS (the root mean \
             square, 0.707 for a full-scale sine) and Peak (the largest magnitude).",
        )
        .input_spread("Audio", AUDIO, no_audio())
        .input("Window", 0.05f32)
        .range(0.001, 10.0)
        .output::<f32>("RMS")
        .output::<f32>("Peak")
        .evaluate(|cx| {
            let sounds = audio(cx, 0)?;
            let seconds = f64::from(first_f32(cx, 1, 0.05)?.clamp(0.001, 10.0));
            let (mut rms, mut peak) = (Vec::new(), Vec::new());
            let mut samples = Vec::new();
            for w in &sounds {
                w.last_into(w.samples_in(seconds), &mut samples);
                let l = spreadlight_audio::level::level(&samples);
                rms.push(l.rms);
                peak.push(l.peak);
            }
            cx.set(0, rms);
            cx.set(1, peak);
            Ok(())
        }),
    );
}
