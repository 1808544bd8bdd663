//! Finishing a batched frame's command encoders off the recording thread.
//!
//! wgpu 30 records a pass's commands into a list and encodes them for the
//! backend only at `CommandEncoder::finish`: a fifth to a quarter of the
//! recording thread in the profiles of docs/benchmarks.md. A batched frame is
//! therefore recorded into [`FRAME_CHUNKS`] encoders, each holding a run of
//! consecutive passes; every one but the last is finished here, on one thread
//! the renderer keeps, while the recording thread records the next run.
//!
//! Error scopes are per thread in wgpu 30 (an error is caught by the scopes
//! of the thread that raised it), and recording errors surface at `finish`:
//! the finishing thread opens its own scope around each `finish` and hands
//! back what it caught, so a frame that fails validation is still dropped.

use std::sync::mpsc::{Receiver, Sender, channel};
use std::sync::{Mutex, MutexGuard};
use std::thread::JoinHandle;

/// Encoders a batched frame is recorded into (at most: a frame of fewer
/// than `2 * FRAME_CHUNKS - 1` passes may have fewer). Each one more lets wgpu encode another part of the
/// frame beside the recording, and costs a command buffer at submit, where
/// wgpu may put a transition buffer before it.
pub const FRAME_CHUNKS: usize = 3;

/// Which of the frame's encoders the pass recorded at `step` of `steps` goes
/// into. The last run, finished on the recording thread after it has
/// recorded everything, holds half as many passes as each run before it:
/// with three, the finishing thread encodes four fifths of the frame. (It
/// keeps up: encoding a run took about a fifth of the time recording it
/// took in the profile.)
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
    jobs: Sender<wgpu::CommandEncoder>,
    finished: Receiver<Finished>,
    thread: JoinHandle<()>,
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
    pub fn begin(&self) -> Finishing<'_> {
        let mut worker = self.worker.lock().unwrap_or_else(|e| e.into_inner());
        if worker.is_none() {
            *worker = spawn(self.device.clone());
        }
        Finishing {
            device: &self.device,
            worker,
            sent: 0,
            here: Vec::new(),
        }
    }
}

impl Drop for Finisher {
    fn drop(&mut self) {
        let worker = self.worker.get_mut().unwrap_or_else(|e| e.into_inner());
        if let Some(Worker { jobs, thread, .. }) = worker.take() {
            // With its queue closed the thread ends after the encoder it finishes.
            drop(jobs);
            let _ = thread.join();
        }
    }
}

fn spawn(device: wgpu::Device) -> Option<Worker> {
    let (jobs, queue) = channel::<wgpu::CommandEncoder>();
    let (done, finished) = channel();
    let thread = std::thread::Builder::new()
        .name("spreadlight encoder finish".into())
        .spawn(move || {
            for encoder in queue {
                if done.send(finish(&device, encoder)).is_err() {
                    break;
                }
            }
        })
        .ok()?;
    Some(Worker {
        jobs,
        finished,
        thread,
    })
}

/// Finish `encoder` inside a validation scope of the calling thread.
fn finish(device: &wgpu::Device, encoder: wgpu::CommandEncoder) -> Finished {
    let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
    let buffer = encoder.finish();
    (buffer, pollster::block_on(scope.pop()))
}

/// One frame's use of the finishing thread: encoders sent, in order.
pub(crate) struct Finishing<'a> {
    device: &'a wgpu::Device,
    worker: MutexGuard<'a, Option<Worker>>,
    sent: usize,
    /// Encoders finished on this thread (no finishing thread, or it died).
    here: Vec<Finished>,
}

impl Finishing<'_> {
    /// Finish `encoder` on the finishing thread while the caller records on.
    pub fn send(&mut self, encoder: wgpu::CommandEncoder) {
        let Some(worker) = self.worker.as_ref() else {
            self.here.push(finish(self.device, encoder));
            return;
        };
        match worker.jobs.send(encoder) {
            Ok(()) => self.sent += 1,
            // The thread is gone (a panic inside wgpu): finish here.
            Err(returned) => self.here.push(finish(self.device, returned.0)),
        }
    }

    /// How many encoders went to the finishing thread this frame.
    pub fn sent(&self) -> usize {
        self.sent
    }

    /// Every encoder sent, finished, in the order sent; `None` if the
    /// finishing thread died before handing them all back (its buffers are
    /// lost, so the frame cannot be submitted).
    pub fn collect(mut self) -> Option<Vec<Finished>> {
        let mut all = Vec::with_capacity(self.sent + self.here.len());
        if let Some(worker) = self.worker.as_ref() {
            for _ in 0..self.sent {
                match worker.finished.recv() {
                    Ok(finished) => all.push(finished),
                    Err(_) => {
                        // The next frame starts another thread.
                        *self.worker = None;
                        return None;
                    }
                }
            }
        }
        // Finished here only where no thread took them: all of the frame, or
        // (the thread gone) none sent before them is left.
        all.append(&mut self.here);
        Some(all)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
