//! The `--set "ID.Resolution=Half"` flags docs/benchmarks.md gives for
//! benching patches/post.ron and patches/emeshe-frame.ron with every
//! screen-space effect at half resolution: they name real nodes and pins,
//! and the frame then runs each effect's half pass and its upsample.

use crate::support;

use support::{spreadlight, text};

/// The flags of docs/benchmarks.md ("Half-resolution effects"), per patch.
const POST: [&str; 5] = ["52", "53", "57", "61", "81"];
const EMESHE_FRAME: [&str; 3] = ["34", "38", "43"];

fn bench_half(patch: &str, ids: &[&str]) -> Vec<String> {
    let sets: Vec<String> = ids
        .iter()
        .map(|id| format!("{id}.Resolution=Half"))
        .collect();
    let mut args = vec![
        "bench", patch, "--size", "48x27", "--warmup", "0", "--frames", "1", "--json",
    ];
    for set in &sets {
        args.extend(["--set", set.as_str()]);
    }
    let o = spreadlight(&args);
    assert_eq!(o.status.code(), Some(0), "{patch}: {}", text(&o.stderr));
    let json: serde_json::Value = serde_json::from_str(&text(&o.stdout)).expect("JSON");
    json["pass_order"]
        .as_array()
        .expect("pass_order")
        .iter()
        .filter_map(|p| p["name"].as_str().map(str::to_owned))
        .collect()
}

fn has(passes: &[String], prefix: &str, what: &str) -> bool {
    passes
        .iter()
        .any(|p| p.starts_with(prefix) && p.ends_with(what))
}

#[test]
fn every_effect_of_post_ron_runs_at_half_resolution() {
    let passes = bench_half("patches/post.ron", &POST);
    for (node, what) in [
        ("SSAO #52", "raw (half)"),
        ("HBAO #53", "raw (half)"),
        ("SSGI #57", "gather (half)"),
        ("SSR #61", "trace (half)"),
        ("DOF #81", "blur (half)"),
    ] {
        assert!(has(&passes, node, what), "{node}: {what} in {passes:?}");
        assert!(
            has(&passes, node, "upsample"),
            "{node} upsamples: {passes:?}"
        );
    }
}

#[test]
fn every_effect_of_the_emeshe_frame_runs_at_half_resolution() {
    let passes = bench_half("patches/emeshe-frame.ron", &EMESHE_FRAME);
    for (node, what) in [
        ("SSAO #34", "raw (half)"),
        ("SSR #38", "trace (half)"),
        ("DOF #43", "blur (half)"),
    ] {
        assert!(has(&passes, node, what), "{node}: {what} in {passes:?}");
        assert!(
            has(&passes, node, "upsample"),
            "{node} upsamples: {passes:?}"
        );
    }
}
