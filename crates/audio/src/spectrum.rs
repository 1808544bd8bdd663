//! The spectrum: an FFT (realfft) of the last samples under a Hann window,
//! as amplitudes per bin, and those bins grouped into bands spaced linearly
//! or logarithmically (equal ratios: octave bands when each spans a doubling).

use std::sync::Arc;

use realfft::num_complex::Complex;
use realfft::{RealFftPlanner, RealToComplex};

/// How bands divide the range between the lowest and highest frequency.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BandScale {
    /// Equal widths in Hz.
    Linear,
    /// Equal ratios: each band spans the same musical interval.
    Logarithmic,
}

/// One band: its edges and centre in Hz, and its amplitude.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Band {
    pub low: f32,
    pub high: f32,
    pub centre: f32,
    pub value: f32,
}

/// An FFT of one size, its window and buffers, reused frame after frame.
pub struct Analyzer {
    fft: Arc<dyn RealToComplex<f32>>,
    window: Vec<f32>,
    /// Turns |X| into the amplitude of a sine at a bin's centre.
    scale: f32,
    input: Vec<f32>,
    output: Vec<Complex<f32>>,
    scratch: Vec<Complex<f32>>,
    magnitudes: Vec<f32>,
}

impl std::fmt::Debug for Analyzer {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Analyzer")
            .field("size", &self.size())
            .finish()
    }
}

impl Analyzer {
    /// An analyzer of `size` samples (at least 2).
    pub fn new(size: usize) -> Self {
        let size = size.max(2);
        let fft = RealFftPlanner::<f32>::new().plan_fft_forward(size);
        let window: Vec<f32> = (0..size)
            .map(|i| 0.5 - 0.5 * (std::f32::consts::TAU * i as f32 / size as f32).cos())
            .collect();
        let sum: f32 = window.iter().sum();
        Analyzer {
            input: fft.make_input_vec(),
            output: fft.make_output_vec(),
            scratch: fft.make_scratch_vec(),
            magnitudes: vec![0.0; size / 2 + 1],
            scale: 2.0 / sum,
            window,
            fft,
        }
    }

    pub fn size(&self) -> usize {
        self.window.len()
    }

    /// Amplitudes of the `size / 2 + 1` bins of `samples` (its last `size`
    /// samples; zeros before a shorter one): a full-scale sine at a bin's
    /// centre frequency reads 1 there.
    pub fn magnitudes(&mut self, samples: &[f32]) -> &[f32] {
        let n = self.size();
        let take = samples.len().min(n);
        let pad = n - take;
        self.input[..pad].fill(0.0);
        for (k, (x, s)) in self.input[pad..]
            .iter_mut()
            .zip(&samples[samples.len() - take..])
            .enumerate()
        {
            *x = s * self.window[pad + k];
        }
        // Lengths come from the plan itself, so this cannot fail.
        let _ = self
            .fft
            .process_with_scratch(&mut self.input, &mut self.output, &mut self.scratch);
        for (m, c) in self.magnitudes.iter_mut().zip(&self.output) {
            *m = c.norm() * self.scale;
        }
        // DC and Nyquist have no mirror image to fold in.
        self.magnitudes[0] *= 0.5;
        if let Some(last) = self.magnitudes.last_mut().filter(|_| n.is_multiple_of(2)) {
            *last *= 0.5;
        }
        &self.magnitudes
    }
}

/// The frequency of bin `k` of an FFT of `size` at `rate`.
pub fn bin_frequency(k: usize, size: usize, rate: u32) -> f32 {
    k as f32 * rate as f32 / size as f32
}

/// The edges of `count` bands between `low` and `high` Hz.
pub fn band_edges(count: usize, low: f32, high: f32, scale: BandScale) -> Vec<f32> {
    let (low, high) = (low.max(0.0), high.max(low));
    (0..=count)
        .map(|i| {
            let t = i as f32 / count.max(1) as f32;
            match scale {
                BandScale::Linear => low + (high - low) * t,
                // Log spacing cannot start at 0 Hz: 1 Hz is below hearing anyway.
                BandScale::Logarithmic => {
                    let (a, b) = (low.max(1.0), high.max(low.max(1.0)));
                    a * (b / a).powf(t)
                }
            }
        })
        .collect()
}

