//! The gate every renderer submission passes ([`GpuContext::submit`]), which a
//! host that configures window surfaces on the same device keeps closed
//! whenever it may configure one.
//!
//! Why: wgpu-core 30's `configure_surface` waits for the device to go idle
//! and then fails (`GpuWaitTimeout`, "Failed to wait for GPU to come idle")
//! when the queue is not empty afterwards, i.e. when another thread submitted
//! during the wait. The surface then stays unconfigured and the next paint
//! panics. The editor renders patches on a worker thread while eframe
//! configures surfaces on the UI thread: on a window's first frame, on a
//! `Resized` event in its event loop, after a frame's viewport commands, on a
//! suboptimal or lost surface. Those happen in eframe's code, outside any call
//! of ours, so the editor cannot fence each of them; instead it keeps the gate
//! closed by default and opens it only while eframe cannot configure anything
//! (its own `update`, minus the immediate viewports it draws there).
//!
//! A submit that finds the gate closed calls the host's waker (the editor's
//! `request_repaint`) so that the host soon opens it, then waits. Headless
//! hosts (the CLI, tests) never close it, so their submits never wait. A host
//! that is about to join a thread which may submit opens the gate for good
//! first, so the join cannot deadlock.
//!
//! [`GpuContext::submit`]: crate::GpuContext::submit

use std::sync::{Arc, Condvar, Mutex, MutexGuard};

/// Called when a submit has to wait: it should make the host open the gate soon.
type Waker = Arc<dyn Fn() + Send + Sync>;

/// Whether the renderer may submit now; cheap to clone (all clones are one gate).
#[derive(Clone, Default)]
pub struct SubmissionGate {
    inner: Arc<Inner>,
}

#[derive(Default)]
struct Inner {
    /// Held by a submit for the whole of the queue's `submit`, so closing
    /// waits for a submission already in flight.
    state: Mutex<State>,
    opened: Condvar,
}

#[derive(Default)]
struct State {
    closed: bool,
    /// Opened for good: closing no longer does anything.
    for_good: bool,
    waker: Option<Waker>,
    counts: GateCounts,
}

/// What passed the gate since it was made ([`SubmissionGate::counts`]): a
/// host compares two readings to say what one of its frames cost the UI.
/// Each wait called the host's waker, which in the editor is one repaint
/// request: a submission that waits costs a UI frame.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct GateCounts {
    /// Submissions that passed.
    pub submissions: u64,
    /// Times a submit found the gate closed and called the waker.
    pub waits: u64,
}

impl GateCounts {
    /// What passed between `earlier` and this reading.
    pub fn since(self, earlier: GateCounts) -> GateCounts {
        GateCounts {
            submissions: self.submissions.saturating_sub(earlier.submissions),
            waits: self.waits.saturating_sub(earlier.waits),
        }
    }
}

impl std::fmt::Debug for SubmissionGate {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let s = self.lock();
        f.debug_struct("SubmissionGate")
            .field("closed", &s.closed)
            .field("for_good", &s.for_good)
            .finish()
    }
}

impl SubmissionGate {
    fn lock(&self) -> MutexGuard<'_, State> {
        // A panic while submitting leaves the flags whole.
        self.inner.state.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// Keep submissions out from now on; returns once none is in flight.
    /// Does nothing after [`SubmissionGate::open_for_good`].
    pub fn close(&self) {
        let mut s = self.lock();
        s.closed = !s.for_good;
    }

    /// Let submissions through, the waiting ones first.
    pub fn open(&self) {
        self.lock().closed = false;
        self.inner.opened.notify_all();
    }

    /// Open, and ignore any later [`SubmissionGate::close`]: before joining a
    /// thread that may be waiting to submit.
    pub fn open_for_good(&self) {
        self.lock().for_good = true;
        self.open();
    }

    pub fn is_open(&self) -> bool {
        !self.lock().closed
    }

    /// Submissions passed and waits (waker calls) so far.
    pub fn counts(&self) -> GateCounts {
        self.lock().counts
    }

    /// Call `waker` whenever a submit finds the gate closed (again).
    pub fn set_waker(&self, waker: impl Fn() + Send + Sync + 'static) {
        self.lock().waker = Some(Arc::new(waker));
    }

    /// Open until the returned guard drops, then closed again (a host's
    /// window where nothing of its own configures a surface).
    pub fn open_scope(&self) -> OpenScope<'_> {
        self.open();
        OpenScope(self)
    }

    /// Closed until the returned guard drops, then open again (a part of an
    /// open window that may configure a surface).
    pub fn closed_scope(&self) -> ClosedScope<'_> {
        self.close();
        ClosedScope(self)
    }

    /// Run `submit` once the gate is open, with it held open meanwhile.
    pub(crate) fn pass<R>(&self, submit: impl FnOnce() -> R) -> R {
        let mut s = self.lock();
        // Whether the waker was called since the gate was last seen open or
        // the waiting last woke: a wake-up that finds the gate closed again
        // (the host opened and closed it before this thread ran) asks again.
        let mut asked = false;
        while s.closed {
            if asked {
                s = self.inner.opened.wait(s).unwrap_or_else(|e| e.into_inner());
                asked = false;
            } else {
                // Called unlocked: the waker may take the host's own locks.
                let waker = s.waker.clone();
                s.counts.waits += 1;
                drop(s);
                if let Some(wake) = waker {
                    wake();
                }
                s = self.lock();
                asked = true;
            }
        }
        let done = submit();
        s.counts.submissions += 1;
        drop(s);
        done
    }
}

