//! `Envelope`: an envelope follower on the sound, with attack and release.
//! It follows the window of sound that decides its value (five time
//! constants) from silence each frame, instead of carrying a level from the
//! frame before, so a render chunk agrees with a full run.

use spreadlight_audio::envelope::{follow, memory_seconds};
use spreadlight_graph::{NodeDef, Registry};

use super::{CATEGORY, audio, audio_input};

/// The longest stretch of sound followed a frame.
const MAX_SECONDS: f32 = 10.0;

pub fn register(r: &mut Registry) {
    r.add(
        NodeDef::new(
            "Envelope",
            CATEGORY,
            "An envelope follower on each Audio slice: a level that rises toward the sound's \
             magnitude with the Attack time constant and falls with the Release one (seconds: a \
             step up reaches 63% after Attack, a step down falls to 37% after Release). Follows \
             the last five time constants of sound (at most 10 s) each frame.",
        )
        .with_pins(|p| {
            let audio_in = audio_input(p);
            let attack_in = p.input("Attack", 0.01f32);
            p.range(0.0, 2.0);
            let release_in = p.input("Release", 0.2f32);
            p.range(0.0, 2.0);
            let envelope = p.output::<f32>("Envelope");
            move |cx| {
                let sounds = audio(cx, audio_in)?;
                let attack = cx.first(attack_in, 0.01)?.clamp(0.0, 2.0);
                let release = cx.first(release_in, 0.2)?.clamp(0.0, 2.0);
                let seconds = f64::from(memory_seconds(attack, release).clamp(0.001, MAX_SECONDS));
                let mut samples = Vec::new();
                let mut out = Vec::new();
                for w in &sounds {
                    w.last_into(w.samples_in(seconds), &mut samples);
                    out.push(follow(&samples, w.rate(), attack, release, 0.0));
                }
                cx.put(envelope, out);
                Ok(())
            }
        }),
    );
}
