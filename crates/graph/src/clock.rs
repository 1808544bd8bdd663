//! The frame clock: frame number, time and delta. Headless runs step it by a
//! fixed delta, so evaluation is deterministic; the editor steps it by wall time.

use serde::Serialize;

#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct FrameClock {
    /// Frames evaluated so far; 0 during the first.
    pub frame: u64,
    /// Seconds since the start.
    pub time: f64,
    /// Seconds since the previous frame (0 on the first).
    pub delta: f64,
}

impl Default for FrameClock {
    fn default() -> Self {
        FrameClock {
            frame: 0,
            time: 0.0,
            delta: 0.0,
        }
    }
}

impl FrameClock {
    /// Move to the next frame, `delta` seconds later. Negative or non-finite
    /// deltas (a clock that jumped back) count as zero, so time never runs backwards.
    pub fn advance(&mut self, delta: f64) {
        let delta = if delta.is_finite() && delta > 0.0 {
            delta
        } else {
            0.0
        };
        self.frame += 1;
        self.time += delta;
        self.delta = delta;
    }
}

impl FrameClock {
    /// The clock of frame `frame` of a run at a fixed `fps`: time is computed,
    /// not summed, so frame 10,000 is as exact as frame 1.
    pub fn fixed(frame: u64, fps: f64) -> Self {
        let delta = if frame == 0 { 0.0 } else { 1.0 / fps };
        FrameClock {
            frame,
            time: frame as f64 / fps,
            delta,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fixed_steps_are_exact_and_time_never_runs_back() {
        let mut c = FrameClock::default();
        c.advance(0.5);
        c.advance(f64::NAN);
        c.advance(-1.0);
        c.advance(0.25);
        assert_eq!(
            c,
            FrameClock {
                frame: 4,
                time: 0.75,
                delta: 0.25
            }
        );
    }
}
