//! Level: the RMS (loudness over the window) and the peak (largest magnitude).

/// RMS and peak of a window of samples.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Level {
    pub rms: f32,
    pub peak: f32,
}

/// The level of `samples`; silence (0, 0) for none.
pub fn level(samples: &[f32]) -> Level {
    if samples.is_empty() {
        return Level::default();
    }
    // Summed in f64: a long window of small samples loses nothing.
    let sum: f64 = samples.iter().map(|&s| f64::from(s) * f64::from(s)).sum();
    let peak = samples.iter().fold(0.0f32, |m, s| m.max(s.abs()));
    Level {
        rms: (sum / samples.len() as f64).sqrt() as f32,
        peak,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tones::sine;

    #[test]
    fn a_sine_has_rms_amplitude_over_root_two_and_its_amplitude_as_peak() {
        // 0.5 s of 100 Hz at 8 kHz: a whole number of periods.
        let l = level(&sine(100.0, 0.6, 8000, 0.5));
        assert!((l.rms - 0.6 / 2f32.sqrt()).abs() < 1e-4, "{l:?}");
        assert!((l.peak - 0.6).abs() < 1e-3, "{l:?}");
        assert_eq!(level(&[]), Level::default());
        assert_eq!(level(&[0.0, -0.5, 0.25]).peak, 0.5);
    }
}
