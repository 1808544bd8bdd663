//! Submitting a frame on a thread of its own (`SPREADLIGHT_SUBMIT=thread`),
//! so the recording thread returns as soon as the last pass has recorded.
//!
//! The frame's tail (docs/benchmarks.md, "cpu22"): collecting the runs the
//! finishing thread encoded (waiting for the one it is on), finishing the
//! last run's encoder, and the queue's `submit` (wgpu's resource tracking
//! and the driver's submission) take 0.3-0.45 ms of a frame on the H200, a
//! third of it. Handed here, they run while the recording thread returns
//! the frame and evaluates the next one's patch. Frames stay in order: the
//! next frame's first use of the queue (a uniform written, a geometry
//! node's submission, a readback's copy) and the start of its recording
//! wait until this frame is submitted (frame_queue.rs), so nothing of the
//! next frame can reach the GPU, or this frame's submission, first. A frame
//! whose timestamps are read back waits for its own submission.
//!
//! What a submission finds out comes back as an [`Outcome`]: a frame that
//! failed validation is dropped here as it is inline, and its error reaches
//! the report of the frame that waited for it (its own when timed), or the
//! last report when a host reads it after the submission was made
//! (`Executor::last_errors`). The thread's time per frame is reported
//! ([`FrameReport::submission_thread_ms`](crate::report::FrameReport)), so
//! that work moved off the recording thread is not taken for work removed.

use std::collections::VecDeque;
use std::sync::mpsc::{Sender, channel};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;

use super::finisher::Finishing;
use crate::context::GpuContext;
use crate::frame_queue::Owed;

/// The environment variable that picks where frames are submitted:
/// `inline`, `thread` or `auto`.
pub const SUBMIT_VAR: &str = "SPREADLIGHT_SUBMIT";

/// Where a frame's tail (finishing the last encoders, the queue's submit) runs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Submission {
    /// On the recording thread, before the frame returns.
    Inline,
    /// On a submission thread, while the recording thread goes on.
    Thread,
    /// `Thread` on a GPU, `Inline` on a CPU adapter: there the GPU's work
    /// is CPU work too (lavapipe renders inside the submission), and a
    /// thread more only competes for the same cores. The default: on the
    /// H200 the thread took post.ron's recording thread from 0.79-0.82 to
    /// 0.50-0.65 ms a frame at the same frame time (docs/benchmarks.md,
    /// "Session 22 on the H200").
    #[default]
    Auto,
}

impl Submission {
    pub fn parse(text: &str) -> Option<Submission> {
        match text.trim().to_ascii_lowercase().as_str() {
            "inline" => Some(Submission::Inline),
            "thread" => Some(Submission::Thread),
            "auto" => Some(Submission::Auto),
            _ => None,
        }
    }

    /// What [`SUBMIT_VAR`] says, `Auto` when unset; an error naming the
    /// variable for a value it does not know (a benchmark must not measure
    /// another setting than the one asked for).
    pub fn from_env() -> Result<Submission, String> {
        crate::setting::from_env(
            SUBMIT_VAR,
            Submission::parse,
            "`inline`, `thread` or `auto`",
        )
    }

    /// The setting taken on an adapter of `class`: `Auto` resolved.
    pub fn on(self, class: crate::adapter_class::AdapterClass) -> Submission {
        use crate::adapter_class::AdapterClass;
        match (self, class) {
            (Submission::Auto, AdapterClass::Gpu) => Submission::Thread,
            (Submission::Auto, AdapterClass::Cpu) => Submission::Inline,
            (submission, _) => submission,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Submission::Inline => "inline",
            Submission::Thread => "thread",
            Submission::Auto => "auto",
        }
    }
}

/// One frame's tail, handed to the submission thread.
pub(crate) struct Job {
    /// The runs handed to the finishing thread (batched), collected first.
    pub finishing: Option<Finishing>,
    /// The last run's encoder (batched), finished here in a scope of this thread's.
    pub last: Option<wgpu::CommandEncoder>,
    /// Buffers finished on the recording thread (isolated: one a pass).
    pub finished: Vec<wgpu::CommandBuffer>,
    /// A validation error the recording thread's frame scope caught (batched).
    pub recording_error: Option<wgpu::Error>,
    /// The host's own commands (`execute_on_then`), after the frame's.
    pub host: Vec<wgpu::CommandBuffer>,
    /// Keep at most this many submissions unfinished (frames in flight,
    /// untimed frames); None for a frame that waits for the GPU anyway.
    pub throttle: Option<usize>,
}

