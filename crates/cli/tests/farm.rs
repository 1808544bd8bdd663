//! The farm on a real Dask cluster: tools/farm/test_farm.py starts a
//! scheduler and three workers on localhost, renders a shipped patch in
//! chunks through tools/farm/farm.py, kills a worker mid-chunk and checks
//! each frame exists once, complete, equal to a single-process render; then
//! that a re-submission renders only missing frames. It fails (never skips)
//! when Python or Dask distributed is missing: .ci/run installs them.

use std::path::Path;
use std::process::Command;

#[test]
fn a_dask_cluster_renders_chunks_and_survives_a_killed_worker() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let out = Command::new("python3")
        .arg(root.join("tools/farm/test_farm.py"))
        .args(["--spreadlight", env!("CARGO_BIN_EXE_spreadlight")])
        .current_dir(&root)
        .output()
        .expect("python3 runs (Debian's python3; .ci/run installs Dask distributed)");
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(out.status.success(), "{text}");
    assert!(text.contains("one killed mid-chunk"), "{text}");
    assert!(
        text.contains("rendered only the two missing frames"),
        "{text}"
    );
}
