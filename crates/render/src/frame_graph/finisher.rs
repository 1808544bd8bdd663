//! Finishing a batched frame's command encoders off the recording thread.
//!
//! wgpu 30 records a pass's commands into a list and encodes them for the
//! backend only at `CommandEncoder::finish`: a fifth to a quarter of the
//! recording thread in the profiles of docs/benchmarks.md. A batched frame is
//! therefore recorded into [`FRAME_CHUNKS`] encoders, each holding a run of
//! consecutive passes; every one but the last is handed to one thread the
//! renderer keeps, which finishes it while the recording thread records the
//! next run. One the thread has not begun when the recording is done (it got
//! no core in time: a loaded machine) is taken back and finished where it was
//! recorded, so the frame is never later than with no thread.
//!
//! Error scopes are per thread in wgpu 30 (an error is caught by the scopes
//! of the thread that raised it), and recording errors surface at `finish`:
//! the finishing thread opens its own scope around each `finish` and hands
//! back what it caught, so a frame that fails validation is still dropped.

use std::collections::VecDeque;
use std::sync::{Arc, Condvar, Mutex, MutexGuard};
use std::thread::JoinHandle;

/// Encoders a batched frame is recorded into (at most: a frame of fewer
/// than `2 * FRAME_CHUNKS - 1` passes may have fewer). Each one more lets
/// wgpu encode another part of the frame beside the recording, and costs a
/// command buffer at submit, where wgpu may put a transition buffer before
/// it, and a hand-over to the finishing thread.
pub const FRAME_CHUNKS: usize = 3;

/// Which of the frame's encoders the pass recorded at `step` of `steps` goes
/// into. The last run, finished on the recording thread after it has
/// recorded everything, holds half as many passes as each run before it:
/// with three, the finishing thread encodes four fifths of the frame. (It
/// keeps up: encoding a run took about half the time recording it took in
/// session 11's profile and timers, docs/benchmarks.md.)
pub(crate) fn chunk_of(step: usize, steps: usize) -> usize {
    // Two units a run before the last, one for the last.
    let units = 2 * FRAME_CHUNKS - 1;
    (step * units / steps.max(1) / 2).min(FRAME_CHUNKS - 1)
}

/// A finished encoder and the validation error its `finish` raised.
pub(crate) type Finished = (wgpu::CommandBuffer, Option<wgpu::Error>);

/// The renderer's finishing thread, started by the first batched frame.
pub(crate) struct Finisher {
    device: wgpu::Device,
    worker: Mutex<Option<Worker>>,
}

struct Worker {
    shared: Arc<Shared>,
    thread: JoinHandle<()>,
}

/// What the recording thread and the finishing thread share.
#[derive(Default)]
struct Shared {
    state: Mutex<State>,
    /// Jobs queued, or the queue closed: for the finishing thread.
    queued: Condvar,
    /// A job finished: for the recording thread.
    finished: Condvar,
}

#[derive(Default)]
struct State {
    /// Encoders not yet begun, with their place in the frame.
    jobs: VecDeque<(usize, wgpu::CommandEncoder)>,
    /// This frame's results by place.
    results: Vec<Slot>,
    /// Jobs the finishing thread is on.
    busy: usize,
    closed: bool,
    /// Who is asleep on a condition variable: a wake is a system call
    /// (about 15 us on the development machine), made only for a sleeper.
    worker_asleep: bool,
    recorder_asleep: bool,
}

enum Slot {
    Pending,
    Done(Finished),
    /// `finish` panicked (inside wgpu): the buffer is lost.
    Lost,
}

fn lock(shared: &Shared) -> MutexGuard<'_, State> {
    shared.state.lock().unwrap_or_else(|e| e.into_inner())
}

impl Finisher {
    pub fn new(device: wgpu::Device) -> Self {
        Finisher {
            device,
            worker: Mutex::new(None),
        }
    }