/// What submitting a frame found out.
#[derive(Debug, Default)]
pub(crate) struct Outcome {
    /// The thread's time on the frame, in milliseconds.
    pub thread_ms: f64,
    /// Of it, the queue's `submit` alone.
    pub queue_submit_ms: f64,
    /// The frame's errors (without an owner: a batched frame's are the frame's).
    pub errors: Vec<String>,
    /// The frame's passes were not submitted (validation failed, or
    /// finishing panicked): their timestamps were not written.
    pub dropped: bool,
    /// Validation failed: passes record separately from now on, as inline.
    pub validation_failed: bool,
    /// Counters for the report the outcome lands in.
    pub counters: Vec<(&'static str, u64)>,
    /// The queue's submission (None if the thread panicked).
    pub submission: Option<wgpu::SubmissionIndex>,
}

/// The renderer's submission thread, started by the first frame sent to it.
pub(crate) struct Submitter {
    owed: Arc<Owed>,
    thread: Mutex<Option<(Sender<Job>, JoinHandle<()>)>>,
    /// The latest outcome nobody has taken yet.
    outcome: Arc<Mutex<Option<Outcome>>>,
}

impl Submitter {
    pub fn new(gpu: &GpuContext) -> Self {
        Submitter {
            owed: gpu.queue.owed().clone(),
            thread: Mutex::new(None),
            outcome: Arc::default(),
        }
    }

    /// Hand `job` to the submission thread (started if it is not running);
    /// the job back where no thread can be started.
    pub fn send(&self, gpu: &GpuContext, job: Job) -> Option<Job> {
        let mut thread = self.thread.lock().unwrap_or_else(|e| e.into_inner());
        if thread.is_none() {
            *thread = spawn(gpu.clone(), self.outcome.clone());
        }
        let Some((sender, _)) = thread.as_ref() else {
            return Some(job);
        };
        // Owed before it is sent: the thread pays it once submitted.
        self.owed.owe();
        match sender.send(job) {
            Ok(()) => None,
            // The thread ended (it cannot while the sender lives): nothing is owed.
            Err(unsent) => {
                self.owed.paid();
                Some(unsent.0)
            }
        }
    }

    /// Wait for the frame submission owed, if any.
    pub fn wait(&self) {
        self.owed.wait();
    }

    /// Whether a frame's submission is owed now.
    pub fn is_owed(&self) -> bool {
        self.owed.is_owed()
    }

    /// The time waited for owed submissions so far (all threads).
    pub fn waited(&self) -> std::time::Duration {
        self.owed.waited()
    }

    /// The latest outcome, taken (after [`Submitter::wait`] it is the last frame's).
    pub fn take(&self) -> Option<Outcome> {
        self.outcome
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .take()
    }

    /// The errors of the latest outcome, taken, leaving the rest of it for
    /// the next frame; and whether its validation failed.
    pub fn take_errors(&self) -> (Vec<String>, bool) {
        let mut outcome = self.outcome.lock().unwrap_or_else(|e| e.into_inner());
        match outcome.as_mut() {
            Some(o) => (
                std::mem::take(&mut o.errors),
                std::mem::take(&mut o.validation_failed),
            ),
            None => (Vec::new(), false),
        }
    }
}

impl Drop for Submitter {
    /// The frames sent are submitted first (a host that may keep the
    /// submission gate closed opens it for good before dropping the
    /// renderer: submission_gate.rs), then the thread ends.
    fn drop(&mut self) {
        let thread = self.thread.get_mut().unwrap_or_else(|e| e.into_inner());
        if let Some((sender, handle)) = thread.take() {
            drop(sender);
            let _ = handle.join();
        }
    }
}

fn spawn(
    gpu: GpuContext,
    slot: Arc<Mutex<Option<Outcome>>>,
) -> Option<(Sender<Job>, JoinHandle<()>)> {
    let (sender, jobs) = channel::<Job>();
    let handle = std::thread::Builder::new()
        .name("spreadlight submit".into())
        .spawn(move || {
            let mut in_flight = VecDeque::new();
            for job in jobs {
                let outcome = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                    submit(&gpu, job, &mut in_flight)
                }))
                .unwrap_or_else(|_| Outcome {
                    errors: vec!["submitting the frame panicked; the frame was dropped".to_owned()],
                    dropped: true,
                    ..Default::default()
                });
                {
                    let mut slot = slot.lock().unwrap_or_else(|e| e.into_inner());
                    // An outcome nobody took (the host read no report): its errors stay.
                    let mut outcome = outcome;
                    if let Some(earlier) = slot.take() {
                        let mut errors = earlier.errors;
                        errors.append(&mut outcome.errors);
                        outcome.errors = errors;
                        outcome.validation_failed |= earlier.validation_failed;
                    }
                    *slot = Some(outcome);
                }
                // After the outcome is in place: whoever waited finds it.
                gpu.queue.owed().paid();
            }
        })
        .ok()?;
    Some((sender, handle))
}

