//! Frame ranges: `0-239` or `17` on the command line, walked in steps of
//! `--step`, and where a run must start evaluating to render them
//! deterministically (the preroll before its first frame).

use std::fmt;
use std::str::FromStr;

/// The frames `first`, `first + step`, ... up to `last` (inclusive).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FrameRange {
    pub first: u64,
    pub last: u64,
    pub step: u64,
}

/// `A-B` (inclusive) or a single frame `A`, as `--frames` takes them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Span(pub u64, pub u64);

impl FromStr for Span {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        let number = |v: &str| {
            v.trim().parse::<u64>().map_err(|_| {
                format!("`{s}` is not a frame range: write FIRST-LAST (e.g. 0-239) or one frame")
            })
        };
        let (first, last) = match s.split_once('-') {
            Some((a, b)) => (number(a)?, number(b)?),
            None => (number(s)?, number(s)?),
        };
        if last < first {
            return Err(format!("`{s}`: the last frame comes before the first"));
        }
        Ok(Span(first, last))
    }
}

/// `--preroll`: a number of frames, or `all` (from frame 0).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Preroll {
    Frames(u64),
    /// Every frame before, from frame 0: what a run from the start evaluates.
    All,
}

impl Preroll {
    /// As [`FrameRange::start_for`] takes it: `All` is more steps than any frame has before it.
    pub fn frames(self) -> u64 {
        match self {
            Preroll::Frames(n) => n,
            Preroll::All => u64::MAX,
        }
    }
}

impl FromStr for Preroll {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        if s.trim().eq_ignore_ascii_case("all") {
            return Ok(Preroll::All);
        }
        s.trim()
            .parse()
            .map(Preroll::Frames)
            .map_err(|_| format!("`{s}` is not a preroll: write a number of frames or `all`"))
    }
}

impl fmt::Display for Preroll {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Preroll::Frames(n) => write!(f, "{n}"),
            Preroll::All => f.write_str("all"),
        }
    }
}

impl fmt::Display for FrameRange {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}-{}", self.first, self.last)?;
        if self.step > 1 {
            write!(f, " step {}", self.step)?;
        }
        Ok(())
    }
}

impl FrameRange {
    pub fn new(span: Span, step: u64) -> Result<Self, String> {
        if step == 0 {
            return Err("--step must be at least 1".to_owned());
        }
        Ok(FrameRange {
            first: span.0,
            last: span.1,
            step,
        })
    }

    /// Every frame of the range, in order.
    pub fn frames(&self) -> impl Iterator<Item = u64> + use<> {
        let FrameRange { first, last, step } = *self;
        (first..=last).step_by(usize::try_from(step).unwrap_or(usize::MAX))
    }

    pub fn len(&self) -> u64 {
        (self.last - self.first) / self.step + 1
    }

    /// The frame a run that must render `frame` starts evaluating at:
    /// `preroll` steps earlier (never before frame 0), so temporal effects and
    /// simulations have settled as they would have in a run from the start.
    pub fn start_for(&self, frame: u64, preroll: u64) -> u64 {
        // Whole steps back, so a chunk evaluates the frames a full run would.
        frame - preroll.min(frame / self.step) * self.step
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn range(s: &str, step: u64) -> FrameRange {
        FrameRange::new(s.parse().expect("span"), step).expect("range")
    }

    #[test]
    fn ranges_parse_and_walk_in_steps() {
        assert_eq!(range("0-239", 1).len(), 240);
        assert_eq!(range("17", 1).frames().collect::<Vec<_>>(), [17]);
        assert_eq!(range("0-10", 4).frames().collect::<Vec<_>>(), [0, 4, 8]);
        assert_eq!(range("0-10", 4).len(), 3);
        assert!("5-2".parse::<Span>().is_err());
        assert!("a-2".parse::<Span>().is_err());
        assert!(FrameRange::new(Span(0, 1), 0).is_err());
    }

    #[test]
    fn preroll_starts_earlier_on_the_same_grid_and_never_before_zero() {
        assert_eq!(range("0-100", 1).start_for(50, 8), 42);
        assert_eq!(range("0-100", 1).start_for(3, 8), 0);
        assert_eq!(range("0-100", 2).start_for(50, 4), 42);
        assert_eq!(range("10-100", 1).start_for(12, 0), 12);
        // All: from frame 0, or the first frame of the step's grid.
        let all = Preroll::All.frames();
        assert_eq!(range("0-100", 1).start_for(50, all), 0);
        assert_eq!(range("2-100", 3).start_for(50, all), 2);
        assert_eq!("all".parse::<Preroll>(), Ok(Preroll::All));
        assert_eq!("12".parse::<Preroll>(), Ok(Preroll::Frames(12)));
        assert!("-1".parse::<Preroll>().is_err());
    }
}
