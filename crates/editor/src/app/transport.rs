//! The patch's time as the editor runs it: its clock, playing or paused, a
//! single step asked for, and a fixed step in place of the wall clock's
//! (`play --fps`).

use spreadlight_graph::FrameClock;

pub(super) struct Transport {
    pub(super) clock: FrameClock,
    pub(super) playing: bool,
    /// One frame forward asked for while paused.
    pub(super) step: bool,
    /// Seconds the clock steps each frame instead of the wall clock's (`play --fps`).
    pub(super) fixed_step: Option<f64>,
}

impl Transport {
    pub(super) fn new(playing: bool) -> Self {
        Transport {
            clock: FrameClock::default(),
            playing,
            step: false,
            fixed_step: None,
        }
    }

    /// Move time on by `dt` seconds of wall clock (or the fixed step) when
    /// playing, by a 60th of a second when a step was asked for; the new
    /// clock when time moved.
    pub(super) fn advance(&mut self, dt: f64) -> Option<FrameClock> {
        let moved = if self.playing {
            self.clock.advance(self.fixed_step.unwrap_or(dt));
            true
        } else if self.step {
            self.clock.advance(1.0 / 60.0);
            true
        } else {
            false
        };
        self.step = false;
        moved.then_some(self.clock)
    }
}