/// The frame's tail, as execute.rs runs it inline (where no thread can
/// start, execute.rs runs it here).
pub(crate) fn submit(
    gpu: &GpuContext,
    job: Job,
    in_flight: &mut VecDeque<wgpu::SubmissionIndex>,
) -> Outcome {
    let started = std::time::Instant::now();
    let mut outcome = Outcome::default();
    let Job {
        finishing,
        last,
        mut finished,
        recording_error,
        host,
        throttle,
    } = job;
    if let Some(finishing) = finishing {
        let collected = finishing.collect();
        if collected.taken_back > 0 {
            outcome
                .counters
                .push(("command encoders taken back", collected.taken_back as u64));
        }
        // The last run, in a scope of this thread's: errors are per thread.
        let last = last.map(|encoder| {
            let scope = gpu.device.push_error_scope(wgpu::ErrorFilter::Validation);
            let buffer = encoder.finish();
            (buffer, pollster::block_on(scope.pop()))
        });
        let failed = match collected.finished {
            Some(runs) => {
                let mut first = None;
                for (buffer, error) in runs {
                    finished.push(buffer);
                    first = first.or(error);
                }
                let mut here = None;
                if let Some((buffer, error)) = last {
                    finished.push(buffer);
                    here = error;
                }
                // The runs handed over come first: their errors are the earlier.
                first.or(recording_error).or(here).map(|e| {
                    outcome.validation_failed = true;
                    format!(
                        "the frame failed validation and was dropped; passes record separately from now on: {e}"
                    )
                })
            }
            None => Some(
                "finishing a command encoder of the frame panicked; the frame was dropped"
                    .to_owned(),
            ),
        };
        if let Some(message) = failed {
            outcome.errors.push(message);
            outcome.dropped = true;
            finished.clear();
        }
    }
    if !finished.is_empty() {
        outcome
            .counters
            .push(("command buffers", finished.len() as u64));
    }
    finished.extend(host);
    let submitting = std::time::Instant::now();
    let submission = gpu.submit_unordered(finished);
    outcome.queue_submit_ms = submitting.elapsed().as_secs_f64() * 1e3;
    outcome.thread_ms = started.elapsed().as_secs_f64() * 1e3;
    outcome.submission = Some(submission.clone());
    // Frames in flight: at most `frames` unfinished, waited for here (the
    // recording thread waits for this thread at its next frame instead).
    if let Some(frames) = throttle {
        in_flight.push_back(submission);
        while in_flight.len() > frames {
            if let Some(oldest) = in_flight.pop_front()
                && let Err(e) = gpu.device.poll(wgpu::PollType::Wait {
                    submission_index: Some(oldest),
                    timeout: None,
                })
            {
                outcome
                    .errors
                    .push(format!("waiting for a frame in flight: {e}"));
            }
        }
    }
    outcome
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_setting_parses_and_auto_takes_the_thread_on_a_gpu_only() {
        use crate::adapter_class::AdapterClass::{Cpu, Gpu};
        assert_eq!(Submission::parse(" Thread"), Some(Submission::Thread));
        assert_eq!(Submission::parse("inline"), Some(Submission::Inline));
        assert_eq!(Submission::parse("auto"), Some(Submission::Auto));
        assert_eq!(Submission::parse("later"), None);
        assert_eq!(Submission::default(), Submission::Auto);
        assert_eq!(Submission::Auto.on(Gpu), Submission::Thread);
        assert_eq!(Submission::Auto.on(Cpu), Submission::Inline);
        for s in [Submission::Inline, Submission::Thread] {
            assert_eq!((s.on(Gpu), s.on(Cpu)), (s, s));
            assert_eq!(Submission::parse(s.name()), Some(s));
        }
    }
}
