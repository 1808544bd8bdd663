//! Generated test signals with known answers: sines, chirps, click tracks,
//! and WAV files of them.

use std::f32::consts::TAU;
use std::path::Path;

/// `seconds` of a sine of `freq` Hz and `amplitude` at `rate` Hz.
pub fn sine(freq: f32, amplitude: f32, rate: u32, seconds: f32) -> Vec<f32> {
    let n = (seconds * rate as f32) as usize;
    (0..n)
        .map(|i| amplitude * (TAU * freq * i as f32 / rate as f32).sin())
        .collect()
}

/// A linear chirp from `f0` to `f1` Hz over `seconds`.
pub fn chirp(f0: f32, f1: f32, rate: u32, seconds: f32) -> Vec<f32> {
    let n = (seconds * rate as f32) as usize;
    let k = (f1 - f0) / seconds;
    (0..n)
        .map(|i| {
            let t = i as f32 / rate as f32;
            (TAU * (f0 * t + 0.5 * k * t * t)).sin()
        })
        .collect()
}

/// Clicks (5 ms bursts of a decaying 1 kHz tone) at `bpm` for `seconds`, the first at 0.
pub fn clicks(bpm: f32, rate: u32, seconds: f32) -> Vec<f32> {
    let n = (seconds * rate as f32) as usize;
    let period = (60.0 / bpm * rate as f32) as usize;
    let burst = (0.005 * rate as f32) as usize;
    let mut out = vec![0.0; n];
    for start in (0..n).step_by(period) {
        for (k, s) in out[start..(start + burst).min(n)].iter_mut().enumerate() {
            let t = k as f32 / rate as f32;
            *s = 0.9 * (TAU * 1000.0 * t).sin() * (-t / 0.002).exp();
        }
    }
    out
}

/// Write `channels` (equal lengths) as a 16-bit WAV file.
pub fn write_wav(path: &Path, channels: &[Vec<f32>], rate: u32) {
    let spec = hound::WavSpec {
        channels: channels.len() as u16,
        sample_rate: rate,
        bits_per_sample: 16,
        sample_format: hound::SampleFormat::Int,
    };
    let mut w = hound::WavWriter::create(path, spec).expect("create wav");
    for i in 0..channels[0].len() {
        for c in channels {
            let v = (c[i].clamp(-1.0, 1.0) * 32767.0).round() as i16;
            w.write_sample(v).expect("write sample");
        }
    }
    w.finalize().expect("finish wav");
}
