//! `AudioIn`: the default capture device (a microphone, a line in) through
//! cpal, ALSA on Linux, for the analysis nodes. A machine without one (a CI
//! machine, a server) shows "no audio device" on the node; the rest of the
//! patch runs on. The device is tried again when a pin changes, not every
//! frame: a missing device would otherwise cost an ALSA probe per frame.

use spreadlight_audio::AudioWindow;
use spreadlight_audio::input::LiveInput;
use spreadlight_graph::{In, Node, NodeDef, NodeError, Out, Registry, Res};

use super::{CATEGORY, audio_output, put_audio};

pub fn register(r: &mut Registry) {
    r.add(
        NodeDef::new(
            "AudioIn",
            CATEGORY,
            "Live sound from the system's default capture device, mixed to mono, for the \
             analysis nodes: Audio holds the latest Buffer seconds. Live input follows the \
             device, not the patch clock, so it is not deterministic (use AudioFile for \
             renders). Without a device the node shows \"no audio device\" and outputs nothing.",
        )
        .time_dependent()
        .with_pins_node(|p| {
            let pins = AudioInPins {
                enabled: p.input("Enabled", true),
                buffer: {
                    let pin = p.input("Buffer", 8.0f32);
                    p.range(0.1, 60.0);
                    pin
                },
                audio: audio_output(p),
                rate: p.output::<i64>("Sample Rate"),
                device: p.output::<String>("Device"),
            };
            move || AudioIn { pins, opened: None }
        }),
    );
}

#[derive(Clone, Copy)]
struct AudioInPins {
    enabled: In<bool>,
    buffer: In<f32>,
    audio: Out<Res<AudioWindow>>,
    rate: Out<i64>,
    device: Out<String>,
}

struct AudioIn {
    pins: AudioInPins,
    /// The open device, or why it did not open, for these pins.
    opened: Option<((bool, u32), Result<LiveInput, String>)>,
}

impl Node for AudioIn {
    fn evaluate(&mut self, cx: &mut spreadlight_graph::EvalContext<'_>) -> Result<(), NodeError> {
        let pins = self.pins;
        let enabled = cx.first(pins.enabled, false)?;
        let seconds = cx.first(pins.buffer, 8.0)?.clamp(0.1, 60.0);
        let key = (enabled, seconds.to_bits());
        if !enabled {
            self.opened = None;
            return Ok(());
        }
        if self.opened.as_ref().is_none_or(|(k, _)| *k != key) {
            // Close the old device before opening it again.
            self.opened = None;
            let input = LiveInput::open_default(seconds).map_err(|e| e.to_string());
            self.opened = Some((key, input));
        }
        let input = match &self.opened {
            Some((_, Ok(input))) => input,
            Some((_, Err(e))) => return Err(NodeError::Other(e.clone())),
            None => return Ok(()),
        };
        let window = input.window();
        let step = (cx.clock.delta * f64::from(input.rate())).round() as i64;
        let (rate, device) = (i64::from(input.rate()), input.name().to_owned());
        put_audio(cx, pins.audio, window.with_step(step));
        cx.put(pins.rate, vec![rate]);
        cx.put(pins.device, vec![device]);
        Ok(())
    }
}
