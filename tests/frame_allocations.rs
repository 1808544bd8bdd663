//! The heap allocations of a shipped frame rendered again with nothing
//! changed, counted by this binary's global allocator: the one part of a
//! frame's CPU cost that is the same on every machine (issue 33: every
//! shipped frame's CPU under 0.6 ms on the H200, where timings cannot be
//! asserted). Each patch renders a few frames at a small size as
//! `spreadlight bench` renders them (batched, timestamps around every pass,
//! the sinks re-evaluated every frame); the median of the steady frames must
//! stay under the patch's bound, and a failure prints where the frame
//! allocates: the patch's evaluation, each pass, the tail.
//!
//! One test function: the count is the process's, so nothing else may run
//! beside it (it counts in a process of its own, started by itself).

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::sync::atomic::{AtomicU64, Ordering};

use spreadlight_render::renderer::{Recording, Timing};
use spreadlight_tests::{PatchRun, root};

/// The system allocator, counting every allocation (and reallocation):
/// in all (every thread: the finishing thread's encoding counts too) and
/// per thread (what the frame graph samples around each pass).
struct Counting;

static ALL: AtomicU64 = AtomicU64::new(0);

thread_local! {
    // Const-initialised and without a destructor: safe to touch from inside the allocator.
    static HERE: Cell<u64> = const { Cell::new(0) };
}

fn count() {
    ALL.fetch_add(1, Ordering::Relaxed);
    let _ = HERE.try_with(|n| n.set(n.get() + 1));
}

fn here() -> u64 {
    HERE.try_with(Cell::get).unwrap_or(0)
}