    /// The finishing thread for one frame, started if it is not running.
    /// Where no thread can be started, encoders are finished where they are sent.
    /// The frame's use may move to another thread (the submission thread
    /// collects it: submitter.rs); the next frame begins once it collected.
    pub fn begin(&self) -> Finishing {
        let mut worker = self.worker.lock().unwrap_or_else(|e| e.into_inner());
        match worker.as_ref() {
            None => *worker = spawn(self.device.clone()),
            // A frame that panicked while recording never collected: what it
            // handed over is not this frame's.
            Some(Worker { shared, .. }) => {
                let mut state = lock(shared);
                state.jobs.clear();
                until_idle(shared, state).results.clear();
            }
        }
        Finishing {
            device: self.device.clone(),
            shared: worker.as_ref().map(|w| w.shared.clone()),
            sent: 0,
            here: Vec::new(),
        }
    }
}

impl Drop for Finisher {
    fn drop(&mut self) {
        let worker = self.worker.get_mut().unwrap_or_else(|e| e.into_inner());
        if let Some(Worker { shared, thread }) = worker.take() {
            lock(&shared).closed = true;
            // Asleep or about to look at the queue (under the lock): either way it sees `closed`.
            shared.queued.notify_one();
            let _ = thread.join();
        }
    }
}

fn spawn(device: wgpu::Device) -> Option<Worker> {
    let shared = Arc::new(Shared::default());
    let theirs = shared.clone();
    let thread = std::thread::Builder::new()
        .name("spreadlight encoder finish".into())
        .spawn(move || work(&device, &theirs))
        .ok()?;
    Some(Worker { shared, thread })
}

/// The finishing thread: take the oldest job, finish it, hand it back.
fn work(device: &wgpu::Device, shared: &Shared) {
    let mut state = lock(shared);
    loop {
        if let Some((place, encoder)) = state.jobs.pop_front() {
            state.busy += 1;
            drop(state);
            let slot = match std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                finish(device, encoder)
            })) {
                Ok(done) => Slot::Done(done),
                Err(_) => Slot::Lost,
            };
            state = lock(shared);
            state.results[place] = slot;
            state.busy -= 1;
            if state.recorder_asleep {
                shared.finished.notify_one();
            }
        } else if state.closed {
            return;
        } else {
            state.worker_asleep = true;
            state = shared.queued.wait(state).unwrap_or_else(|e| e.into_inner());
            state.worker_asleep = false;
        }
    }
}

/// Wait (asleep) until the finishing thread is on no job.
fn until_idle<'a>(shared: &'a Shared, mut state: MutexGuard<'a, State>) -> MutexGuard<'a, State> {
    while state.busy > 0 {
        state.recorder_asleep = true;
        state = shared
            .finished
            .wait(state)
            .unwrap_or_else(|e| e.into_inner());
        state.recorder_asleep = false;
    }
    state
}

/// Finish `encoder` inside a validation scope of the calling thread.
fn finish(device: &wgpu::Device, encoder: wgpu::CommandEncoder) -> Finished {
    let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
    let buffer = encoder.finish();
    (buffer, pollster::block_on(scope.pop()))
}

/// One frame's use of the finishing thread: encoders handed over, in order.
pub(crate) struct Finishing {
    device: wgpu::Device,
    /// The finishing thread's state; None where no thread could start.
    shared: Option<Arc<Shared>>,
    sent: usize,
    /// Encoders finished on this thread (no finishing thread could start).
    here: Vec<Finished>,
}

/// What [`Finishing::collect`] hands back.
pub(crate) struct Collected {
    /// Every encoder handed over, finished, in the order handed over; `None`
    /// if one was lost (a panic inside wgpu): the frame cannot be submitted.
    pub finished: Option<Vec<Finished>>,
    /// Encoders handed over that the finishing thread had not begun when the
    /// recording thread was done: it finished them itself.
    pub taken_back: usize,
}

