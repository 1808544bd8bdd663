//! Where a sequence's time goes, by stage (the `stages` object of `render
//! --json`'s `done` line; docs/sequences.md, "Frames in flight"): what the
//! main thread spends evaluating frames, waiting for a free writer and
//! renaming files, and what the writers spend per frame waiting for the
//! GPU's copy, taking it out of the mapped buffer, converting, compressing,
//! writing and syncing. So a run that misses its frame rate says which of
//! them holds it: a busy pool (encoding), a main thread that waits for
//! writers, a readback that waits for the GPU, or a disk.

use std::time::{Duration, Instant};

use serde_json::{Value, json};

/// One frame's time on the writer threads, summed over its outputs.
#[derive(Clone, Copy, Debug, Default)]
pub struct FrameStages {
    /// Blocked until the GPU had made the copies and mapped them.
    pub readback_wait: Duration,
    /// Taking the rows out of the mapped buffers (and averaging sub-frames).
    pub readback_copy: Duration,
    /// The pixels into the file's samples: 8-bit sRGB for PNG; halves laid
    /// out and ZIP's predictor for `--exr half` (summed over its blocks).
    pub convert: Duration,
    /// PNG's filter and deflate, ZIP's deflate (summed over the blocks,
    /// which run on rayon's threads), the EXR crate's float writer.
    pub compress: Duration,
    /// Creating and writing the temporary file (into the page cache).
    pub write: Duration,
    /// Syncing it to the disk, on a thread of its own (a writer goes on
    /// with the next frame meanwhile).
    pub sync: Duration,
    /// The writer thread's whole time on the frame (not the sync).
    pub busy: Duration,
}

/// The run's totals, reported as means per frame.
pub struct RunStages {
    threads: usize,
    /// Frames evaluated (not the preroll), and how many of them after the first.
    evaluated: u64,
    /// The main thread evaluating frames after the first (the first is the
    /// cold start, `cold_start` says where it went).
    evaluate: Duration,
    later_frames: u64,
    preroll: Duration,
    preroll_frames: u64,
    /// The main thread waiting for a writer to take a frame.
    submit_wait: Duration,
    /// The main thread renaming finished files into place.
    commit: Duration,
    writers: FrameStages,
    written: u64,
    /// When the first and the last frame were placed.
    first_placed: Option<Instant>,
    last_placed: Option<Instant>,
    /// From the first frame handed to a writer to the last one placed.
    first_submitted: Option<Instant>,
}

fn ms(d: Duration) -> f64 {
    d.as_secs_f64() * 1e3
}

impl RunStages {
    pub fn new(threads: usize) -> Self {
        RunStages {
            threads,
            evaluated: 0,
            evaluate: Duration::ZERO,
            later_frames: 0,
            preroll: Duration::ZERO,
            preroll_frames: 0,
            submit_wait: Duration::ZERO,
            commit: Duration::ZERO,
            writers: FrameStages::default(),
            written: 0,
            first_placed: None,
            last_placed: None,
            first_submitted: None,
        }
    }

    /// A frame evaluated in `took` (its copies started).
    pub fn evaluated(&mut self, took: Duration) {
        if self.evaluated > 0 {
            self.evaluate += took;
            self.later_frames += 1;
        }
        self.evaluated += 1;
    }

    pub fn prerolled(&mut self, frames: u64, took: Duration) {
        self.preroll += took;
        self.preroll_frames += frames;
    }

    /// A frame handed to the writers after waiting `waited` for one.
    pub fn submitted(&mut self, waited: Duration) {
        self.submit_wait += waited;
        self.first_submitted.get_or_insert_with(Instant::now);
    }

    /// A frame's turn: its files renamed in `took`; `stages`: its writers' times.
    pub fn placed(&mut self, written: bool, stages: &FrameStages, took: Duration) {
        self.commit += took;
        let w = &mut self.writers;
        w.readback_wait += stages.readback_wait;
        w.readback_copy += stages.readback_copy;
        w.convert += stages.convert;
        w.compress += stages.compress;
        w.write += stages.write;
        w.sync += stages.sync;
        w.busy += stages.busy;
        if written {
            self.written += 1;
            let now = Instant::now();
            self.first_placed.get_or_insert(now);
            self.last_placed = Some(now);
        }
    }

    /// The `stages` object: milliseconds as means per frame.
    pub fn json(&self) -> Value {
        let per = |d: Duration, n: u64| ms(d) / n.max(1) as f64;
        let frames = self.evaluated;
        let w = &self.writers;
        // Frames a second once the first was placed: the run's rate without its cold start.
        let steady = match (self.first_placed, self.last_placed) {
            (Some(first), Some(last)) if self.written > 1 && last > first => {
                Some((self.written - 1) as f64 / (last - first).as_secs_f64())
            }
            _ => None,
        };
        // The share of the writer threads' time they were busy, from the first frame handed to
        // them to the last placed: near 1, encoding is the bound; well under it, they wait.
        let utilization = match (self.first_submitted, self.last_placed) {
            (Some(first), Some(last)) if last > first => {
                Some(w.busy.as_secs_f64() / ((last - first).as_secs_f64() * self.threads as f64))
            }
            _ => None,
        };
        json!({
            "threads": self.threads,
            "frames": frames,
            "evaluate_ms": per(self.evaluate, self.later_frames),
            "preroll_frames": self.preroll_frames,
            "preroll_ms": ms(self.preroll),
            "submit_wait_ms": per(self.submit_wait, frames),
            "commit_ms": per(self.commit, frames),
            "readback_wait_ms": per(w.readback_wait, frames),
            "readback_copy_ms": per(w.readback_copy, frames),
            "convert_ms": per(w.convert, frames),
            "compress_ms": per(w.compress, frames),
            "write_ms": per(w.write, frames),
            "sync_ms": per(w.sync, frames),
            "writer_busy_ms": per(w.busy, frames),
            "writer_utilization": utilization,
            "fps_after_first": steady,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stages_are_means_per_frame_and_the_first_frame_is_the_cold_starts() {
        let mut run = RunStages::new(2);
        // The first frame's evaluation is the cold start's: left out of the mean.
        run.evaluated(Duration::from_millis(500));
        run.evaluated(Duration::from_millis(3));
        run.evaluated(Duration::from_millis(5));
        run.submitted(Duration::from_millis(6));
        let frame = FrameStages {
            readback_wait: Duration::from_millis(2),
            compress: Duration::from_millis(30),
            busy: Duration::from_millis(40),
            ..FrameStages::default()
        };
        for _ in 0..3 {
            run.placed(true, &frame, Duration::from_millis(1));
        }
        run.prerolled(4, Duration::from_millis(20));
        let json = run.json();
        let at = |key: &str| json[key].as_f64().unwrap_or(f64::NAN);
        let expected = [
            ("frames", 3.0),
            ("evaluate_ms", 4.0),
            ("submit_wait_ms", 2.0),
            ("commit_ms", 1.0),
            ("readback_wait_ms", 2.0),
            ("readback_copy_ms", 0.0),
            ("compress_ms", 30.0),
            ("writer_busy_ms", 40.0),
            ("sync_ms", 0.0),
            ("preroll_frames", 4.0),
            ("preroll_ms", 20.0),
        ];
        for (key, value) in expected {
            assert!((at(key) - value).abs() < 1e-9, "{key}: {}", json[key]);
        }
        assert_eq!(json["threads"], 2);
        assert!(json.get("fps_after_first").is_some());
    }
}
