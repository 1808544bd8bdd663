//! Shared helpers for the workspace tests: where the example and bad patches live.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use spreadlight_graph::{FrameClock, Patch, Runtime, format};
use spreadlight_nodes::output::RenderedImages;
use spreadlight_render::image_io::Encoding;
use spreadlight_render::readback::ImageF32;

pub mod float_compare;

/// Set in a process [`ran_in_a_process_of_its_own`] started.
const OWN_PROCESS: &str = "SPREADLIGHT_TEST_OWN_PROCESS";

/// Runs `test` (its whole name, `file::test`) again in a process of the
/// running test binary of its own, with Mesa's shader cache off, asserts
/// that it passed there, and says whether this was the process that started
/// it: the test is then done, and returns at once. In the process started,
/// false: the test runs.
///
/// Why: Mesa's lavapipe (22.3, what CI runs) now and then crashes (SIGSEGV
/// in libvulkan_lvp.so) while rendering fused light sets with its shader
/// cache on. Session 29 saw the two fused-set tests of patches.rs crash 7
/// times in 24 run one after the other in one process, never in 16 each
/// alone, and never in 16 with `MESA_SHADER_CACHE_DISABLE=true`, and gave
/// each a process of its own. Session 30 saw them crash alone too: once in
/// a full test run, 1 in 16 and 1 in 24 runs of one test (gdb: lavapipe's
/// queue thread, once a thread creating a pipeline; neither one device for
/// the whole test nor creating pipelines one at a time helped). So the
/// process started runs with the cache off, which costs each of the two
/// tests about 18 s of compiling on the development machine.
pub fn ran_in_a_process_of_its_own(test: &str) -> bool {
    ran_in_a_process_of_its_own_with(test, &[("MESA_SHADER_CACHE_DISABLE", "true")])
}

/// [`ran_in_a_process_of_its_own`] with `env` set in the process started
/// (`frame_allocations.rs` counts with library backtraces off).
pub fn ran_in_a_process_of_its_own_with(test: &str, env: &[(&str, &str)]) -> bool {
    if std::env::var_os(OWN_PROCESS).is_some() {
        return false;
    }
    let out = std::process::Command::new(std::env::current_exe().expect("this test binary"))
        .args([test, "--exact", "--nocapture", "--test-threads=1"])
        .env(OWN_PROCESS, "1")
        .envs(env.iter().copied())
        .output()
        .expect("the test's own process runs");
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    println!("{text}");
    assert!(
        out.status.success() && text.contains("1 passed"),
        "{test} failed in its own process ({}):\n{text}",
        out.status
    );
    true
}

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

/// The host service that makes a patch's relative file names resolve beside it.
pub fn patch_dir(path: &Path) -> std::sync::Arc<spreadlight_graph::PatchDir> {
    let dir = path.parent().unwrap_or(Path::new("")).to_path_buf();
    std::sync::Arc::new(spreadlight_graph::PatchDir(dir))
}

/// Render frame `frame` of a patch at `size` on the test GPU and return the
/// image its Output named `output` produced.
pub fn render_patch(path: &Path, size: (u32, u32), frame: u64, output: &str) -> ImageF32 {
    let mut run = PatchRun::new(path, size, |_| {});
    run.run_to(frame);
    run.image(output).0
}

/// A patch running on the test GPU at a fixed 60 fps, frame after frame,
/// with the images its Outputs rendered at the last frame.
pub struct PatchRun {
    path: PathBuf,
    rt: Runtime,
    images: Arc<RenderedImages>,
    renderer: Arc<spreadlight_render::Renderer>,
    next: u64,
}

impl PatchRun {
    /// Load the patch at `path`, changed by `edit` (a test's pin values),
    /// onto a renderer of output size `size`. Panics on any load problem.
    pub fn new(path: &Path, size: (u32, u32), edit: impl FnOnce(&mut Patch)) -> Self {
        let mut patch = format::load(path).unwrap_or_else(|e| panic!("{e}"));
        edit(&mut patch);
        let mut rt = Runtime::new(spreadlight_nodes::registry());
        rt.provide(patch_dir(path));
        let renderer = spreadlight_render::renderer::test_renderer();
        renderer.set_output_size(size);
        spreadlight_nodes::gpu::provide_renderer(&mut rt, renderer.clone());
        let images = Arc::new(RenderedImages::default());
        rt.provide(images.clone());
        let problems = rt.load(&patch).to_vec();
        assert!(problems.is_empty(), "{}: {problems:?}", path.display());
        PatchRun {
            path: path.to_owned(),
            rt,
            images,
            renderer,
            next: 0,
        }
    }

    /// The renderer the patch runs on (a test sets its recording mode).
    pub fn renderer(&self) -> &Arc<spreadlight_render::Renderer> {
        &self.renderer
    }

    /// Evaluate every frame from the next one to `frame`; panics on a node error.
    pub fn run_to(&mut self, frame: u64) {
        while self.next <= frame {
            self.rt.evaluate(FrameClock::fixed(self.next, 60.0));
            self.next += 1;
        }
        let errors: Vec<String> = self
            .rt
            .node_errors()
            .map(|(id, e)| format!("{id}: {e}"))
            .collect();
        assert!(errors.is_empty(), "{}: {errors:?}", self.path.display());
    }

    /// Evaluate the next frame with every sink rendering again though
    /// nothing changed (as `spreadlight bench` times frames); panics on a
    /// node error.
    pub fn render_next(&mut self) {
        self.rt.invalidate_sinks();
        self.run_to(self.next);
    }

    /// The image the Output named `output` rendered last, and the encoding it asks for.
    pub fn image(&self, output: &str) -> (ImageF32, Encoding) {
        self.images
            .get(output)
            .unwrap_or_else(|| panic!("{}: no output `{output}`", self.path.display()))
    }

    /// The names of the Outputs that rendered.
    pub fn outputs(&self) -> Vec<String> {
        self.images.names()
    }
}
