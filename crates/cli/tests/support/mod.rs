//! Shared by the sequence tests: running `spreadlight render`, reading its
//! JSON lines and images, and variants of a shipped patch.

#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

pub fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

pub fn command(args: &[&str]) -> Command {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_spreadlight"));
    cmd.args(args).current_dir(root());
    cmd
}

pub fn spreadlight(args: &[&str]) -> Output {
    command(args).output().expect("runs")
}

pub fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

pub fn path(p: &Path) -> &str {
    p.to_str().expect("utf-8")
}

/// The JSON lines a `--json` run printed.
pub fn events(out: &Output) -> Vec<serde_json::Value> {
    text(&out.stdout)
        .lines()
        .map(|l| serde_json::from_str(l).unwrap_or_else(|e| panic!("not JSON: {l}: {e}")))
        .collect()
}

/// Each frame event's (frame, status).
pub fn statuses(out: &Output) -> Vec<(u64, String)> {
    events(out)
        .iter()
        .filter(|e| e["event"] == "frame")
        .map(|e| {
            (
                e["frame"].as_u64().expect("frame"),
                e["status"].as_str().expect("status").to_owned(),
            )
        })
        .collect()
}

pub fn done(out: &Output) -> serde_json::Value {
    events(out)
        .into_iter()
        .find(|e| e["event"] == "done")
        .unwrap_or_else(|| {
            panic!(
                "no done event in {}{}",
                text(&out.stdout),
                text(&out.stderr)
            )
        })
}

pub fn ok(out: &Output) {
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}{}",
        text(&out.stdout),
        text(&out.stderr)
    );
}

/// The file names in `dir`, sorted (dot files included).
pub fn listing(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .expect("ls")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

/// An EXR's RGB values.
pub fn rgb(path: &Path) -> Vec<f32> {
    let image = image::open(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .to_rgba32f();
    image
        .pixels()
        .flat_map(|p| [p.0[0], p.0[1], p.0[2]])
        .collect()
}

pub fn max_difference(a: &[f32], b: &[f32]) -> f32 {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f32::max)
}

pub fn mean_difference(a: &[f32], b: &[f32]) -> f32 {
    a.iter().zip(b).map(|(x, y)| (x - y).abs()).sum::<f32>() / a.len() as f32
}

/// patches/gbuffer-spheres.ron with `edits` (text replacements), written into `dir`.
pub fn spheres_variant(dir: &Path, name: &str, edits: &[(&str, &str)]) -> PathBuf {
    let mut text =
        std::fs::read_to_string(root().join("patches/gbuffer-spheres.ron")).expect("read");
    for (from, to) in edits {
        assert!(text.contains(from), "the patch has no `{from}`");
        text = text.replacen(from, to, 1);
    }
    let out = dir.join(name);
    std::fs::write(&out, text).expect("write");
    out
}

/// gbuffer-spheres with a second `Output`, named `copy`, of the same texture.
pub fn two_outputs(dir: &Path) -> PathBuf {
    spheres_variant(
        dir,
        "two-outputs.ron",
        &[(
            "    ],\n    links: [\n",
            "        (\n            id: 99,\n            type: \"Output\",\n            values: {\n                \"Name\": String([\"copy\"]),\n            },\n        ),\n    ],\n    links: [\n        (\n            from: (8, \"Texture\"),\n            to: (99, \"Texture\"),\n        ),\n",
        )],
    )
}

/// The `q` quantile (0..1) of the absolute differences.
pub fn quantile_difference(a: &[f32], b: &[f32], q: f64) -> f32 {
    let mut d: Vec<f32> = a.iter().zip(b).map(|(x, y)| (x - y).abs()).collect();
    d.sort_by(f32::total_cmp);
    d[((d.len() - 1) as f64 * q) as usize]
}

/// RGB values of an image `factor` x `factor` larger, box-downsampled.
pub fn downsampled(values: &[f32], width: usize, factor: usize) -> Vec<f32> {
    let height = values.len() / 3 / width;
    let (w, h) = (width / factor, height / factor);
    let mut out = vec![0.0f32; w * h * 3];
    for y in 0..height {
        for x in 0..width {
            for c in 0..3 {
                out[((y / factor) * w + x / factor) * 3 + c] +=
                    values[(y * width + x) * 3 + c] / (factor * factor) as f32;
            }
        }
    }
    out
}

pub fn rmse(a: &[f32], b: &[f32]) -> f32 {
    (a.iter().zip(b).map(|(x, y)| (x - y) * (x - y)).sum::<f32>() / a.len() as f32).sqrt()
}
