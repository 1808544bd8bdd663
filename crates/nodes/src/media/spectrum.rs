//! `Spectrum`: an FFT of the latest sound grouped into bands, a spread of
//! amplitudes to drive anything with (light intensities, particle rates).

use spreadlight_audio::AudioWindow;
use spreadlight_audio::spectrum::{Analyzer, BandScale, bands};
use spreadlight_graph::{Choice, Choices, In, Node, NodeDef, NodeError, Out, Registry, Res};

use super::{CATEGORY, audio, audio_input};

static SCALE: Choices<BandScale> = Choices::new(
    "BandScale",
    &["Logarithmic", "Linear"],
    &[BandScale::Logarithmic, BandScale::Linear],
);

pub fn register(r: &mut Registry) {
    r.add(
        NodeDef::new(
            "Spectrum",
            CATEGORY,
            "The spectrum of the last FFT Size samples of each Audio slice (Hann window), \
             grouped into Bands between Min and Max Frequency: Logarithmic bands span equal \
             musical intervals (9 bands from 31.25 Hz to 16 kHz are octaves), Linear ones equal \
             Hz. A band's value is the amplitude of its loudest bin: a full-scale sine reads \
             about 1. Bands holds Bands slices per Audio slice; Frequencies their centres in Hz. \
             FFT Size is rounded to a power of two (64 to 16384).",
        )
        .with_pins_node(|p| {
            let audio = audio_input(p);
            let fft_size = p.input("FFT Size", 1024i64);
            p.range(64.0, 16384.0);
            let bands = p.input("Bands", 16i64);
            p.range(1.0, 1024.0);
            let pins = SpectrumPins {
                audio,
                fft_size,
                bands,
                scale: p.input_choice("Scale", &SCALE, BandScale::Logarithmic),
                min_frequency: p.input("Min Frequency", 40.0f32),
                max_frequency: p.input("Max Frequency", 16000.0f32),
                values: p.output::<f32>("Bands"),
                frequencies: p.output::<f32>("Frequencies"),
            };
            move || Spectrum {
                pins,
                analyzer: None,
                samples: Vec::new(),
            }
        }),
    );
}

#[derive(Clone, Copy)]
struct SpectrumPins {
    audio: In<Res<AudioWindow>>,
    fft_size: In<i64>,
    bands: In<i64>,
    scale: In<Choice<BandScale>>,
    min_frequency: In<f32>,
    max_frequency: In<f32>,
    values: Out<f32>,
    frequencies: Out<f32>,
}

struct Spectrum {
    pins: SpectrumPins,
    /// Planned once per size: planning is most of a first FFT's cost.
    analyzer: Option<Analyzer>,
    samples: Vec<f32>,
}

impl Node for Spectrum {
    fn evaluate(&mut self, cx: &mut spreadlight_graph::EvalContext<'_>) -> Result<(), NodeError> {
        let pins = self.pins;
        let sounds = audio(cx, pins.audio)?;
        let size = cx.first(pins.fft_size, 1024)?.clamp(64, 16384) as usize;
        let size = size.next_power_of_two().min(16384);
        let count = cx.first(pins.bands, 16)?.clamp(1, 1024) as usize;
        let scale = cx.choice(pins.scale)?;
        let low = cx.first(pins.min_frequency, 40.0)?;
        let high = cx.first(pins.max_frequency, 16000.0)?;
        if !(low.is_finite() && high.is_finite() && 0.0 <= low && low < high) {
            return Err(cx.error(
                pins.min_frequency,
                format!("Min Frequency {low} must be at least 0 and below Max Frequency {high}"),
            ));
        }
        let analyzer = match &mut self.analyzer {
            Some(a) if a.size() == size => a,
            slot => slot.insert(Analyzer::new(size)),
        };
        let (mut values, mut centres) = (Vec::new(), Vec::new());
        for w in &sounds {
            w.last_into(size, &mut self.samples);
            let magnitudes = analyzer.magnitudes(&self.samples);
            for band in bands(magnitudes, size, w.rate(), count, (low, high), scale) {
                values.push(band.value);
                centres.push(band.centre);
            }
        }
        cx.put(pins.values, values);
        cx.put(pins.frequencies, centres);
        Ok(())
    }
}
