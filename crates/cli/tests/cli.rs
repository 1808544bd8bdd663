//! The `spreadlight` binary as a user runs it: exit codes, messages, output.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn spreadlight(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_spreadlight"))
        .args(args)
        .current_dir(root())
        .output()
        .expect("runs")
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

#[test]
fn check_passes_every_example() {
    let out = spreadlight(&["check", "patches"]);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}{}",
        text(&out.stdout),
        text(&out.stderr)
    );
    assert!(text(&out.stderr).contains("0 error(s), 0 warning(s)"));
}

#[test]
fn check_reports_every_bad_patch_and_exits_1() {
    let out = spreadlight(&["check", "patches/bad"]);
    assert_eq!(out.status.code(), Some(1));
    let stdout = text(&out.stdout);
    let files = std::fs::read_dir(root().join("patches/bad"))
        .expect("ls")
        .count();
    for entry in std::fs::read_dir(root().join("patches/bad")).expect("ls") {
        let name = entry
            .expect("entry")
            .file_name()
            .into_string()
            .expect("utf-8");
        assert!(stdout.contains(&name), "{name} not reported in:\n{stdout}");
    }
    assert!(text(&out.stderr).contains(&format!("checked {files} patch(es)")));
}

#[test]
fn a_warning_alone_passes_unless_warnings_are_denied() {
    let path = "patches/bad/21-unknown-node-type.ron";
    assert_eq!(spreadlight(&["check", path]).status.code(), Some(0));
    assert_eq!(
        spreadlight(&["check", "--deny-warnings", path])
            .status
            .code(),
        Some(1)
    );
}

#[test]
fn a_missing_file_is_named() {
    let out = spreadlight(&["check", "patches/no-such-patch.ron"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(
        text(&out.stdout).contains("no-such-patch.ron: cannot read the patch"),
        "{}",
        text(&out.stdout)
    );
}

#[test]
fn usage_errors_exit_2() {
    assert_eq!(spreadlight(&["check"]).status.code(), Some(2));
    assert_eq!(spreadlight(&["frobnicate"]).status.code(), Some(2));
    assert_eq!(
        spreadlight(&["eval", "patches/lfo-sine.ron", "--fps", "0"])
            .status
            .code(),
        Some(2)
    );
}

#[test]
fn every_command_has_help() {
    for args in [
        &["--help"][..],
        &["check", "--help"],
        &["eval", "--help"],
        &["nodes", "--help"],
    ] {
        let out = spreadlight(args);
        assert_eq!(out.status.code(), Some(0), "{args:?}");
        assert!(text(&out.stdout).contains("Usage:"), "{args:?}");
    }
}

#[test]
fn eval_prints_probed_values_per_frame() {
    let out = spreadlight(&[
        "eval",
        "patches/lfo-sine.ron",
        "--frames",
        "31",
        "--probe",
        "wave",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    let stdout = text(&out.stdout);
    let lines: Vec<&str> = stdout.lines().collect();
    assert_eq!(lines.len(), 31);
    assert!(
        lines[0].starts_with("frame 0 t=0.0000  wave = [0.0] (1 slices)"),
        "{}",
        lines[0]
    );
    assert!(
        lines[30].starts_with("frame 30 t=0.5000  wave = [10.0] (1 slices)"),
        "{}",
        lines[30]
    );
}

#[test]
fn eval_stats_is_json_with_the_runtime_counters() {
    let out = spreadlight(&["eval", "patches/lfo-sine.ron", "--frames", "3", "--stats"]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).expect("valid JSON");
    let frames = json["frames"].as_array().expect("frames");
    assert_eq!(frames.len(), 3);
    for (i, frame) in frames.iter().enumerate() {
        assert_eq!(frame["frame"], i as u64);
        let stats = &frame["stats"];
        let nodes = stats["nodes"].as_array().expect("per-node stats").len() as u64;
        let counted = ["evaluated", "reused", "skipped"]
            .iter()
            .map(|k| stats[k].as_u64().expect("count"))
            .sum::<u64>();
        assert_eq!(counted, nodes, "every node is evaluated, reused or skipped");
    }
}

#[test]
fn eval_names_a_probe_that_does_not_exist() {
    let out = spreadlight(&["eval", "patches/lfo-sine.ron", "--probe", "nothing"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(text(&out.stderr).contains("no probe named `nothing`"));
}

#[test]
fn nodes_lists_the_registry() {
    let out = spreadlight(&["nodes"]);
    assert_eq!(out.status.code(), Some(0));
    let stdout = text(&out.stdout);
    for name in [
        "Add (Value)",
        "LFO",
        "LinearSpread",
        "Camera",
        "Probe",
        "Translate (Transform)",
    ] {
        assert!(stdout.contains(name), "{name} missing");
    }
}
