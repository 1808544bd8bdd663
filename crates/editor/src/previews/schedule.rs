//! Which thumbnails the worker refreshes in a frame, so that previews do not
//! slow the patch.
//!
//! A thumbnail once cost the patch more than its scaling: its texture was
//! requested from the first viewport's frame graph, so the pass that wrote
//! it was neither culled nor merged into the next one and its texture was
//! kept from later passes and histories. Now a thumbnail watches its texture
//! (engine.rs, `FrameGraph::watch`), which leaves the patch's frame as it
//! is; what is left is its scaling, on lavapipe CPU work beside the patch's
//! own passes.
//!
//! So, per frame of a playing patch:
//! - a thumbnail whose source is the very image it already shows (the same
//!   recipe at the same frame size: its node was not evaluated again) is
//!   skipped: it costs nothing;
//! - the hovered (large) preview and a thumbnail under the pointer are live:
//!   refreshed every frame;
//! - the rest share a budget, [`BUDGET_SHARE`] of the patch's measured frame
//!   time, spent on one thumbnail after another, the longest unrefreshed
//!   first (round-robin). Each thumbnail's cost is measured too: the frame
//!   time with `n` thumbnails against the frame time with none, over `n`. On
//!   a GPU that is every thumbnail every frame; on lavapipe every few frames.
//!
//! A paused patch has no frame rate to keep: every changed thumbnail is
//! refreshed at once. Off-screen nodes ask for nothing (the canvas), so
//! they are never candidates.

use std::collections::HashMap;

use super::PreviewKey;

/// The share of the patch's frame time the thumbnails may add (the issue
/// allows a rise under 5%).
pub const BUDGET_SHARE: f64 = 0.03;

/// A frame that refreshed no thumbnail is made at least this often while
/// thumbnails are due, to measure the patch's frame time without them.
pub const BASE_EVERY: u64 = 60;

/// Weight of a new sample in the running frame-time and cost averages.
const SMOOTHING: f64 = 0.15;

/// One preview asked for this frame.
#[derive(Clone, Debug, PartialEq)]
pub struct Candidate<S> {
    pub key: PreviewKey,
    /// The image it shows, as far as telling an unchanged one goes (`None`:
    /// unknown, always refreshed when its turn comes).
    pub source: Option<S>,
    /// The large preview or a thumbnail under the pointer: refreshed every frame.
    pub live: bool,
}

/// When a preview was last refreshed and from which source.
struct Shown<S> {
    frame: u64,
    source: Option<S>,
}

/// The thumbnails' round-robin and budget. `S` identifies a source image
/// (the worker's holds the recipe, so an equal one is the same image).
pub struct Scheduler<S> {
    shown: HashMap<PreviewKey, Shown<S>>,
    frame: u64,
    /// Milliseconds of budget saved up (at most one frame's, or one thumbnail's).
    tokens: f64,
    /// The patch's frame time with no thumbnail refreshed, averaged.
    base_ms: Option<f64>,
    /// One thumbnail's cost, averaged.
    thumb_ms: Option<f64>,
    /// The frame of the last measurement with no thumbnail refreshed.
    last_base: u64,
    /// Thumbnails whose source changed and that the last pick left for later.
    pending: usize,
}

impl<S> Default for Scheduler<S> {
    fn default() -> Self {
        Scheduler {
            shown: HashMap::new(),
            frame: 0,
            tokens: 0.0,
            base_ms: None,
            thumb_ms: None,
            last_base: 0,
            pending: 0,
        }
    }
}

/// What the scheduler has measured, for `--measure-frames`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Measured {
    /// The patch's frame with no thumbnail refreshed, milliseconds.
    pub base_ms: Option<f64>,
    /// One thumbnail's cost, milliseconds.
    pub thumb_ms: Option<f64>,
}

impl<S: PartialEq> Scheduler<S> {
    /// Which of `candidates` to refresh this frame (one flag each, in order).
    /// `budgeted`: the patch is playing, so its frame time is kept.
    pub fn pick(&mut self, candidates: &[Candidate<S>], budgeted: bool) -> Vec<bool> {
        self.frame += 1;
        let mut refresh = vec![false; candidates.len()];
        // The changed thumbnails, longest unrefreshed (or never shown) first.
        let mut due: Vec<(u64, usize)> = Vec::new();
        for (i, c) in candidates.iter().enumerate() {
            let shown = self.shown.get(&c.key);
            let unchanged = c.source.is_some()
                && shown.is_some_and(|s| s.source.is_some() && s.source == c.source);
            if c.live || shown.is_none() {
                // A thumbnail coming on screen shows at once.
                refresh[i] = true;
            } else if !unchanged {
                due.push((shown.map_or(0, |s| s.frame), i));
            }
        }
        due.sort_by(|a, b| {
            a.0.cmp(&b.0)
                .then_with(|| candidates[a.1].key.cmp(&candidates[b.1].key))
        });
        let mut taken = 0;
        match (budgeted, self.base_ms, self.thumb_ms) {
            // Paused: all of them.
            (false, _, _) => taken = due.len(),
            // The frame alone is measured first, and now and then.
            (true, None, _) => {}
            (true, Some(_), _) if self.frame - self.last_base >= BASE_EVERY => {}
            // The cost of one is not known yet: one, to measure it.
            (true, Some(_), None) => taken = due.len().min(1),
            (true, Some(base), Some(cost)) => {
                let per_frame = BUDGET_SHARE * base;
                self.tokens = (self.tokens + per_frame).min(per_frame.max(cost));
                while taken < due.len() && self.tokens >= cost {
                    self.tokens -= cost;
                    taken += 1;
                }
            }
        }
        for &(_, i) in &due[..taken] {
            refresh[i] = true;
        }
        self.pending = due.len() - taken;
        refresh
    }

    /// `key` was refreshed from `source` this frame.
    pub fn refreshed(&mut self, key: &PreviewKey, source: Option<S>) {
        self.shown.insert(
            key.clone(),
            Shown {
                frame: self.frame,
                source,
            },
        );
    }

    /// The frame took `ms` milliseconds with `thumbnails` (not live)
    /// refreshed. Only frames of a playing patch are measured.
    pub fn measured(&mut self, ms: f64, thumbnails: usize) {
        let average =
            |old: Option<f64>, new: f64| Some(old.map_or(new, |o| o + SMOOTHING * (new - o)));
        if thumbnails == 0 {
            self.base_ms = average(self.base_ms, ms);
            self.last_base = self.frame;
        } else if let Some(base) = self.base_ms {
            // A noisy machine may make one sample negative: the average stays >= 0.
            let one = (ms - base) / thumbnails as f64;
            self.thumb_ms = average(self.thumb_ms, one).map(|c| c.max(0.0));
        }
    }

    /// Changed thumbnails left for a later frame by the last pick.
    pub fn pending(&self) -> usize {
        self.pending
    }

    /// Forget a preview no longer kept.
    pub fn forget(&mut self, key: &PreviewKey) {
        self.shown.remove(key);
    }

    pub fn measurements(&self) -> Measured {
        Measured {
            base_ms: self.base_ms,
            thumb_ms: self.thumb_ms,
        }
    }
}