impl Finishing {
    /// Hand `encoder` to the finishing thread while the caller records on.
    pub fn send(&mut self, encoder: wgpu::CommandEncoder) {
        self.sent += 1;
        let Some(shared) = self.shared.as_ref() else {
            self.here.push(finish(&self.device, encoder));
            return;
        };
        let mut state = lock(shared);
        let place = state.results.len();
        state.results.push(Slot::Pending);
        state.jobs.push_back((place, encoder));
        let asleep = state.worker_asleep;
        drop(state);
        if asleep {
            shared.queued.notify_one();
        }
    }

    /// How many encoders were handed over this frame.
    pub fn sent(&self) -> usize {
        self.sent
    }

    /// Every encoder handed over, finished. Those the finishing thread has
    /// not begun (it did not get a core in time) are finished here rather
    /// than waited for, so a frame never takes longer than finishing all on
    /// the recording thread would, beyond waiting for the one in progress.
    pub fn collect(self) -> Collected {
        let Some(shared) = self.shared.as_ref() else {
            return Collected {
                taken_back: self.here.len(),
                finished: Some(self.here),
            };
        };
        let mut taken_back = 0;
        let mut state = lock(shared);
        while let Some((place, encoder)) = state.jobs.pop_front() {
            drop(state);
            let done = finish(&self.device, encoder);
            taken_back += 1;
            state = lock(shared);
            state.results[place] = Slot::Done(done);
        }
        let mut state = until_idle(shared, state);
        let finished = std::mem::take(&mut state.results)
            .into_iter()
            .map(|slot| match slot {
                Slot::Done(done) => Some(done),
                Slot::Pending | Slot::Lost => None,
            })
            .collect();
        Collected {
            finished,
            taken_back,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn encoders_the_thread_has_not_begun_are_finished_by_the_recording_thread() {
        // The executor alone: the frame graph's layer knows no renderer.
        let gpu = crate::context::GpuContext::headless()
            .unwrap_or_else(|e| panic!("GPU tests need a GPU adapter: {e}"));
        let executor = super::super::Executor::new(&gpu).expect("an executor");
        let device = gpu.device.clone();
        // A finishing thread that never takes a job (it ends at once): as
        // one that gets no core before the recording is done.
        let finisher = Finisher::new(device.clone());
        *finisher.worker.lock().expect("unpoisoned") = Some(Worker {
            shared: Arc::new(Shared::default()),
            thread: std::thread::spawn(|| {}),
        });
        let mut finishing = finisher.begin();
        for label in ["first run", "second run"] {
            finishing.send(
                device
                    .create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some(label) }),
            );
        }
        assert_eq!(finishing.sent(), 2);
        let collected = finishing.collect();
        assert_eq!(collected.taken_back, 2);
        let finished = collected.finished.expect("nothing lost");
        assert_eq!(finished.len(), 2);
        assert!(finished.iter().all(|(_, error)| error.is_none()));
        gpu.submit(finished.into_iter().map(|(buffer, _)| buffer));
        executor.wait_idle().expect("drains");
    }

    #[test]
    fn runs_are_in_order_and_the_last_is_the_shortest() {
        for steps in 1..40 {
            let chunks: Vec<usize> = (0..steps).map(|s| chunk_of(s, steps)).collect();
            assert_eq!(chunks[0], 0);
            assert!(chunks.windows(2).all(|w| w[1] == w[0] || w[1] == w[0] + 1));
            let runs = chunks[steps - 1] + 1;
            // Every run once the frame has a pass for each unit of them.
            if steps >= 2 * FRAME_CHUNKS - 1 {
                assert_eq!(runs, FRAME_CHUNKS, "{steps} passes");
            }
            assert!(
                runs >= steps.min(2) && runs <= FRAME_CHUNKS,
                "{steps} passes"
            );
            let last = chunks.iter().filter(|&&c| c == runs - 1).count();
            let first = chunks.iter().filter(|&&c| c == 0).count();
            assert!(last <= first, "{steps} passes: {chunks:?}");
        }
    }
}
