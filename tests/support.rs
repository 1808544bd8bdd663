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

/// Render frame `frame` of a patch at `size` on the test GPU and return the
/// image its Output named `output` produced.
/// The host service that makes a patch's relative file names resolve beside it.
pub fn patch_dir(path: &Path) -> std::sync::Arc<spreadlight_graph::PatchDir> {
    let dir = path.parent().unwrap_or(Path::new("")).to_path_buf();
    std::sync::Arc::new(spreadlight_graph::PatchDir(dir))
}

pub fn render_patch(
    path: &Path,
    size: (u32, u32),
    frame: u64,
    output: &str,
) -> spreadlight_render::readback::ImageF32 {
    use spreadlight_graph::{FrameClock, Runtime, format};
    let patch = format::load(path).unwrap_or_else(|e| panic!("{e}"));
    let mut rt = Runtime::new(spreadlight_nodes::registry());
    rt.provide(patch_dir(path));
    let renderer = spreadlight_render::renderer::test_renderer();
    renderer.set_output_size(size);
    spreadlight_nodes::gpu::provide_renderer(&mut rt, renderer);
    let images = std::sync::Arc::new(spreadlight_nodes::output::RenderedImages::default());
    rt.provide(images.clone());
    let problems = rt.load(&patch).to_vec();
    assert!(problems.is_empty(), "{}: {problems:?}", path.display());
    for f in 0..=frame {
        rt.evaluate(FrameClock::fixed(f, 60.0));
    }
    let errors: Vec<String> = rt
        .node_errors()
        .map(|(id, e)| format!("{id}: {e}"))
        .collect();
    assert!(errors.is_empty(), "{}: {errors:?}", path.display());
    images
        .get(output)
        .unwrap_or_else(|| panic!("{}: no output `{output}`", path.display()))
        .0
}
