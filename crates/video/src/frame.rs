//! A decoded picture and what a source knows about its frames.

/// A decoded frame: 8-bit RGBA, rows packed, straight alpha.
#[derive(Clone, Debug, PartialEq)]
pub struct Frame {
    /// Its number in the source, from 0.
    pub index: u64,
    pub width: u32,
    pub height: u32,
    pub rgba: Vec<u8>,
}

/// A source's frames: size, rate and count.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VideoInfo {
    pub width: u32,
    pub height: u32,
    /// Frames a second.
    pub fps: f64,
    /// How many frames it has.
    pub frames: u64,
}

impl VideoInfo {
    /// Seconds it lasts.
    pub fn duration(&self) -> f64 {
        self.frames as f64 / self.fps
    }

    /// The frame shown at `time` seconds: the last one starting at or before
    /// it, held at the ends (before 0 the first, past the end the last), or
    /// wrapped around when `looping`. A small tolerance keeps `n / fps`
    /// computed in floating point on frame `n`, not `n - 1`.
    pub fn frame_at(&self, time: f64, looping: bool) -> u64 {
        let frames = self.frames.max(1);
        let at = (time * self.fps + 1e-6).floor();
        if !at.is_finite() {
            return 0;
        }
        if looping {
            at.rem_euclid(frames as f64) as u64
        } else {
            at.clamp(0.0, (frames - 1) as f64) as u64
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_frame_at_a_time_is_exact_held_at_the_ends_or_wrapped() {
        let info = VideoInfo {
            width: 1,
            height: 1,
            fps: 30.0,
            frames: 90,
        };
        for n in 0..90u64 {
            assert_eq!(info.frame_at(n as f64 / 30.0, false), n);
        }
        assert_eq!(info.frame_at(-1.0, false), 0);
        assert_eq!(info.frame_at(10.0, false), 89);
        assert_eq!(info.frame_at(3.0 + 1.0 / 30.0, true), 1);
        assert_eq!(info.frame_at(-1.0 / 30.0, true), 89);
        assert_eq!(info.frame_at(f64::NAN, true), 0);
        assert!((info.duration() - 3.0).abs() < 1e-12);
    }
}
