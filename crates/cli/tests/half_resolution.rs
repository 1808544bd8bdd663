//! The `--set "ID.Resolution=Half"` flags docs/benchmarks.md gives for
//! benching patches/post.ron and patches/emeshe-frame.ron with every
//! screen-space effect at half resolution: they name real nodes and pins,
//! and the frame then runs each effect's half pass and its upsample; and
//! `SPREADLIGHT_RESOLUTION_AUTO`, which forces what the pins' default Auto
//! resolves to, so one binary benches both ways.

use crate::support;

use support::{command, spreadlight, text};

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
    pass_names(&serde_json::from_str(&text(&o.stdout)).expect("JSON"))
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

/// `bench --json` of post.ron at 48x27 with SPREADLIGHT_RESOLUTION_AUTO set
/// to `value` (unset: None): the JSON line.
fn bench_auto(value: Option<&str>) -> serde_json::Value {
    let mut cmd = command(&[
        "bench",
        "patches/post.ron",
        "--size",
        "48x27",
        "--warmup",
        "0",
        "--frames",
        "1",
        "--json",
    ]);
    match value {
        Some(v) => cmd.env("SPREADLIGHT_RESOLUTION_AUTO", v),
        None => cmd.env_remove("SPREADLIGHT_RESOLUTION_AUTO"),
    };
    let o = cmd.output().expect("runs");
    assert_eq!(o.status.code(), Some(0), "{value:?}: {}", text(&o.stderr));
    serde_json::from_str(&text(&o.stdout)).expect("JSON")
}

fn pass_names(json: &serde_json::Value) -> Vec<String> {
    json["pass_order"]
        .as_array()
        .expect("pass_order")
        .iter()
        .filter_map(|p| p["name"].as_str().map(str::to_owned))
        .collect()
}

/// post.ron's SSAO, HBAO, SSGI and SSR leave their Resolution pin at Auto:
/// at 48x27 (below 1920x1080) they run at Full, `half` forces Half (the AO
/// and SSGI half chains: blur passes at half size too) and `full` Full;
/// `bench --json` says the choice and how many nodes of each effect ran
/// at half resolution. DOF has no Auto and stays at Full.
#[test]
fn the_auto_variable_forces_what_auto_resolves_to() {
    let effects = [
        ("SSAO #52", "raw (half)"),
        ("HBAO #53", "raw (half)"),
        ("SSGI #57", "gather (half)"),
        ("SSR #61", "trace (half)"),
    ];
    for (value, half) in [(None, false), (Some("full"), false), (Some("half"), true)] {
        let json = bench_auto(value);
        assert_eq!(
            json["resolution_auto"],
            value.unwrap_or("size"),
            "{value:?}"
        );
        let passes = pass_names(&json);
        for (node, what) in effects {
            assert_eq!(
                has(&passes, node, what),
                half,
                "{value:?}: {node} {what} in {passes:?}"
            );
        }
        for node in ["SSAO #52", "HBAO #53", "SSGI #57"] {
            assert_eq!(
                has(&passes, node, "blur y (half)"),
                half,
                "{value:?}: {node}'s blur at half size in {passes:?}"
            );
        }
        assert!(!has(&passes, "DOF #81", "(half)"), "{passes:?}");
        let counts = &json["half_resolution"];
        let n = u64::from(half);
        assert_eq!(counts["AO"], 2 * n, "{value:?}: {counts}");
        assert_eq!(counts["SSGI"], n, "{value:?}: {counts}");
        assert_eq!(counts["SSR"], n, "{value:?}: {counts}");
        assert_eq!(counts["DOF"], 0, "{value:?}: {counts}");
    }
    // A value the variable does not take is an error naming it.
    let o = command(&[
        "bench",
        "patches/post.ron",
        "--size",
        "48x27",
        "--frames",
        "1",
    ])
    .env("SPREADLIGHT_RESOLUTION_AUTO", "quarter")
    .output()
    .expect("runs");
    assert_ne!(o.status.code(), Some(0));
    assert!(
        text(&o.stderr).contains("SPREADLIGHT_RESOLUTION_AUTO"),
        "{}",
        text(&o.stderr)
    );
}
