//! [`AudioWindow`]: a mono signal up to a moment, what the analysis nodes
//! take. It shares the samples (a decoded file, a snapshot of a live input)
//! and says where "now" is in them, so passing it along a link copies nothing.

use std::sync::Arc;

/// The samples of a mono signal before `end`: the sound heard up to now.
///
/// Positions are absolute sample indices on the signal's own timeline
/// (sample 0 is a file's start, or the first sample a live input
/// delivered), so analyses can remember work by position across frames.
#[derive(Clone, Debug)]
pub struct AudioWindow {
    samples: Arc<[f32]>,
    rate: u32,
    /// The absolute index of `samples[0]` (a live input's snapshot starts late).
    origin: i64,
    /// The absolute index of "now", which may lie before the start or past
    /// the end of `samples` (silence there), or wrap when `looping`.
    end: i64,
    looping: bool,
    /// How far "now" moved since the previous frame, in samples: what an
    /// analysis counts as this frame's news (an onset in it).
    step: i64,
}

impl AudioWindow {
    /// The signal `samples` at `rate` Hz, heard up to sample `end`. When
    /// `looping`, the signal repeats in both directions instead of falling silent.
    pub fn new(samples: Arc<[f32]>, rate: u32, end: i64, looping: bool) -> Self {
        AudioWindow {
            samples,
            rate: rate.max(1),
            origin: 0,
            end,
            looping,
            step: 0,
        }
    }

    /// The same window, saying that "now" moved `step` samples since the previous frame.
    pub fn with_step(self, step: i64) -> Self {
        AudioWindow { step, ..self }
    }

    /// How far "now" moved since the previous frame, in samples.
    pub fn step(&self) -> i64 {
        self.step
    }

    /// A live input's snapshot: `samples` are the latest, ending "now", and
    /// `end` samples have arrived since the input opened.
    pub fn live(samples: Arc<[f32]>, rate: u32, end: i64) -> Self {
        AudioWindow {
            origin: end - samples.len() as i64,
            ..AudioWindow::new(samples, rate, end, false)
        }
    }

    /// The absolute sample index of "now".
    pub fn end(&self) -> i64 {
        self.end
    }

    pub fn rate(&self) -> u32 {
        self.rate
    }

    /// "Now", in seconds from the signal's start.
    pub fn time(&self) -> f64 {
        self.end as f64 / f64::from(self.rate)
    }

    /// How many samples `seconds` are at this rate (at least one).
    pub fn samples_in(&self, seconds: f64) -> usize {
        ((seconds.max(0.0) * f64::from(self.rate)).round() as usize).max(1)
    }

    /// The last `n` samples before "now" into `out` (cleared first), oldest
    /// first; silence where the signal has none.
    pub fn last_into(&self, n: usize, out: &mut Vec<f32>) {
        self.read_into(self.end - n as i64, n, out);
    }

    /// `n` samples from absolute index `start` into `out` (cleared first);
    /// silence where the signal has none.
    pub fn read_into(&self, start: i64, n: usize, out: &mut Vec<f32>) {
        out.clear();
        out.reserve(n);
        let len = self.samples.len() as i64;
        let end = start + n as i64;
        if self.looping && len > 0 {
            out.extend(
                (start..end).map(|i| self.samples[(i - self.origin).rem_euclid(len) as usize]),
            );
            return;
        }
        // The part inside the signal is one copy; silence pads either side.
        let from = (start - self.origin).clamp(0, len);
        let to = (end - self.origin).clamp(0, len);
        out.resize(
            (from + self.origin - start).clamp(0, n as i64) as usize,
            0.0,
        );
        if to > from {
            out.extend_from_slice(&self.samples[from as usize..to as usize]);
        }
        out.resize(n, 0.0);
    }

    /// The last `n` samples before "now", as a new vector.
    pub fn last(&self, n: usize) -> Vec<f32> {
        let mut out = Vec::new();
        self.last_into(n, &mut out);
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn windows_pad_with_silence_outside_the_signal_and_wrap_when_looping() {
        let samples: Arc<[f32]> = Arc::from(vec![1.0, 2.0, 3.0, 4.0]);
        let w = AudioWindow::new(samples.clone(), 10, 2, false);
        assert_eq!(w.last(4), [0.0, 0.0, 1.0, 2.0]);
        let past = AudioWindow::new(samples.clone(), 10, 6, false);
        assert_eq!(past.last(4), [3.0, 4.0, 0.0, 0.0]);
        let far = AudioWindow::new(samples.clone(), 10, 100, false);
        assert_eq!(far.last(2), [0.0, 0.0]);
        let looped = AudioWindow::new(samples, 10, 6, true);
        assert_eq!(looped.last(4), [3.0, 4.0, 1.0, 2.0]);
        assert!((looped.time() - 0.6).abs() < 1e-9);
        // A live snapshot of the latest four of ten samples received.
        let live = AudioWindow::live(Arc::from(vec![7.0, 8.0, 9.0, 10.0]), 10, 10);
        assert_eq!(live.last(3), [8.0, 9.0, 10.0]);
        let mut out = Vec::new();
        live.read_into(5, 4, &mut out);
        assert_eq!(out, [0.0, 7.0, 8.0, 9.0]);
    }
}