/// Group `magnitudes` (of an FFT of `size` at `rate`) into `count` bands
/// between `low` and `high` Hz. A band's value is the largest amplitude of
/// the bins inside it, so a tone reads the same in a wide band as in a
/// narrow one; a band narrower than a bin reads the spectrum interpolated at
/// its centre.
pub fn bands(
    magnitudes: &[f32],
    size: usize,
    rate: u32,
    count: usize,
    (low, high): (f32, f32),
    scale: BandScale,
) -> Vec<Band> {
    let edges = band_edges(count, low, high, scale);
    let hz_per_bin = rate as f32 / size.max(1) as f32;
    let last = magnitudes.len().saturating_sub(1);
    let at = |hz: f32| -> f32 {
        let x = (hz / hz_per_bin).clamp(0.0, last as f32);
        let (i, t) = (x.floor() as usize, x.fract());
        let next = magnitudes.get(i + 1).copied().unwrap_or(0.0);
        magnitudes.get(i).map_or(0.0, |m| m + (next - m) * t)
    };
    edges
        .windows(2)
        .map(|e| {
            let (lo, hi) = (e[0], e[1]);
            let centre = match scale {
                BandScale::Linear => 0.5 * (lo + hi),
                BandScale::Logarithmic => (lo * hi).sqrt(),
            };
            let first = (lo / hz_per_bin).ceil() as usize;
            let end = ((hi / hz_per_bin).ceil() as usize).min(magnitudes.len());
            let value = if first < end {
                magnitudes[first..end].iter().fold(0.0f32, |m, &v| m.max(v))
            } else {
                at(centre)
            };
            Band {
                low: lo,
                high: hi,
                centre,
                value,
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tones::{chirp, sine};

    fn peak_bin(m: &[f32]) -> usize {
        m.iter()
            .enumerate()
            .max_by(|a, b| a.1.total_cmp(b.1))
            .map_or(0, |(i, _)| i)
    }

    #[test]
    fn a_440_hz_sine_peaks_in_its_bin_with_its_amplitude() {
        // 8 kHz, 1024 points: 7.8125 Hz a bin, 440 Hz is bin 56.32.
        let mut a = Analyzer::new(1024);
        let m = a.magnitudes(&sine(440.0, 0.5, 8000, 0.2)).to_vec();
        assert_eq!(m.len(), 513);
        assert_eq!(peak_bin(&m), 56);
        // Between bins a Hann window loses a little (at most 1.42 dB mid-way).
        assert!(m[56] > 0.5 * 0.84 && m[56] <= 0.5, "{}", m[56]);
        // A tone on a bin's centre reads its amplitude.
        let on_bin = bin_frequency(64, 1024, 8000);
        let m = a.magnitudes(&sine(on_bin, 0.5, 8000, 0.2)).to_vec();
        assert!((m[64] - 0.5).abs() < 0.005, "{}", m[64]);
        // Far from the tone the window's side lobes are small.
        assert!(m[200] < 1e-3, "{}", m[200]);
    }

    #[test]
    fn a_chirp_moves_its_peak_up() {
        let rate = 8000;
        let signal = chirp(200.0, 3000.0, rate, 1.0);
        let mut a = Analyzer::new(512);
        let mut peaks = Vec::new();
        for t in [0.1f32, 0.4, 0.7, 1.0] {
            let end = (t * rate as f32) as usize;
            let m = a.magnitudes(&signal[..end]);
            peaks.push(bin_frequency(peak_bin(m), 512, rate));
        }
        // The instantaneous frequency at the middle of each 64 ms window.
        for (t, f) in [0.1f32, 0.4, 0.7, 1.0].iter().zip(&peaks) {
            let expected = 200.0 + 2800.0 * (t - 0.032);
            assert!(
                (f - expected).abs() < 40.0,
                "at {t}s: {f} Hz, want {expected}"
            );
        }
        assert!(peaks.windows(2).all(|w| w[1] > w[0]), "{peaks:?}");
    }

    #[test]
    fn bands_group_bins_linearly_or_by_octaves() {
        let edges = band_edges(4, 0.0, 4000.0, BandScale::Linear);
        assert_eq!(edges, [0.0, 1000.0, 2000.0, 3000.0, 4000.0]);
        // Nine bands from 31.25 Hz to 16 kHz are octaves.
        let octaves = band_edges(9, 31.25, 16000.0, BandScale::Logarithmic);
        for w in octaves.windows(2) {
            assert!((w[1] / w[0] - 2.0).abs() < 1e-3, "{octaves:?}");
        }
        let mut a = Analyzer::new(1024);
        let m = a.magnitudes(&sine(440.0, 0.8, 8000, 0.2)).to_vec();
        let linear = bands(&m, 1024, 8000, 4, (0.0, 4000.0), BandScale::Linear);
        let loudest = linear
            .iter()
            .enumerate()
            .max_by(|a, b| a.1.value.total_cmp(&b.1.value))
            .map(|(i, _)| i);
        assert_eq!(loudest, Some(0));
        assert!(
            linear[0].value > 0.6 && linear[2].value < 0.01,
            "{linear:?}"
        );
        // 440 Hz sits in the octave 250..500 Hz of these (the fourth).
        let log = bands(&m, 1024, 8000, 5, (31.25, 1000.0), BandScale::Logarithmic);
        assert!(log[3].low <= 440.0 && 440.0 < log[3].high, "{log:?}");
        assert!(log[3].value > 0.6, "{log:?}");
        assert!(log[0].value < 0.01 && log[1].value < 0.01, "{log:?}");
    }
}
