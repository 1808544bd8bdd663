//! The driver's compiled pipelines, kept on disk between runs
//! (`wgpu::PipelineCache`, where the adapter offers `PIPELINE_CACHE`: Vulkan).
//!
//! A fresh process spends most of its first frame compiling pipelines (on
//! the H200, 1.6 s of 2.1 s for post.ron, `bench --json`'s `cold_start`). The
//! driver keeps a cache of its own, but a farm worker or a CI machine often
//! starts with it empty or cleared; this one lives in Spreadlight's cache
//! directory, so every run after the first on a machine finds the pipelines
//! it compiled before.
//!
//! Where: `SPREADLIGHT_CACHE_DIR`, else `$XDG_CACHE_HOME/spreadlight`, else
//! `~/.cache/spreadlight`; one file per adapter (`wgpu::util::pipeline_cache_key`:
//! vendor and device), whose header wgpu checks against the driver, so a
//! driver update makes the next run start empty and write the file anew.
//! `SPREADLIGHT_PIPELINE_CACHE=off` leaves it out (a run that must measure
//! the cold compile).
//!
//! The file is written when the last holder of the context drops it, or
//! when `render` leaves without dropping it (the CLI's `Evaluator::leave`),
//! only if the driver's data grew (something new was compiled), through a
//! temporary file and a rename, so a run killed half-way leaves the old file.

use std::path::PathBuf;
use std::sync::Arc;

/// What `SPREADLIGHT_PIPELINE_CACHE` says: off (`off`/`0`), on (`on`/`1`,
/// even on a CPU adapter), or None (the default: on for GPUs).
fn setting() -> Option<bool> {
    match std::env::var("SPREADLIGHT_PIPELINE_CACHE").as_deref() {
        Ok("off" | "0") => Some(false),
        Ok("on" | "1") => Some(true),
        _ => None,
    }
}

/// Whether `dir` holds a file of this cache with data in it, for any
/// adapter (the check runs before the driver loads, so before the adapter
/// is known). A save's temporary file left by a killed run does not count.
fn holds_kept_pipelines(dir: &std::path::Path) -> bool {
    std::fs::read_dir(dir).is_ok_and(|entries| {
        entries.flatten().any(|entry| {
            let name = entry.file_name();
            let name = name.to_string_lossy();
            name.starts_with(FILE_PREFIX)
                && !name.ends_with(".tmp")
                && entry.metadata().is_ok_and(|m| m.is_file() && m.len() > 0)
        })
    })
}

/// How `wgpu::util::pipeline_cache_key` begins every file's name.
const FILE_PREFIX: &str = "wgpu_pipeline_cache_";

static DRIVER_CACHE_OFF: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// Whether [`prefer_kept_pipelines`] turned the driver's disk cache off.
pub fn driver_disk_cache_turned_off() -> bool {
    DRIVER_CACHE_OFF.load(std::sync::atomic::Ordering::Relaxed)
}

/// NVIDIA's driver keeps a disk cache of its own (`__GL_SHADER_DISK_CACHE`,
/// on by default). Where this cache already holds a run's pipelines, the
/// driver's is redundant, and it is not free: on the H200 a warm start of
/// post.ron created its 46 pipelines in 126-138 ms with it and 81-92 ms
/// without (one device call; docs/benchmarks.md, "Session 25"), the same
/// whether 3 or 15 threads made them (the driver makes them one at a time).
///
/// So where this cache's folder holds a file with data (for any adapter),
/// and neither the user set the driver's variable nor turned this cache
/// off, the driver's is turned off for this process. A machine's first
/// run (no file yet) keeps the driver's; other drivers ignore the
/// variable. Returns whether it turned it off.
///
/// # Safety
///
/// It sets an environment variable (the driver reads it when it loads):
/// call it before any other thread of the process starts, first thing in
/// `main`, as nothing may read the environment while it changes.
#[allow(unsafe_code)]
pub unsafe fn prefer_kept_pipelines() -> bool {
    const DRIVER_CACHE: &str = "__GL_SHADER_DISK_CACHE";
    if std::env::var_os(DRIVER_CACHE).is_some() || setting() == Some(false) {
        return false;
    }
    let kept = holds_kept_pipelines(&cache_dir());
    if kept {
        DRIVER_CACHE_OFF.store(true, std::sync::atomic::Ordering::Relaxed);
        // SAFETY: no other thread runs yet (this function's contract).
        unsafe {
            std::env::set_var(DRIVER_CACHE, "0");
        }
    }
    kept
}

/// A pipeline cache read from disk, saved back when dropped.
pub struct DiskPipelineCache {
    cache: wgpu::PipelineCache,
    path: PathBuf,
    /// Bytes read from the file (0 when none).
    loaded: usize,
    /// Bytes of the driver's data once made from them: what it took of the
    /// file (about the header's size where it refused a stale or damaged
    /// one). No more when saved means nothing new was compiled.
    accepted: usize,
    /// The file is not what the driver holds (refused, or written by
    /// another driver): it is replaced when the cache is saved, grown or not.
    stale: bool,
}

impl std::fmt::Debug for DiskPipelineCache {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "DiskPipelineCache({})", self.path.display())
    }
}

/// Spreadlight's cache directory (see the module docs).
pub use spreadlight_dirs::cache_dir;

