//! Counting a frame's heap allocations pass by pass, where the host can.
//!
//! A heap allocation is the one cost of recording a pass that is the same
//! on every machine: a test can bound it where timings cannot be asserted
//! (issue 33: every shipped frame's CPU under 0.6 ms). Only a program's
//! `#[global_allocator]` can count, and it lives in the binary, not here:
//! a host that counts (the allocation test, tests/frame_allocations.rs)
//! hands the renderer a function that reads its count for the calling
//! thread, and the frame graph samples it around each pass
//! ([`PassReport::allocations`](crate::report::PassReport::allocations))
//! and the tail after the last one. Without a counter nothing is sampled.

use std::sync::OnceLock;

static COUNTER: OnceLock<fn() -> u64> = OnceLock::new();

/// Use `counter` (the allocations the calling thread has made so far) from
/// now on, for every renderer of the process. The first counter set stays.
pub fn count_with(counter: fn() -> u64) {
    let _ = COUNTER.set(counter);
}

/// The calling thread's allocations so far, when a host counts them.
pub(crate) fn now() -> Option<u64> {
    COUNTER.get().map(|count| count())
}

/// The allocations since `before` (both from [`now`]).
pub(crate) fn since(before: Option<u64>) -> Option<u64> {
    Some(now()?.saturating_sub(before?))
}
