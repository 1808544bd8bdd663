//! Frames submitted on a submission thread (`SPREADLIGHT_SUBMIT=thread`,
//! docs/benchmarks.md "cpu22") render the bytes inline submission renders:
//! a sequence of post.ron (TAA's and motion blur's history, autofocus read
//! back across frames, frames in flight read back on other threads), and
//! `bench` reports the submission thread's time beside the recording
//! thread's, with `--wall` too. 64x36 (lavapipe in CI is slow).

use crate::support::*;

fn render(out: &std::path::Path, submit: &str) {
    let mut cmd = command(&[
        "render",
        "patches/post.ron",
        "-o",
        path(out),
        "--size",
        "64x36",
        "--frames",
        "0-3",
    ]);
    cmd.env("SPREADLIGHT_SUBMIT", submit);
    let o = cmd.output().expect("runs");
    assert_eq!(o.status.code(), Some(0), "{submit}: {}", text(&o.stderr));
}

#[test]
fn a_sequence_submitted_on_the_thread_has_the_bytes_of_inline_submission() {
    let dir = tempfile::tempdir().expect("tempdir");
    let inline = dir.path().join("inline/f_#.png");
    let thread = dir.path().join("thread/f_#.png");
    render(&inline, "inline");
    render(&thread, "thread");
    for f in 0..4 {
        let read = |sub: &str| {
            let p = dir.path().join(format!("{sub}/f_{f}.png"));
            std::fs::read(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
        };
        assert!(read("inline") == read("thread"), "frame {f} differs");
    }
    // An unknown setting is an error naming the variable.
    let mut cmd = command(&["render", "patches/post.ron", "-o", path(&inline)]);
    let o = cmd
        .env("SPREADLIGHT_SUBMIT", "later")
        .output()
        .expect("runs");
    assert_ne!(o.status.code(), Some(0));
    assert!(
        text(&o.stderr).contains("SPREADLIGHT_SUBMIT"),
        "{}",
        text(&o.stderr)
    );
}

#[test]
fn bench_reports_the_submission_threads_time_apart_from_the_recording_threads() {
    let bench = |submit: &str| {
        let o = spreadlight(&[
            "bench",
            "patches/bench-gbuffer.ron",
            "--size",
            "32x18",
            "--warmup",
            "2",
            "--frames",
            "3",
            "--timing",
            "frame",
            "--recording",
            "batched",
            "--wall",
            "--submit",
            submit,
            "--json",
        ]);
        assert_eq!(o.status.code(), Some(0), "{submit}: {}", text(&o.stderr));
        let json: serde_json::Value = serde_json::from_str(&text(&o.stdout)).expect("JSON");
        assert_eq!(json["submit"], submit);
        json
    };
    let thread = bench("thread");
    for prefix in ["", "wall_"] {
        let ms = |key: &str| {
            let key = format!("{prefix}{key}");
            thread[&key]
                .as_f64()
                .unwrap_or_else(|| panic!("{key}: {thread}"))
        };
        let cpu = ms("cpu_ms_median");
        let own = ms("cpu_submission_thread_ms_median");
        assert!(own > 0.0, "{prefix}: the thread's time");
        // Medians of sums are not sums of medians: the total is at least
        // the larger part, and never the recording thread's alone.
        let total = ms("cpu_total_ms_median");
        assert!(total >= cpu.max(own) * 0.999 && total > 0.0, "{thread}");
        assert!(ms("cpu_critical_ms_median") >= cpu * 0.999, "{thread}");
        assert!(ms("cpu_submission_wait_ms_median") >= 0.0);
    }
    let inline = bench("inline");
    assert!(
        inline["cpu_submission_thread_ms_median"].is_null(),
        "{inline}"
    );
    assert!(inline["wall_cpu_submission_thread_ms_median"].is_null());
    assert_eq!(inline["cpu_total_ms_median"], inline["cpu_ms_median"]);
    assert_eq!(inline["cpu_submission_wait_ms_median"], 0.0);
}