impl DiskPipelineCache {
    /// The cache for `device` on the adapter `info` describes, from its file
    /// when there is one; None when the device lacks `PIPELINE_CACHE`, the
    /// backend has no cache key, or the user turned it off.
    pub fn open(device: &wgpu::Device, info: &wgpu::AdapterInfo) -> Option<Arc<Self>> {
        if !device.features().contains(wgpu::Features::PIPELINE_CACHE) {
            return None;
        }
        let wanted = setting().unwrap_or_else(|| {
            crate::adapter_class::AdapterClass::of(info) == crate::adapter_class::AdapterClass::Gpu
        });
        if !wanted {
            return None;
        }
        let key = wgpu::util::pipeline_cache_key(info)?;
        let path = cache_dir().join(key);
        // A missing or unreadable file is a cold start, not an error.
        let data = std::fs::read(&path).ok();
        // SAFETY: `data` is what an earlier run's `PipelineCache::get_data`
        // wrote to a file named by `pipeline_cache_key` for this adapter.
        // wgpu prefixes that data with a header (magic, version, adapter
        // and driver identity, length and hash of the body) that it checks
        // before the driver sees a byte, and with `fallback` a file that
        // fails the check (truncated, edited, another driver) gives an
        // empty cache instead of an error. What the check cannot prove is
        // that nobody wrote a well-formed file with a matching hash and a
        // hostile body; the cache directory is the user's own.
        #[allow(unsafe_code)]
        let cache = unsafe {
            device.create_pipeline_cache(&wgpu::PipelineCacheDescriptor {
                label: Some("spreadlight pipeline cache"),
                data: data.as_deref(),
                fallback: true,
            })
        };
        // Measured from the driver, not the file: after a driver update the
        // file (named by the adapter alone) is refused, and comparing with
        // its size would keep a smaller fresh cache from ever being saved.
        // (A driver whose data holds no pipelines, as lavapipe's, never
        // grows it: a refused file is replaced all the same.)
        let fresh = data.as_ref().and_then(|_| cache.get_data());
        let stale = data.is_some() && fresh != data;
        Some(Arc::new(DiskPipelineCache {
            cache,
            path,
            loaded: data.map_or(0, |d| d.len()),
            accepted: fresh.map_or(0, |d| d.len()),
            stale,
        }))
    }

    pub fn cache(&self) -> &wgpu::PipelineCache {
        &self.cache
    }

    pub fn path(&self) -> &std::path::Path {
        &self.path
    }

    /// Bytes read from the file when the cache was made (0: a cold start).
    pub fn loaded_bytes(&self) -> usize {
        self.loaded
    }

    /// Bytes of the driver's data right after it was made from the file
    /// (0 without a file; small where the driver refused it).
    pub fn accepted_bytes(&self) -> usize {
        self.accepted
    }

    /// Write the driver's data to the file if it grew since it was made, or
    /// if the file was not what the driver took.
    /// Errors are returned for a caller that wants them; dropping the cache
    /// saves too and only warns ([`DiskPipelineCache::save_or_warn`]).
    pub fn save(&self) -> std::io::Result<bool> {
        let Some(data) = self.cache.get_data() else {
            return Ok(false);
        };
        if data.len() <= self.accepted && !self.stale {
            return Ok(false);
        }
        if let Some(dir) = self.path.parent() {
            std::fs::create_dir_all(dir)?;
        }
        let temp = self
            .path
            .with_extension(format!("{}.tmp", std::process::id()));
        std::fs::write(&temp, &data)?;
        std::fs::rename(&temp, &self.path)?;
        Ok(true)
    }

    /// [`DiskPipelineCache::save`], a failure a warning on stderr: nothing
    /// else is lost, the next run compiles again.
    pub fn save_or_warn(&self) {
        if let Err(e) = self.save() {
            eprintln!(
                "warning: could not save the pipeline cache to {}: {e}",
                self.path.display()
            );
        }
    }
}

impl Drop for DiskPipelineCache {
    fn drop(&mut self) {
        self.save_or_warn();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_a_cache_file_with_data_counts_as_kept_pipelines() {
        let dir = tempfile::tempdir().expect("temp dir");
        assert!(!holds_kept_pipelines(&dir.path().join("missing")));
        assert!(!holds_kept_pipelines(dir.path()), "empty folder");
        std::fs::write(dir.path().join("other.bin"), b"data").expect("write");
        assert!(!holds_kept_pipelines(dir.path()), "not a cache file");
        let temp = dir
            .path()
            .join(format!("{FILE_PREFIX}vulkan_4318_9013.1234.tmp"));
        std::fs::write(&temp, b"data").expect("write");
        assert!(
            !holds_kept_pipelines(dir.path()),
            "a killed save's temporary file"
        );
        let file = dir.path().join(format!("{FILE_PREFIX}vulkan_4318_9013"));
        std::fs::write(&file, b"").expect("write");
        assert!(!holds_kept_pipelines(dir.path()), "an empty cache file");
        std::fs::write(&file, b"data").expect("write");
        assert!(holds_kept_pipelines(dir.path()));
    }

    #[test]
    fn the_file_prefix_is_wgpus() {
        let info = wgpu::AdapterInfo {
            vendor: 0x10de,
            device: 0x2335,
            ..wgpu::AdapterInfo::new(wgpu::DeviceType::DiscreteGpu, wgpu::Backend::Vulkan)
        };
        let key = wgpu::util::pipeline_cache_key(&info).expect("Vulkan has a key");
        assert!(key.starts_with(FILE_PREFIX), "{key}");
    }
}
