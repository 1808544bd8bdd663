//! Shared helpers for the workspace tests: where the example and bad patches live.

use std::path::{Path, PathBuf};

/// The repository root (this crate lives in `tests/`).
pub fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .map(Path::to_owned)
        .unwrap_or_default()
}

/// The `.ron` files directly in `dir`, sorted.
pub fn ron_files(dir: &Path) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("cannot list {}: {e}", dir.display()))
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.is_file() && p.extension().is_some_and(|e| e == "ron"))
        .collect();
    files.sort();
    files
}

/// The example patches in `patches/`.
pub fn example_patches() -> Vec<PathBuf> {
    ron_files(&root().join("patches"))
}

/// The bad patches in `patches/bad/`.
pub fn bad_patches() -> Vec<PathBuf> {
    ron_files(&root().join("patches/bad"))
}