// SAFETY: every call is passed on to `System` unchanged; counting touches
// only an atomic and a const thread-local, neither of which allocates. A
// global allocator cannot be written without `unsafe` (the workspace denies
// it elsewhere, Cargo.toml).
#[allow(unsafe_code)]
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        count();
        // SAFETY: the caller's contract, passed on.
        unsafe { System.alloc(layout) }
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        count();
        // SAFETY: the caller's contract, passed on.
        unsafe { System.alloc_zeroed(layout) }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        count();
        // SAFETY: the caller's contract, passed on.
        unsafe { System.realloc(ptr, layout, new_size) }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: the caller's contract, passed on.
        unsafe { System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static ALLOCATOR: Counting = Counting;

const SIZE: (u32, u32) = (64, 36);
/// Frames before counting: pipelines compile, pools and caches fill.
const WARMUP: usize = 6;
/// Frames counted; the median is checked.
const COUNTED: usize = 5;

/// Where one frame allocated.
struct Frame {
    /// Every thread, the whole `evaluate`.
    all: u64,
    /// The recording thread outside the frame graph's execution: the
    /// patch's evaluation (the nodes, their recipes, the graph declared).
    evaluate: u64,
    before_passes: u64,
    /// Each pass's name and count.
    passes: Vec<(String, u64)>,
    after_passes: u64,
    /// Other threads (the finishing thread's `finish`).
    elsewhere: u64,
    /// Bind groups and pipelines of the frame's dispatches: made, found in
    /// the shader cache's maps, kept from last frame's calls with no look-up.
    groups_created: u64,
    groups_reused: u64,
    groups_kept: u64,
    pipelines_kept: u64,
}

impl Frame {
    fn breakdown(&self) -> String {
        let mut passes: Vec<&(String, u64)> = self.passes.iter().collect();
        passes.sort_by_key(|p| std::cmp::Reverse(p.1));
        let mut text = format!(
            "{} in all: evaluating {}, before the passes {}, the {} passes {}, after them {}, other threads {}\n",
            self.all,
            self.evaluate,
            self.before_passes,
            self.passes.len(),
            self.passes.iter().map(|p| p.1).sum::<u64>(),
            self.after_passes,
            self.elsewhere,
        );
        for (name, n) in passes {
            text.push_str(&format!("  {n:>5}  {name}\n"));
        }
        text
    }
}

fn frame(run: &mut PatchRun) -> Frame {
    let (all, mine) = (ALL.load(Ordering::Relaxed), here());
    run.render_next();
    let (all, mine) = (ALL.load(Ordering::Relaxed) - all, here() - mine);
    let report = run.renderer().last_report();
    let counted = |n: Option<u64>| n.expect("the renderer samples the allocation counter");
    let passes: Vec<(String, u64)> = report
        .passes
        .iter()
        .map(|p| (p.name.clone(), counted(p.allocations)))
        .collect();
    let before_passes = counted(report.allocations_before_passes);
    let after_passes = counted(report.allocations_after_passes);
    let recorded = before_passes + after_passes + passes.iter().map(|p| p.1).sum::<u64>();
    Frame {
        all,
        evaluate: mine.saturating_sub(recorded),
        before_passes,
        passes,
        after_passes,
        elsewhere: all.saturating_sub(mine),
        groups_created: report.counter("bind groups created"),
        groups_reused: report.counter("bind groups reused"),
        groups_kept: report.counter("bind groups kept"),
        pipelines_kept: report.counter("pipelines kept"),
    }
}

/// The median frame of `COUNTED` after `WARMUP`, by its count in all.
fn steady_frame(patch: &str) -> Frame {
    let mut run = PatchRun::new(&root().join("patches").join(patch), SIZE, |_| {});
    run.renderer().set_recording(Recording::Batched);
    run.renderer().set_timing(Timing::PerPass);
    for _ in 0..WARMUP {
        run.render_next();
    }
    let mut frames: Vec<Frame> = (0..COUNTED).map(|_| frame(&mut run)).collect();
    frames.sort_by_key(|f| f.all);
    frames.swap_remove(COUNTED / 2)
}

/// The shipped frames issue 33 names, each with its bound: the count left
/// on lavapipe by session 19's kept frame-graph plan (docs/benchmarks.md,
/// "Session 19: the frame graph's plan, kept across frames": emeshe-frame
/// 1,097-1,115, post 1,372-1,388; 1,409 and 1,960 before it, 1,877 and
/// 2,687 before session 18) and an eighth more for wgpu's own bookkeeping,
/// which varies a little from frame to frame. (Another adapter takes other
/// paths, a compute shadow raster for one, so counts there differ.)
const BOUNDS: [(&str, u64); 2] = [("emeshe-frame.ron", 1_240), ("post.ron", 1_550)];

/// A debug build of wgpu-core captures a backtrace at every lock it takes
/// when `std::backtrace` is enabled (`RUST_BACKTRACE=1`, as many shells
/// set): allocations of the measurement, not of the frame. The count runs in
/// a process of this binary with library backtraces off, so it is the same
/// whatever the caller's environment.
#[test]
fn a_frame_rendered_again_allocates_under_its_bound() {
    if spreadlight_tests::ran_in_a_process_of_its_own_with(
        "a_frame_rendered_again_allocates_under_its_bound",
        &[("RUST_LIB_BACKTRACE", "0")],
    ) {
        return;
    }
    spreadlight_render::allocation_count::count_with(here);
    let mut failures = Vec::new();
    for (patch, bound) in BOUNDS {
        let frame = steady_frame(patch);
        println!("{patch}: {}", frame.breakdown());
        // Nothing changed that a pass binds (the moving sphere's buffers
        // are kept and rewritten in place), so every dispatch takes last
        // frame's bind groups and pipeline without a look-up.
        if frame.groups_created > 0
            || frame.groups_kept == 0
            || frame.groups_kept != frame.groups_reused
            || frame.pipelines_kept == 0
        {
            failures.push(format!(
                "{patch}: a steady frame made {} bind groups and reused {}, of which {} \
                 kept from its last frame, and kept {} pipelines: every group should be kept",
                frame.groups_created, frame.groups_reused, frame.groups_kept, frame.pipelines_kept
            ));
        }
        if frame.all > bound {
            failures.push(format!(
                "{patch} allocates {} times a frame, over its bound of {bound}:\n{}",
                frame.all,
                frame.breakdown()
            ));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
