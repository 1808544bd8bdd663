//! `Beat`: onsets (the starts of notes and hits) and the tempo of the
//! latest seconds of sound. The onset strength of each short frame is
//! remembered by its position in the sound, so a frame's work is only the
//! frames that are new; the result equals a computation from scratch, so a
//! render is deterministic.

use spreadlight_audio::AudioWindow;
use spreadlight_audio::beat::{OnsetTracker, PEAK_FRAMES, onsets, tempo};
use spreadlight_graph::{In, Node, NodeDef, NodeError, Out, Registry, Res};

use super::{CATEGORY, audio, audio_input};

pub fn register(r: &mut Registry) {
    r.add(
        NodeDef::new(
            "Beat",
            CATEGORY,
            "Onsets and tempo of the last Window seconds of each Audio slice. Onset is on in the \
             frame an onset is found (about 60 ms after it sounds: a peak is known only once the \
             sound after it is in); Strength is the latest onset strength (spectral flux) over the \
             window's largest, 0 to 1; BPM is the tempo between Min and Max BPM that fits the \
             onsets best (0 when nothing repeats). Threshold: how far above its surroundings a \
             peak must rise, as a fraction of the window's largest (lower finds more onsets).",
        )
        .with_pins_node(|p| {
            let audio = audio_input(p);
            let window = p.input("Window", 6.0f32);
            p.range(1.0, 30.0);
            let threshold = p.input("Threshold", 0.3f32);
            p.range(0.0, 1.0);
            let pins = BeatPins {
                audio,
                window,
                threshold,
                min_bpm: p.input("Min BPM", 60.0f32),
                max_bpm: p.input("Max BPM", 180.0f32),
                onset: p.output::<bool>("Onset"),
                bpm: p.output::<f32>("BPM"),
                strength: p.output::<f32>("Strength"),
            };
            move || Beat {
                pins,
                trackers: Vec::new(),
            }
        }),
    );
}

#[derive(Clone, Copy)]
struct BeatPins {
    audio: In<Res<AudioWindow>>,
    window: In<f32>,
    threshold: In<f32>,
    min_bpm: In<f32>,
    max_bpm: In<f32>,
    onset: Out<bool>,
    bpm: Out<f32>,
    strength: Out<f32>,
}

struct Beat {
    pins: BeatPins,
    /// One tracker per Audio slice, remade when the sample rate changes.
    trackers: Vec<OnsetTracker>,
}

impl Node for Beat {
    fn evaluate(&mut self, cx: &mut spreadlight_graph::EvalContext<'_>) -> Result<(), NodeError> {
        let pins = self.pins;
        let sounds = audio(cx, pins.audio)?;
        let seconds = f64::from(cx.first(pins.window, 6.0)?.clamp(1.0, 30.0));
        let threshold = cx.first(pins.threshold, 0.3)?.clamp(0.0, 1.0);
        let min_bpm = cx.first(pins.min_bpm, 60.0)?;
        let max_bpm = cx.first(pins.max_bpm, 180.0)?;
        if !(min_bpm >= 1.0 && max_bpm > min_bpm && max_bpm.is_finite()) {
            return Err(cx.error(
                pins.min_bpm,
                format!("Min BPM {min_bpm} must be at least 1 and below Max BPM {max_bpm}"),
            ));
        }
        self.trackers.truncate(sounds.len());
        let (mut onset, mut bpm, mut strength) = (Vec::new(), Vec::new(), Vec::new());
        for (k, w) in sounds.iter().enumerate() {
            if self.trackers.get(k).is_none_or(|t| t.rate() != w.rate()) {
                let tracker = OnsetTracker::new(w.rate());
                match self.trackers.get_mut(k) {
                    Some(slot) => *slot = tracker,
                    None => self.trackers.push(tracker),
                }
            }
            let tracker = &mut self.trackers[k];
            let (first, strengths) = tracker.strengths(w, seconds);
            // An onset is news in the frame in which it became known: when
            // the frames after its peak ended, within this frame's step.
            let known = |i: usize| tracker.frame_end(first + (i + PEAK_FRAMES) as i64);
            let fresh = onsets(&strengths, threshold)
                .into_iter()
                .any(|i| (w.end() - w.step() < known(i)) && known(i) <= w.end());
            let max = strengths.iter().fold(0.0f32, |m, &s| m.max(s));
            let latest = strengths.last().copied().unwrap_or(0.0);
            onset.push(fresh);
            bpm.push(tempo(&strengths, tracker.hop_seconds(), min_bpm, max_bpm).unwrap_or(0.0));
            strength.push(if max > 0.0 { latest / max } else { 0.0 });
        }
        cx.put(pins.onset, onset);
        cx.put(pins.bpm, bpm);
        cx.put(pins.strength, strength);
        Ok(())
    }
}
