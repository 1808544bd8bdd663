//! The device's queue as the renderer shares it ([`GpuContext::queue`]):
//! a `wgpu::Queue` that waits, before anyone uses it, for a frame whose
//! submission a submission thread still owes (frame_graph/submitter.rs,
//! `SPREADLIGHT_SUBMIT=thread`).
//!
//! Why every use waits: wgpu applies `Queue::write_buffer` and
//! `write_texture` at the *next* `submit`, before its command buffers. A
//! uniform the next frame writes while this frame's submission is still
//! owed would land in this frame's submission and be read by this frame's
//! passes; a submission of the next frame's (a geometry node's compute,
//! a readback's copy) would reach the GPU before this frame's passes. So the
//! next frame runs (evaluates its patch, declares its graph) beside this
//! frame's submission up to its first use of the queue, and waits there:
//! frames stay in order and nothing that writes through the queue has to
//! know about the thread. The submission thread itself submits through
//! [`FrameQueue::unordered`], which does not wait (it would wait for itself).
//!
//! [`GpuContext::queue`]: crate::context::GpuContext::queue

use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};
use std::sync::{Arc, Condvar, Mutex};
use std::time::{Duration, Instant};

/// `wgpu::Queue`, behind the frame submission owed by a submission thread.
#[derive(Clone, Debug)]
pub struct FrameQueue {
    queue: wgpu::Queue,
    owed: Arc<Owed>,
}

/// Frame submissions a submission thread owes, and how long others waited for them.
#[derive(Debug, Default)]
pub(crate) struct Owed {
    /// Frames handed to a submission thread and not yet submitted (or dropped).
    count: AtomicUsize,
    /// Guards the count's going to zero, for [`Owed::wait`]'s sleep.
    lock: Mutex<()>,
    paid: Condvar,
    /// Nanoseconds threads spent waiting in [`Owed::wait`], summed.
    waited_ns: AtomicU64,
}

impl Owed {
    /// One more frame owed: before the job goes to the submission thread.
    pub(crate) fn owe(&self) {
        self.count.fetch_add(1, Ordering::SeqCst);
    }

    /// A frame submitted (or dropped): wake those waiting.
    pub(crate) fn paid(&self) {
        let _guard = self.lock.lock().unwrap_or_else(|e| e.into_inner());
        self.count.fetch_sub(1, Ordering::SeqCst);
        self.paid.notify_all();
    }

    /// Whether a frame's submission is owed now.
    pub(crate) fn is_owed(&self) -> bool {
        self.count.load(Ordering::SeqCst) > 0
    }

    /// Return once no frame's submission is owed; one atomic load when none is.
    pub(crate) fn wait(&self) {
        if !self.is_owed() {
            return;
        }
        let started = Instant::now();
        let mut guard = self.lock.lock().unwrap_or_else(|e| e.into_inner());
        while self.is_owed() {
            guard = self.paid.wait(guard).unwrap_or_else(|e| e.into_inner());
        }
        drop(guard);
        self.waited_ns
            .fetch_add(started.elapsed().as_nanos() as u64, Ordering::Relaxed);
    }

    /// The time spent waiting so far, summed over every thread and frame:
    /// a frame's share is the difference of two readings.
    pub(crate) fn waited(&self) -> Duration {
        Duration::from_nanos(self.waited_ns.load(Ordering::Relaxed))
    }
}

impl FrameQueue {
    pub(crate) fn new(queue: wgpu::Queue) -> Self {
        FrameQueue {
            queue,
            owed: Arc::default(),
        }
    }

    /// The queue without waiting for an owed frame submission: for the
    /// submission thread, which pays it, and for what only reads the
    /// queue's properties.
    pub(crate) fn unordered(&self) -> &wgpu::Queue {
        &self.queue
    }

    pub(crate) fn owed(&self) -> &Arc<Owed> {
        &self.owed
    }

    /// The timestamp period, without waiting (a property of the queue).
    pub fn get_timestamp_period(&self) -> f32 {
        self.queue.get_timestamp_period()
    }
}

impl std::ops::Deref for FrameQueue {
    type Target = wgpu::Queue;

    /// The queue, once the frame submission owed (if any) is made.
    fn deref(&self) -> &wgpu::Queue {
        self.owed.wait();
        &self.queue
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_wait_returns_only_once_the_owed_submission_is_paid() {
        use std::sync::atomic::AtomicBool;
        let owed = Arc::new(Owed::default());
        owed.wait();
        assert_eq!(owed.waited(), Duration::ZERO, "nothing owed: no wait");
        owed.owe();
        let submitted = Arc::new(AtomicBool::new(false));
        let (payer, flag) = (owed.clone(), submitted.clone());
        let paid = std::thread::spawn(move || {
            std::thread::sleep(Duration::from_millis(20));
            flag.store(true, Ordering::SeqCst);
            payer.paid();
        });
        owed.wait();
        assert!(
            submitted.load(Ordering::SeqCst),
            "returned before the payment"
        );
        assert!(!owed.is_owed());
        paid.join().expect("the payer ends");
    }
}
