use super::*;
use crate::post::copy_key::CopyKey;
use crate::shaders::{Permutation, ShaderCache};

fn gpu() -> crate::context::GpuContext {
    crate::context::GpuContext::headless()
        .unwrap_or_else(|e| panic!("GPU tests need a GPU adapter: {e}"))
}

/// What the threads made, a shader cache takes instead of making it; an
/// entry point the permutation lacks (a stale list) is skipped without a
/// device error, and the cache makes what the list did not name.
#[test]
fn a_cache_takes_the_pipelines_made_ahead_and_a_stale_entry_is_skipped() {
    let gpu = gpu();
    let copy = CopyKey.key();
    let ahead = PipelinesAhead::start(
        gpu.device.clone(),
        gpu.pipeline_cache().cloned(),
        vec![
            PipelineId::entry(&copy, "main").into(),
            PipelineId::entry(&copy, "no_such_entry").into(),
            // Listed twice: made once.
            PipelineId::entry(&copy, "main").into(),
        ],
        4,
    );
    let done = ahead.wait();
    assert_eq!(
        (done.listed, done.threads, done.created, done.failed),
        (2, 2, 1, 1),
        "{done:?}"
    );
    assert!(done.wall > Duration::ZERO);
    // The threads' time: the one made, its module within it (the skipped
    // entry point is let go before any module is made).
    assert!(done.longest > Duration::ZERO, "{done:?}");
    assert!(done.busy >= done.longest && done.modules > Duration::ZERO);
    assert!(done.modules <= done.busy, "{done:?}");

    let mut cache = ShaderCache::lazy().with_pipeline_cache(gpu.pipeline_cache().cloned());
    cache.set_pipelines_ahead(ahead.clone());
    cache
        .compute_pipeline(&gpu.device, &copy, "main")
        .expect("taken");
    assert_eq!(
        (cache.pipelines_compiled, cache.pipelines_taken_ahead),
        (1, 1),
        "made ahead, not by the cache"
    );
    let stats = cache.pipelines_ahead().expect("given");
    assert_eq!((stats.taken, stats.waited, stats.claimed), (1, 0, 0));
    // Looked up again: the cache's own now.
    cache
        .compute_pipeline(&gpu.device, &copy, "main")
        .expect("cached");
    assert_eq!(ahead.stats().taken, 1);
    // Not in the list: the cache makes it.
    let other = crate::permutations::all_permutations()
        .into_iter()
        .find(|k| k.path() == "post/tonemap.wgsl")
        .expect("a tonemap permutation");
    cache
        .compute_pipeline(&gpu.device, &other, "main")
        .expect("made");
    assert_eq!(
        (cache.pipelines_compiled, cache.pipelines_taken_ahead),
        (2, 1)
    );
    assert_eq!(
        cache.compute_pipelines_used(),
        [
            PipelineId::entry(&copy, "main"),
            PipelineId::entry(&other, "main")
        ],
        "what the next run's list names, in the order asked for"
    );
    assert!(
        gpu.take_uncaptured_errors().is_empty(),
        "the skipped entry raised no device error"
    );
}

/// A listed pipeline the frame asks for before any thread began it is the
/// frame's to make (claimed), and no thread makes it again.
#[test]
fn a_pipeline_no_thread_began_is_claimed_by_the_frame() {
    let gpu = gpu();
    let copy = CopyKey.key();
    // No threads at all: the list stays queued, as when every thread is busy.
    let ahead = PipelinesAhead {
        shared: Arc::new(Shared {
            slots: Mutex::new(
                [(PipelineId::entry(&copy, "main"), Slot::Queued)]
                    .into_iter()
                    .collect(),
            ),
            changed: Condvar::new(),
            stats: Mutex::new(AheadStats {
                listed: 1,
                ..AheadStats::default()
            }),
        }),
    };
    let mut cache = ShaderCache::lazy();
    cache.set_pipelines_ahead(ahead.clone());
    cache
        .compute_pipeline(&gpu.device, &copy, "main")
        .expect("made by the cache");
    assert_eq!(
        (cache.pipelines_compiled, cache.pipelines_taken_ahead),
        (1, 0)
    );
    assert_eq!(ahead.stats().claimed, 1);
    assert!(
        ahead.take(&PipelineId::entry(&copy, "main")).is_none(),
        "claimed, not queued"
    );
}

/// A frame's announced pipelines (frame_graph/gather.rs): those the cache
/// lacks go to threads, and the frame's look-up takes, waits for or claims
/// each; one the cache has, or threads make already, is not handed again.
#[test]
fn announced_pipelines_the_cache_lacks_are_made_on_threads_once() {
    let gpu = gpu();
    let copy = CopyKey.key();
    let tonemap = crate::permutations::all_permutations()
        .into_iter()
        .find(|k| k.path() == "post/tonemap.wgsl")
        .expect("a tonemap permutation");
    let mut cache = ShaderCache::lazy();
    cache
        .compute_pipeline(&gpu.device, &tonemap, "main")
        .expect("made by the cache");
    assert_eq!(cache.pipelines_gathered(), None, "none announced yet");
    let announced: Vec<Job> = vec![
        PipelineId::entry(&copy, "main").into(),
        PipelineId::entry(&tonemap, "main").into(),
    ];
    cache.make_ahead(&gpu.device, announced.clone());
    // Announced again (the next frame) while the threads still run: not handed twice.
    cache.make_ahead(&gpu.device, announced);
    cache
        .compute_pipeline(&gpu.device, &copy, "main")
        .expect("taken, or made");
    cache.end_frame_ahead();
    let made = cache
        .pipelines_gathered()
        .expect("one announced the cache lacked");
    assert_eq!(
        made.listed, 1,
        "the tonemap was the cache's already: {made:?}"
    );
    // The thread made it (taken, or waited for), or the frame asked first.
    assert_eq!(made.taken + made.waited + made.claimed, 1, "{made:?}");
    assert_eq!(cache.pipelines_compiled, 2, "the tonemap and the copy");
    assert_eq!(
        cache.pipelines_taken_ahead,
        1 - made.claimed as u64,
        "{made:?}"
    );
}
