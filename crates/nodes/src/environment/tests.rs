//! The environment nodes' bad input: a missing or corrupt image file and bad
//! pins are errors on the pin that name the file or the slice.

use spreadlight_graph::Spread;

use crate::testing::{eval_err, floats};

fn file(path: &std::path::Path) -> Spread {
    Spread::String(vec![path.display().to_string()])
}

#[test]
fn a_missing_environment_file_is_an_error_naming_it() {
    let dir = tempfile::tempdir().expect("tempdir");
    let missing = dir.path().join("nowhere.hdr");
    let e = eval_err(
        "Environment (File)",
        &[("Filename", file(&missing))],
        "Filename",
    );
    assert!(e.to_string().contains("nowhere.hdr"), "{e}");
    let e = eval_err("Environment (File)", &[], "Filename");
    assert!(e.to_string().contains("no file given"), "{e}");
}

#[test]
fn a_corrupt_environment_file_is_an_error_naming_it() {
    let dir = tempfile::tempdir().expect("tempdir");
    let corrupt = dir.path().join("broken.hdr");
    std::fs::write(
        &corrupt,
        b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 4 +X 4\ngarbage",
    )
    .expect("write");
    let e = eval_err(
        "Environment (File)",
        &[("Filename", file(&corrupt))],
        "Filename",
    );
    assert!(e.to_string().contains("broken.hdr"), "{e}");
    let text = dir.path().join("notes.exr");
    std::fs::write(&text, b"not an image at all").expect("write");
    let e = eval_err(
        "Environment (File)",
        &[("Filename", file(&text))],
        "Filename",
    );
    assert!(e.to_string().contains("notes.exr"), "{e}");
}

#[test]
fn bad_environment_pins_are_errors_naming_the_pin() {
    let e = eval_err(
        "Environment (Sky)",
        &[("Glow", floats(&[1.0, f32::NAN]))],
        "Glow",
    );
    assert!(e.to_string().contains("slice 1"), "{e}");
    let e = eval_err(
        "Environment (Sky)",
        &[("Cube Size", Spread::Int(vec![0]))],
        "Cube Size",
    );
    assert!(e.to_string().contains("at least 1"), "{e}");
    let e = eval_err("Reflection", &[("IOR", floats(&[f32::INFINITY]))], "IOR");
    assert!(e.to_string().contains("NaN or infinite"), "{e}");
    let e = eval_err("SSR", &[("Blend", floats(&[f32::NAN]))], "Blend");
    assert!(e.to_string().contains("slice 0"), "{e}");
    let e = eval_err("SSR", &[("Rays", Spread::Int(vec![0]))], "Rays");
    assert!(e.to_string().contains("at least 1"), "{e}");
}

/// A probe's bad numbers are errors on their pins, before any GPU work: a
/// NaN position would put NaN in every texel of its cube.
#[test]
fn bad_environment_probe_pins_are_errors_naming_the_pin() {
    use glam::Vec3;
    let vec3 = |v: Vec3| Spread::Vec3(vec![v]);
    let e = eval_err(
        "EnvironmentProbe",
        &[("Position", vec3(Vec3::new(0.0, f32::NAN, 0.0)))],
        "Position",
    );
    assert!(e.to_string().contains("NaN or infinite"), "{e}");
    let e = eval_err(
        "EnvironmentProbe",
        &[
            ("Volume", crate::testing::option("Box")),
            ("Volume Size", vec3(Vec3::new(1.0, -2.0, 1.0))),
        ],
        "Volume Size",
    );
    assert!(e.to_string().contains("cannot be negative"), "{e}");
    let e = eval_err(
        "EnvironmentProbe",
        &[("Volume Radius", floats(&[-1.0]))],
        "Volume Radius",
    );
    assert!(e.to_string().contains("cannot be negative"), "{e}");
    let e = eval_err(
        "EnvironmentProbe",
        &[
            ("Update", crate::testing::option("Every N Frames")),
            ("Every N", Spread::Int(vec![0])),
        ],
        "Every N",
    );
    assert!(e.to_string().contains("at least 1"), "{e}");
    let e = eval_err(
        "EnvironmentProbe",
        &[("Cube Size", Spread::Int(vec![0]))],
        "Cube Size",
    );
    assert!(e.to_string().contains("at least 1"), "{e}");
    let e = eval_err(
        "EnvironmentProbe",
        &[("Max Lights", Spread::Int(vec![-1]))],
        "Max Lights",
    );
    assert!(e.to_string().contains("0 or more"), "{e}");
}