/// The gate is open while this lives ([`SubmissionGate::open_scope`]).
#[must_use = "the gate closes again when this drops"]
pub struct OpenScope<'a>(&'a SubmissionGate);

impl Drop for OpenScope<'_> {
    fn drop(&mut self) {
        self.0.close();
    }
}

/// The gate is closed while this lives ([`SubmissionGate::closed_scope`]).
#[must_use = "the gate opens again when this drops"]
pub struct ClosedScope<'a>(&'a SubmissionGate);

impl Drop for ClosedScope<'_> {
    fn drop(&mut self) {
        self.0.open();
    }
}

#[cfg(test)]
mod tests {
    use std::sync::atomic::{AtomicBool, Ordering};
    use std::sync::mpsc;
    use std::time::Duration;

    use super::*;

    /// Long enough for any machine; only reached when the gate deadlocks.
    const HUNG: Duration = Duration::from_secs(30);

    /// `gate.pass` on another thread; the receiver gets its result.
    fn submit_elsewhere(gate: &SubmissionGate, ran: &Arc<AtomicBool>) -> mpsc::Receiver<u32> {
        let (done, result) = mpsc::channel();
        let (gate, ran) = (gate.clone(), ran.clone());
        std::thread::spawn(move || {
            let value = gate.pass(|| {
                ran.store(true, Ordering::SeqCst);
                7
            });
            let _ = done.send(value);
        });
        result
    }

    #[test]
    fn a_submit_waits_while_closed_asks_to_be_let_in_and_runs_once_opened() {
        let gate = SubmissionGate::default();
        let (woke, wakes) = mpsc::channel();
        gate.set_waker(move || {
            let _ = woke.send(());
        });
        gate.close();
        assert!(!gate.is_open());
        let ran = Arc::new(AtomicBool::new(false));
        let result = submit_elsewhere(&gate, &ran);
        wakes.recv_timeout(HUNG).expect("the waker fires");
        // The waker fires only once the submit found the gate closed, and it
        // cannot pass a closed gate.
        assert!(
            !ran.load(Ordering::SeqCst),
            "nothing submitted while closed"
        );
        assert!(matches!(result.try_recv(), Err(mpsc::TryRecvError::Empty)));
        gate.open();
        assert_eq!(result.recv_timeout(HUNG), Ok(7), "it ran once opened");
        assert!(ran.load(Ordering::SeqCst));
    }

    #[test]
    fn an_open_gate_and_one_opened_for_good_never_block() {
        let gate = SubmissionGate::default();
        let woken = Arc::new(AtomicBool::new(false));
        let flag = woken.clone();
        gate.set_waker(move || flag.store(true, Ordering::SeqCst));
        // Never closed (a headless host).
        let ran = Arc::new(AtomicBool::new(false));
        assert_eq!(submit_elsewhere(&gate, &ran).recv_timeout(HUNG), Ok(7));
        // Opened for good: closing does nothing, scopes included.
        gate.close();
        gate.open_for_good();
        gate.close();
        let _closed = gate.closed_scope();
        assert!(gate.is_open());
        let ran = Arc::new(AtomicBool::new(false));
        assert_eq!(submit_elsewhere(&gate, &ran).recv_timeout(HUNG), Ok(7));
        assert!(!woken.load(Ordering::SeqCst), "no submit had to wait");
    }

    #[test]
    fn scopes_open_and_close_and_nest_as_the_editor_uses_them() {
        let gate = SubmissionGate::default();
        gate.close();
        {
            let _update = gate.open_scope();
            assert!(gate.is_open());
            {
                let _immediate_viewport = gate.closed_scope();
                assert!(!gate.is_open());
            }
            assert!(gate.is_open());
        }
        assert!(!gate.is_open());
    }

    #[test]
    fn a_waiting_submit_opened_for_good_runs() {
        let gate = SubmissionGate::default();
        gate.close();
        let (woke, wakes) = mpsc::channel();
        gate.set_waker(move || {
            let _ = woke.send(());
        });
        let ran = Arc::new(AtomicBool::new(false));
        let result = submit_elsewhere(&gate, &ran);
        wakes.recv_timeout(HUNG).expect("the waker fires");
        // What the editor does before joining its worker.
        gate.open_for_good();
        assert_eq!(result.recv_timeout(HUNG), Ok(7));
    }
}
