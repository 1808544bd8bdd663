//! Onsets and tempo. The onset strength is the spectral flux: how much the
//! log-compressed spectrum rose from one short frame (about 23 ms, half
//! overlapping) to the next. Onsets are its local peaks above a threshold;
//! the tempo is the lag at which it best correlates with itself.
//!
//! Frames sit on a grid of absolute sample positions, so an [`OnsetTracker`]
//! computes each frame once, however the windows it is shown overlap, and
//! what it returns equals a computation from scratch.

use std::collections::VecDeque;

use crate::spectrum::Analyzer;
use crate::window::AudioWindow;

/// Frames a peak must lead on either side; an onset is known this many hops after it.
pub const PEAK_FRAMES: usize = 3;
/// Frames before a peak whose mean strength it must exceed.
const MEAN_FRAMES: usize = 10;
/// Below this strength nothing happens: a steady sound's frame-to-frame
/// wobble, far under a click's 0.1 and more.
pub const QUIET: f32 = 0.005;

/// The analysis frame at `rate`: the power of two nearest 23 ms (512 at
/// 22.05 kHz, 1024 at 44.1 and 48 kHz); hops are half of it.
pub fn frame_size(rate: u32) -> usize {
    let ideal = f64::from(rate) * 0.023;
    1usize << ideal.max(2.0).log2().round() as u32
}

/// The onset strength of frames on a fixed grid, remembered by position.
#[derive(Debug)]
pub struct OnsetTracker {
    rate: u32,
    frame: usize,
    analyzer: Analyzer,
    /// Strengths of consecutive frames, the first being frame `first`.
    first: i64,
    strengths: VecDeque<f32>,
    /// The log spectrum of the last frame computed, by frame index.
    previous: Option<(i64, Vec<f32>)>,
    samples: Vec<f32>,
}

impl OnsetTracker {
    pub fn new(rate: u32) -> Self {
        let frame = frame_size(rate);
        OnsetTracker {
            rate,
            frame,
            analyzer: Analyzer::new(frame),
            first: 0,
            strengths: VecDeque::new(),
            previous: None,
            samples: Vec::new(),
        }
    }

    pub fn rate(&self) -> u32 {
        self.rate
    }

    pub fn hop(&self) -> usize {
        self.frame / 2
    }

    /// Seconds between frames.
    pub fn hop_seconds(&self) -> f64 {
        self.hop() as f64 / f64::from(self.rate)
    }

    /// The absolute sample where frame `i` ends.
    pub fn frame_end(&self, i: i64) -> i64 {
        i * self.hop() as i64 + self.frame as i64
    }

    /// The log-compressed spectrum of frame `i` of `window`.
    fn log_spectrum(&mut self, window: &AudioWindow, i: i64) -> Vec<f32> {
        window.read_into(i * self.hop() as i64, self.frame, &mut self.samples);
        self.analyzer
            .magnitudes(&self.samples)
            .iter()
            .map(|m| (1.0 + 100.0 * m).ln())
            .collect()
    }

    /// The strengths of the frames that end within the last `seconds` of
    /// `window` (before its end), and the index of the first. Frames
    /// computed for an earlier window are reused.
    pub fn strengths(&mut self, window: &AudioWindow, seconds: f64) -> (i64, Vec<f32>) {
        let hop = self.hop() as i64;
        let last = (window.end() - self.frame as i64).div_euclid(hop);
        let count = (seconds * f64::from(self.rate) / hop as f64)
            .ceil()
            .max(1.0) as i64;
        let first = last - count + 1;
        // Keep what overlaps; a jump (seek, loop) starts over.
        let cached_end = self.first + self.strengths.len() as i64;
        if first < self.first || first > cached_end {
            self.strengths.clear();
            self.first = first;
        }
        while self.first < first && !self.strengths.is_empty() {
            self.strengths.pop_front();
            self.first += 1;
        }
        if self.strengths.is_empty() {
            self.first = first;
        }
        let mut next = self.first + self.strengths.len() as i64;
        while next <= last {
            let before = match self.previous.take() {
                Some((k, s)) if k == next - 1 => s,
                _ => self.log_spectrum(window, next - 1),
            };
            let now = self.log_spectrum(window, next);
            let flux = now
                .iter()
                .zip(&before)
                .map(|(a, b)| (a - b).max(0.0))
                .sum::<f32>()
                / now.len() as f32;
            self.strengths.push_back(flux);
            self.previous = Some((next, now));
            next += 1;
        }
        // The cache may hold frames past `last` after a jump back within it.
        let take = (last - self.first + 1).clamp(0, self.strengths.len() as i64) as usize;
        (
            self.first,
            self.strengths.iter().take(take).copied().collect(),
        )
    }
}

/// The frames (indices into `strengths`) that are onsets: the largest within
/// [`PEAK_FRAMES`] on either side, above the mean of the [`MEAN_FRAMES`]
/// before by `threshold` times the window's largest strength. The last
/// [`PEAK_FRAMES`] frames cannot be judged yet.
pub fn onsets(strengths: &[f32], threshold: f32) -> Vec<usize> {
    let max = strengths.iter().fold(0.0f32, |m, &s| m.max(s));
    if max <= QUIET {
        return Vec::new();
    }
    let n = strengths.len();
    (0..n.saturating_sub(PEAK_FRAMES))
        .filter(|&i| {
            let s = strengths[i];
            let around = &strengths[i.saturating_sub(PEAK_FRAMES)..=i + PEAK_FRAMES];
            // Ties go to the first frame of a plateau.
            let leads = around.iter().all(|&v| v <= s)
                && strengths[i.saturating_sub(PEAK_FRAMES)..i]
                    .iter()
                    .all(|&v| v < s);
            let before = &strengths[i.saturating_sub(MEAN_FRAMES)..i];
            let mean = if before.is_empty() {
                0.0
            } else {
                before.iter().sum::<f32>() / before.len() as f32
            };
            leads && s > QUIET && s > mean + threshold * max
        })
        .collect()
}

