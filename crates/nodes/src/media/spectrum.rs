//! `Spectrum`: an FFT of the latest sound grouped into bands, a spread of
//! amplitudes to drive anything with (light intensities, particle rates).

use spreadlight_audio::spectrum::{Analyzer, BandScale, bands};
use spreadlight_graph::{EnumDef, Node, NodeDef, NodeError, Registry};

use super::{AUDIO, CATEGORY, audio, first_f32, first_i64, no_audio};

static SCALE: EnumDef = EnumDef {
    name: "BandScale",
    options: &["Logarithmic", "Linear"],
};

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
        .input_spread("Audio", AUDIO, no_audio())
        .input("FFT Size", 1024i64)
        .range(64.0, 16384.0)
        .input("Bands", 16i64)
        .range(1.0, 1024.0)
        .input_enum("Scale", &SCALE, "Logarithmic")
        .input("Min Frequency", 40.0f32)
        .input("Max Frequency", 16000.0f32)
        .output::<f32>("Bands")
        .output::<f32>("Frequencies")
        .construct(Spectrum::default),
    );
}

#[derive(Default)]
struct Spectrum {
    /// Planned once per size: planning is most of a first FFT's cost.
    analyzer: Option<Analyzer>,
    samples: Vec<f32>,
}

impl Node for Spectrum {
    fn evaluate(&mut self, cx: &mut spreadlight_graph::EvalContext<'_>) -> Result<(), NodeError> {
        let sounds = audio(cx, 0)?;
        let size = first_i64(cx, 1, 1024)?.clamp(64, 16384) as usize;
        let size = size.next_power_of_two().min(16384);
        let count = first_i64(cx, 2, 16)?.clamp(1, 1024) as usize;
        let scale = match cx.enum_slices(3)?.first().map(String::as_str) {
            Some("Linear") => BandScale::Linear,
            _ => BandScale::Logarithmic,
        };
        let low = first_f32(cx, 4, 40.0)?;
        let high = first_f32(cx, 5, 16000.0)?;
        if !(low.is_finite() && high.is_finite() && 0.0 <= low && low < high) {
            return Err(cx.input_error(
                4,
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
        cx.set(0, values);
        cx.set(1, centres);
        Ok(())
    }
}
