//! The threads a herd is posed on (animation channels, skinned poses): a
//! pool of their own rather than rayon's global one, so that work others
//! queue there (a sequence's EXR blocks compress on it) never holds up a
//! frame's evaluation behind a frame's encoding.

use std::sync::OnceLock;

/// At most this many posing threads: a pose is a fraction of a millisecond.
const MAX_THREADS: usize = 8;

fn pool() -> Option<&'static rayon::ThreadPool> {
    static POOL: OnceLock<Option<rayon::ThreadPool>> = OnceLock::new();
    POOL.get_or_init(|| {
        let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads.min(MAX_THREADS))
            .thread_name(|i| format!("spreadlight pose {i}"))
            .build()
            .ok()
    })
    .as_ref()
}

/// Runs `work` on the posing threads: its parallel iterators spread over
/// them. Where the pool could not be made, on this thread and rayon's global pool.
pub fn posing<R: Send>(work: impl FnOnce() -> R + Send) -> R {
    match pool() {
        Some(pool) => pool.install(work),
        None => work(),
    }
}

#[cfg(test)]
mod tests {
    use rayon::prelude::*;

    #[test]
    fn posing_work_runs_on_the_posing_threads_not_rayons_global_pool() {
        let names: Vec<String> = super::posing(|| {
            (0..64)
                .into_par_iter()
                .map(|_| std::thread::current().name().unwrap_or("").to_owned())
                .collect()
        });
        assert!(
            names.iter().all(|n| n.starts_with("spreadlight pose")),
            "{names:?}"
        );
    }
}