/// The tempo in beats per minute between `min_bpm` and `max_bpm` that best
/// fits `strengths` (frames `hop_seconds` apart): the lag of the highest
/// autocorrelation, refined between frames. `None` without a periodic signal.
pub fn tempo(strengths: &[f32], hop_seconds: f64, min_bpm: f32, max_bpm: f32) -> Option<f32> {
    let (lo, hi) = (min_bpm.min(max_bpm).max(1.0), max_bpm.max(min_bpm).max(1.0));
    let shortest = (60.0 / f64::from(hi) / hop_seconds).floor().max(1.0) as usize;
    let longest = (60.0 / f64::from(lo) / hop_seconds).ceil() as usize;
    if strengths.len() < longest + 2 {
        return None;
    }
    if strengths.iter().all(|&s| s <= QUIET) {
        return None;
    }
    let mean = strengths.iter().sum::<f32>() / strengths.len() as f32;
    let x: Vec<f32> = strengths.iter().map(|s| s - mean).collect();
    // Unnormalised sums favour the shorter of two lags that both fit (the
    // beat over the bar), as they add up more frames.
    let acf = |lag: usize| -> f32 { x.iter().zip(&x[lag..]).map(|(a, b)| a * b).sum() };
    let (best, value) = (shortest..=longest)
        .map(|l| (l, acf(l)))
        .max_by(|a, b| a.1.total_cmp(&b.1))?;
    // Less than a tenth of the signal's own energy repeating is no beat.
    if value <= 0.1 * acf(0) {
        return None;
    }
    let (a, b, c) = (acf(best.saturating_sub(1).max(1)), value, acf(best + 1));
    let bend = a - 2.0 * b + c;
    let shift = if bend < 0.0 {
        (0.5 * (a - c) / bend).clamp(-0.5, 0.5)
    } else {
        0.0
    };
    let lag = best as f64 + f64::from(shift);
    Some((60.0 / (lag * hop_seconds)) as f32)
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use super::*;
    use crate::tones::{clicks, sine};

    #[test]
    fn a_120_bpm_click_track_gives_120_bpm_and_its_clicks_as_onsets() {
        let rate = 22050;
        let signal: Arc<[f32]> = Arc::from(clicks(120.0, rate, 6.0));
        let window = AudioWindow::new(signal.clone(), rate, signal.len() as i64, false);
        let mut tracker = OnsetTracker::new(rate);
        assert_eq!(tracker.hop(), 256);
        let (first, strengths) = tracker.strengths(&window, 6.0);
        let bpm = tempo(&strengths, tracker.hop_seconds(), 60.0, 180.0).expect("a tempo");
        assert!((bpm - 120.0).abs() < 1.0, "{bpm}");
        let found = onsets(&strengths, 0.3);
        // A click every half second, each found once, near its time.
        assert!((11..=12).contains(&found.len()), "{found:?}");
        let mut beats = Vec::new();
        for &i in &found {
            // The frame's centre, in seconds.
            let end = tracker.frame_end(first + i as i64) as f64 / f64::from(rate);
            let centre = end - 0.5 * tracker.frame as f64 / f64::from(rate);
            let beat = (centre / 0.5).round();
            assert!((centre - 0.5 * beat).abs() < 0.03, "onset at {centre}s");
            beats.push(beat as i64);
        }
        assert!(beats.windows(2).all(|w| w[1] == w[0] + 1), "{beats:?}");
    }

    #[test]
    fn the_tracker_reuses_frames_and_matches_a_fresh_computation() {
        let rate = 8000;
        let signal: Arc<[f32]> = Arc::from(clicks(100.0, rate, 3.0));
        let at =
            |t: f64| AudioWindow::new(signal.clone(), rate, (t * f64::from(rate)) as i64, false);
        let mut stepped = OnsetTracker::new(rate);
        for k in 0..=30 {
            stepped.strengths(&at(1.0 + f64::from(k) / 30.0), 1.0);
        }
        let (i, a) = stepped.strengths(&at(2.0), 1.0);
        let (j, b) = OnsetTracker::new(rate).strengths(&at(2.0), 1.0);
        assert_eq!((i, a), (j, b));
    }

    #[test]
    fn a_steady_tone_has_no_tempo_and_no_onsets_after_it_starts() {
        let rate = 8000;
        let signal: Arc<[f32]> = Arc::from(sine(300.0, 0.5, rate, 4.0));
        let window = AudioWindow::new(signal, rate, 4 * 8000, false);
        let mut tracker = OnsetTracker::new(rate);
        // The last three seconds: the tone's start is outside.
        let (_, strengths) = tracker.strengths(&window, 3.0);
        assert!(onsets(&strengths, 0.3).is_empty());
        assert_eq!(tempo(&strengths, tracker.hop_seconds(), 60.0, 180.0), None);
    }
}
