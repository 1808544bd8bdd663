//! `spreadlight accuracy gltf` at a tiny size: the GPU's shaded glTF floor
//! stays within a stated bound of the CPU reference, and filtering the maps
//! reduces the aliasing error against the supersampled reference.

use std::path::Path;
use std::process::Command;

/// Point filtering samples the texels the CPU reference samples: what is
/// left is the GPU's half-float targets, sRGB decoding in hardware and the
/// odd pixel whose centre falls on another side of a texel edge.
const POINT_RMSE_BOUND: f64 = 0.03;

#[test]
fn filtering_reduces_aliasing_and_point_sampling_matches_the_reference() {
    let dir = tempfile::tempdir().expect("tempdir");
    let table = dir.path().join("gltf.md");
    let plot = dir.path().join("gltf.svg");
    let out = Command::new(env!("CARGO_BIN_EXE_spreadlight"))
        .args([
            "accuracy",
            "gltf",
            "--error-size",
            "96x54",
            "--time-size",
            "96x54",
            "--warmup",
            "0",
            "--frames",
            "1",
            "--out",
            table.to_str().expect("utf-8"),
            "--plot",
            plot.to_str().expect("utf-8"),
        ])
        .current_dir(Path::new(env!("CARGO_MANIFEST_DIR")).join("../.."))
        .output()
        .expect("runs");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    // | filtering | resolve ms | RMSE vs 1 ray | SSIM vs 1 ray | RMSE vs 16 rays | SSIM vs 16 rays |
    let rows: Vec<(String, Vec<f64>)> = stdout
        .lines()
        .filter(|l| l.starts_with("| ") && !l.starts_with("| filtering"))
        .map(|l| {
            let cells: Vec<&str> = l.split('|').map(str::trim).collect();
            let numbers = cells[3..7]
                .iter()
                .map(|c| c.parse::<f64>().expect("a number"))
                .collect();
            (cells[1].to_owned(), numbers)
        })
        .collect();
    assert_eq!(rows.len(), 4, "{stdout}");
    let row = |name: &str| {
        &rows
            .iter()
            .find(|(n, _)| n == name)
            .unwrap_or_else(|| panic!("{name} in {stdout}"))
            .1
    };
    for (name, numbers) in &rows {
        assert!(numbers.iter().all(|v| v.is_finite()), "{name}: {numbers:?}");
    }
    let (point, trilinear, anisotropic) = (
        row("point (mip 0)"),
        row("trilinear"),
        row("trilinear + 16x anisotropic"),
    );
    assert!(
        point[0] < POINT_RMSE_BOUND && point[1] > 0.9,
        "point filtering against the point-sampled reference: {point:?}"
    );
    // Against the 16-ray reference: mips remove aliasing that point sampling keeps.
    assert!(
        trilinear[2] < 0.8 * point[2] && anisotropic[2] < 0.8 * point[2],
        "aliasing error: point {point:?}, trilinear {trilinear:?}, anisotropic {anisotropic:?}"
    );
    assert_eq!(
        std::fs::read_to_string(&table).expect("the table"),
        stdout.as_ref()
    );
    let svg = std::fs::read_to_string(&plot).expect("the plot");
    assert!(svg.starts_with("<svg") && svg.contains("16 rays"));
}
