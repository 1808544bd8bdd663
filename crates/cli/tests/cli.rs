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
fn check_looks_inside_subpatch_files_beside_the_patch() {
    let dir = tempfile::tempdir().expect("tempdir");
    std::fs::create_dir(dir.path().join("modules")).expect("mkdir");
    let module = r#"(version: 2, nodes: [
        (id: 1, type: "Inlet", values: {"Name": String(["In"])}),
        (id: 2, type: "Multiply (Value)", values: {"Input 2": String(["two"])}),
        (id: 3, type: "Outlet", values: {"Name": String(["Out"])}),
    ], links: [
        (from: (1, "Output"), to: (2, "Input 1")),
        (from: (2, "Output"), to: (3, "Input")),
    ])"#;
    std::fs::write(dir.path().join("modules/Scale.ron"), module).expect("write");
    let patch = r#"(version: 2, nodes: [(id: 5, type: "Scale"), (id: 6, type: "Probe")],
        links: [(from: (5, "Out"), to: (6, "Input"))])"#;
    let path = dir.path().join("uses-scale.ron");
    std::fs::write(&path, patch).expect("write");
    let out = spreadlight(&["check", path.to_str().expect("utf-8")]);
    assert_eq!(out.status.code(), Some(1));
    let stdout = text(&out.stdout);
    assert!(
        stdout.contains("node #5 > #2 `Multiply (Value)`, pin `Input 2`: value is String"),
        "{stdout}"
    );
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

/// The G-buffer of a sphere, lit by a misspelled `CookTorance`, into an
/// Output: the placeholder drops the lighting the Output was wired for.
const MISSPELLED: &str = r#"(version: 1, nodes: [
    (id: 1, type: "Sphere"),
    (id: 2, type: "DeferredBase"),
    (id: 3, type: "MRE"),
    (id: 4, type: "CookTorance"),
    (id: 5, type: "Output"),
], links: [
    (from: (1, "Mesh"), to: (2, "Mesh")),
    (from: (2, "Layer"), to: (3, "Layer")),
    (from: (3, "G-Buffer"), to: (4, "G-Buffer")),
    (from: (4, "Diffuse"), to: (5, "Texture")),
])"#;

/// A misspelled type kept as a placeholder is fine in the editor, but
/// headless it would render the frame without its work: `check` and
/// `render` fail, suggesting the known name, unless `--allow-unknown`.
#[test]
fn a_misspelled_type_that_feeds_an_output_fails_check_and_render_unless_allowed() {
    let dir = tempfile::tempdir().expect("tempdir");
    let patch = dir.path().join("misspelled.ron");
    std::fs::write(&patch, MISSPELLED).expect("write");
    let patch = patch.to_str().expect("utf-8");
    let image = dir.path().join("out.png");
    let image = image.to_str().expect("utf-8");
    let expected = "error: PATCH: node #4 `CookTorance`: unknown node type (did you mean `CookTorrance`?); \
        kept as a placeholder with its values and links (saved back unchanged), outputs nothing, \
        so `Output` #5, which it feeds, runs without its work (--allow-unknown runs the patch without it)"
        .replace("PATCH", patch);

    let out = spreadlight(&["check", patch]);
    assert_eq!(out.status.code(), Some(1), "{}", text(&out.stderr));
    assert!(
        text(&out.stdout).contains(&expected),
        "{}",
        text(&out.stdout)
    );
    let out = spreadlight(&["check", "--allow-unknown", patch]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stdout));
    assert!(
        text(&out.stdout).starts_with("warning: "),
        "{}",
        text(&out.stdout)
    );

    // render: bad input, nothing rendered.
    let out = spreadlight(&["render", patch, "-o", image, "--size", "32x18"]);
    assert_eq!(out.status.code(), Some(2), "{}", text(&out.stderr));
    assert!(
        text(&out.stderr).contains(&expected),
        "{}",
        text(&out.stderr)
    );
    assert!(!Path::new(image).exists());
    // Allowed, it runs; the Output's error names the placeholder as the cause.
    let out = spreadlight(&[
        "render",
        "--allow-unknown",
        patch,
        "-o",
        image,
        "--size",
        "32x18",
    ]);
    let stderr = text(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains(
            "node #5: input `Texture`: no texture connected (it is linked from node #4 `CookTorance`, \
             an unknown node type that outputs nothing)"
        ),
        "{stderr}"
    );

    // A placeholder that feeds no sink drops nothing anyone asked for: a warning.
    assert_eq!(
        spreadlight(&["check", "patches/bad/21-unknown-node-type.ron"])
            .status
            .code(),
        Some(0)
    );
}

/// A shader node whose file is missing names the file that would make it
/// and every folder searched, where the next node used to say only that no
/// texture is connected.
#[test]
fn a_shader_node_without_its_file_names_the_file_and_the_folders_searched() {
    let dir = tempfile::tempdir().expect("tempdir");
    let library = tempfile::tempdir().expect("tempdir");
    let patch = dir.path().join("shaded.ron");
    std::fs::write(
        &patch,
        r#"(version: 1, nodes: [(id: 1, type: "WarpSpeed (Shader)"), (id: 2, type: "Output")],
            links: [(from: (1, "Texture"), to: (2, "Texture"))])"#,
    )
    .expect("write");
    let out = Command::new(env!("CARGO_BIN_EXE_spreadlight"))
        .args(["check", patch.to_str().expect("utf-8")])
        .env("SPREADLIGHT_SHADERS", library.path())
        .output()
        .expect("runs");
    let stdout = text(&out.stdout);
    assert_eq!(out.status.code(), Some(1), "{stdout}");
    let folder = |p: &Path| format!("`{}`", p.display());
    for part in [
        "node #1 `WarpSpeed (Shader)`: unknown node type".to_owned(),
        "no shader file makes it: `warp_speed.wgsl`".to_owned(),
        folder(library.path()),
        folder(&dir.path().join("shaders")),
        "examples built in (shaders/nodes/)".to_owned(),
    ] {
        assert!(stdout.contains(&part), "`{part}` missing from: {stdout}");
    }
}

/// Every size the CLI accepts renders or fails, fast and with a message
/// naming the limit it exceeds, before allocating: 16384x16384 (the largest
/// `--size` takes) on a patch of one shader node panicked in wgpu's default
/// error handler. Its Rgba16Float image needs a readback buffer of exactly
/// 2 GiB: one byte past lavapipe's largest, so in CI it fails fast; an
/// adapter with larger buffers renders it. One past the CLI's own limit is
/// a usage error naming the range.
#[test]
fn the_largest_accepted_size_renders_or_fails_fast_naming_the_limit() {
    let dir = tempfile::tempdir().expect("tempdir");
    let patch = dir.path().join("noise.ron");
    std::fs::write(
        &patch,
        r#"(version: 1, nodes: [(id: 1, type: "Noise (Shader)"), (id: 2, type: "Output")],
            links: [(from: (1, "Texture"), to: (2, "Texture"))])"#,
    )
    .expect("write");
    let patch = patch.to_str().expect("utf-8");
    let image = dir.path().join("big.png");
    let image = image.to_str().expect("utf-8");
    let out = spreadlight(&["render", patch, "-o", image, "--size", "16384x16384"]);
    let stderr = text(&out.stderr);
    assert!(!stderr.contains("panicked"), "{stderr}");
    let gpu = spreadlight_render::GpuContext::headless().expect("a GPU adapter");
    let limits = gpu.device.limits();
    let readback = 16384u64 * 8 * 16384;
    if limits.max_texture_dimension_2d < 16384 {
        assert_eq!(out.status.code(), Some(1), "{stderr}");
        assert!(
            stderr.contains(&format!(
                "--size 16384x16384 is past the adapter's limit max_texture_dimension_2d ({})",
                limits.max_texture_dimension_2d
            )),
            "{stderr}"
        );
    } else if readback > limits.max_buffer_size {
        assert_eq!(out.status.code(), Some(1), "{stderr}");
        assert!(
            stderr.contains(&format!(
                "node #2: the readback of the Output's texture (16384x16384 Rgba16Float: a \
                 {readback}-byte buffer) is past the adapter's limit max_buffer_size ({})",
                limits.max_buffer_size
            )),
            "{stderr}"
        );
        assert!(!Path::new(image).exists());
    } else {
        assert_eq!(out.status.code(), Some(0), "{stderr}");
        let written = image::image_dimensions(image).expect("the image");
        assert_eq!(written, (16384, 16384));
    }

    let out = spreadlight(&["render", patch, "-o", image, "--size", "16385x16384"]);
    assert_eq!(out.status.code(), Some(2), "{}", text(&out.stderr));
    assert!(
        text(&out.stderr).contains("width and height must be whole numbers from 1 to 16384"),
        "{}",
        text(&out.stderr)
    );
}

/// The issue's two-node patch: an image file straight into an Output.
/// `render` and `stats` panicked on a wgpu validation error (the file's
/// texture could not be copied for the readback); now it renders the file.
#[test]
fn an_image_file_straight_into_an_output_renders() {
    let dir = tempfile::tempdir().expect("tempdir");
    let tiles = root().join("patches/assets/tiles.png");
    let patch = dir.path().join("file.ron");
    std::fs::write(
        &patch,
        format!(
            r#"(version: 1, nodes: [
                (id: 1, type: "FileTexture", values: {{"Filename": String(["{}"])}}),
                (id: 2, type: "Output")],
                links: [(from: (1, "Texture"), to: (2, "Texture"))])"#,
            tiles.display()
        ),
    )
    .expect("write");
    let patch = patch.to_str().expect("utf-8");
    let out = dir.path().join("out.png");
    let (width, height) = image::image_dimensions(&tiles).expect("tiles.png");
    let size = format!("{width}x{height}");
    let o = spreadlight(&[
        "render",
        patch,
        "-o",
        out.to_str().expect("utf-8"),
        "--size",
        &size,
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    let want = image::open(&tiles).expect("tiles").to_rgba8();
    let got = image::open(&out).expect("written").to_rgba8();
    assert_eq!(got.dimensions(), want.dimensions());
    // sRGB decoded on upload, encoded on write: the file's own pixels, within rounding.
    let worst = want
        .pixels()
        .zip(got.pixels())
        .flat_map(|(a, b)| (0..3).map(move |c| (i32::from(a[c]) - i32::from(b[c])).abs()))
        .max();
    assert!(worst.is_some_and(|w| w <= 1), "{worst:?}");
    let o = spreadlight(&["stats", patch, "--size", &size]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
}

/// A bypassed node passes its first input on in `render` as in the editor: a
/// bypassed Tonemap between an image and the Output leaves the image's own
/// pixels, where the same Tonemap running changes them.
#[test]
fn render_passes_a_bypassed_nodes_input_through() {
    let dir = tempfile::tempdir().expect("tempdir");
    let tiles = root().join("patches/assets/tiles.png");
    let want = image::open(&tiles).expect("tiles").to_rgba8();
    let (width, height) = want.dimensions();
    let worst = |bypass: bool| {
        let patch = dir.path().join(format!("bypass-{bypass}.ron"));
        std::fs::write(
            &patch,
            format!(
                r#"(version: 3, nodes: [
                    (id: 1, type: "FileTexture", values: {{"Filename": String(["{}"])}}),
                    (id: 2, type: "Tonemap", values: {{"Exposure": Float([3.0])}}, bypass: {bypass}),
                    (id: 3, type: "Output")],
                    links: [(from: (1, "Texture"), to: (2, "Texture")), (from: (2, "Texture"), to: (3, "Texture"))])"#,
                tiles.display()
            ),
        )
        .expect("write");
        let out = dir.path().join(format!("out-{bypass}.png"));
        let o = spreadlight(&[
            "render",
            patch.to_str().expect("utf-8"),
            "-o",
            out.to_str().expect("utf-8"),
            "--size",
            &format!("{width}x{height}"),
        ]);
        assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
        let got = image::open(&out).expect("written").to_rgba8();
        want.pixels()
            .zip(got.pixels())
            .flat_map(|(a, b)| (0..3).map(move |c| (i32::from(a[c]) - i32::from(b[c])).abs()))
            .max()
            .unwrap_or(0)
    };
    assert!(worst(true) <= 1, "bypassed: the file's pixels");
    assert!(worst(false) > 8, "running, the Tonemap changes them");
}

/// Accuracy images go into a folder named for the effect, inside
/// `accuracy-images/` (ignored by git) when `--images` names no folder:
/// never loose in the current folder, as 85 of them once were in `1/`.
#[test]
fn accuracy_images_go_under_a_folder_named_for_the_effect() {
    let dir = tempfile::tempdir().expect("tempdir");
    let out = Command::new(env!("CARGO_BIN_EXE_spreadlight"))
        .args([
            "accuracy",
            "ao",
            "--time-size",
            "16x16",
            "--error-size",
            "16x9",
            "--warmup",
            "0",
            "--frames",
            "1",
            "--samples",
            "4",
            "--resolutions",
            "full",
            "--rays",
            "4",
            "--settle",
            "1",
            "--images",
        ])
        .current_dir(dir.path())
        .output()
        .expect("runs");
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    let listing = |path: &Path| -> Vec<String> {
        let mut names: Vec<String> = std::fs::read_dir(path)
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
            .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        names
    };
    assert_eq!(listing(dir.path()), ["accuracy-images"]);
    assert_eq!(listing(&dir.path().join("accuracy-images")), ["ao"]);
    // The reference, and each estimator with temporal off and on (SSGI's
    // gathered share among them, as `accuracy ao` measures it).
    assert_eq!(
        listing(&dir.path().join("accuracy-images/ao")),
        [
            "HBAO-4-Full.png",
            "HBAO-4-temporal-Full.png",
            "SAO-4-Full.png",
            "SAO-4-temporal-Full.png",
            "SSGI-4-Full.png",
            "SSGI-4-temporal-Full.png",
            "Stochastic-4-Full.png",
            "Stochastic-4-temporal-Full.png",
            "reference.png",
        ]
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
fn nodes_help_documents_one_node_type() {
    let out = spreadlight(&["nodes", "--help", "getslice (spreads)"]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    let stdout = text(&out.stdout);
    assert!(
        stdout.starts_with("GetSlice (Spreads)  [Spreads]"),
        "{stdout}"
    );
    assert!(stdout.contains("Bin Size: Int = 1"), "{stdout}");
    // Its help patch, from the table F1 in the editor uses, and where it lies.
    assert!(
        stdout.contains("Help patch: patches/help/spreads.ron"),
        "{stdout}"
    );
    let file = root().join("patches/help/spreads.ron");
    let listed = stdout.lines().find_map(|l| {
        let l = l.trim();
        (l.starts_with('/') && l.ends_with("spreads.ron")).then(|| std::path::PathBuf::from(l))
    });
    assert!(
        listed
            .is_some_and(|p| p.is_absolute() && p.canonicalize().ok() == file.canonicalize().ok()),
        "the help patch's path: {stdout}"
    );
    let out = spreadlight(&["nodes", "--help", "DOF"]);
    assert!(
        text(&out.stdout).contains("Help patch: patches/help/post.ron"),
        "{}",
        text(&out.stdout)
    );
    let out = spreadlight(&["nodes", "--help", "GetSlice"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(text(&out.stderr).contains("GetSlice (Color)"));
    let out = spreadlight(&["nodes", "--help", "NoSuchNode"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(text(&out.stderr).contains("no node type named `NoSuchNode`"));
}

#[test]
fn nodes_markdown_is_docs_nodes_md() {
    let out = spreadlight(&["nodes", "--markdown"]);
    assert_eq!(out.status.code(), Some(0));
    let file = std::fs::read_to_string(root().join("docs/nodes.md")).expect("docs/nodes.md");
    assert!(text(&out.stdout) == file, "docs/nodes.md is out of date");
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

/// `render PATCH -o IMAGE --size 32x18 --json` with `env`, which must
/// succeed: its done line's `cold_start`, the image's bytes and stderr
/// (the cold-start tests run it a few times over one cache).
fn cold_start_render(
    patch: &str,
    image: &str,
    env: &[(&str, &str)],
) -> (serde_json::Value, Vec<u8>, String) {
    let args = ["render", patch, "-o", image, "--size", "32x18", "--json"];
    let out = spreadlight_env(&args, env);
    let stdout = text(&out.stdout);
    assert_eq!(out.status.code(), Some(0), "{stdout}{}", text(&out.stderr));
    let done: serde_json::Value = stdout
        .lines()
        .filter_map(|l| serde_json::from_str(l).ok())
        .next_back()
        .expect("a done line");
    let bytes = std::fs::read(image).expect("image written");
    (done["cold_start"].clone(), bytes, text(&out.stderr))
}

fn spreadlight_env(args: &[&str], env: &[(&str, &str)]) -> Output {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_spreadlight"));
    cmd.args(args).current_dir(root());
    for (k, v) in env {
        cmd.env(k, v);
    }
    cmd.output().expect("runs")
}

/// A one-triangle glTF with its buffer inline, facing +Z.
const TRIANGLE_GLTF: &str = r#"{
  "asset": {"version": "2.0"},
  "scene": 0,
  "scenes": [{"nodes": [0]}],
  "nodes": [{"mesh": 0}],
  "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
  "buffers": [{"byteLength": 36, "uri": "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"}],
  "bufferViews": [{"buffer": 0, "byteLength": 36}],
  "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]}]
}"#;

#[test]
fn render_writes_png_and_exr() {
    let dir = tempfile::tempdir().expect("tempdir");
    for name in ["out.png", "out.exr"] {
        let out = dir.path().join(name);
        let o = spreadlight(&[
            "render",
            "patches/gbuffer-spheres.ron",
            "-o",
            out.to_str().expect("utf-8"),
            "--size",
            "64x36",
        ]);
        assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
        let image = image::open(&out).expect("a readable image");
        assert_eq!((image.width(), image.height()), (64, 36));
    }
}

/// The headline command, `spreadlight render PATCH -o out.png`, on every
/// shipped example with an `Output` (found by listing `patches/`, so a new
/// example is covered without touching this test), at 64x36: it exits 0 and
/// writes one image of that size per Output, named by the Output's Name.
#[test]
fn render_succeeds_on_every_example_with_an_output() {
    use spreadlight_graph::Spread;
    let dir = tempfile::tempdir().expect("tempdir");
    let mut examples: Vec<PathBuf> = std::fs::read_dir(root().join("patches"))
        .expect("ls patches")
        .map(|e| e.expect("entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "ron"))
        .collect();
    examples.sort();
    let mut rendered = Vec::new();
    let mut failures = Vec::new();
    for path in &examples {
        let patch = spreadlight_graph::format::load(path).unwrap_or_else(|e| panic!("{e}"));
        let names: Vec<String> = patch
            .nodes
            .iter()
            .filter(|n| n.type_name == "Output")
            .map(|n| match n.values.get("Name") {
                Some(Spread::String(v)) => v.first().cloned().unwrap_or_default(),
                _ => "output".to_owned(),
            })
            .collect();
        if names.is_empty() {
            continue;
        }
        let stem = path.file_stem().expect("stem").to_string_lossy();
        let out = dir.path().join(format!("{stem}-{{name}}.png"));
        let o = spreadlight(&[
            "render",
            path.to_str().expect("utf-8"),
            "-o",
            out.to_str().expect("utf-8"),
            "--size",
            "64x36",
        ]);
        if o.status.code() != Some(0) {
            failures.push(format!(
                "{}: exit {:?}\n{}",
                path.display(),
                o.status.code(),
                text(&o.stderr)
            ));
            continue;
        }
        for name in &names {
            let file = dir.path().join(format!("{stem}-{name}.png"));
            match image::open(&file) {
                Ok(i) if (i.width(), i.height()) == (64, 36) => {}
                Ok(i) => failures.push(format!(
                    "{}: {name} is {}x{}",
                    file.display(),
                    i.width(),
                    i.height()
                )),
                Err(e) => failures.push(format!("{}: {e}", file.display())),
            }
        }
        rendered.push(stem.into_owned());
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    // The lister found the examples: shader-nodes.ron (seven Outputs, one of them 1x1) among them.
    assert!(
        rendered.iter().any(|s| s == "shader-nodes"),
        "rendered only {rendered:?}"
    );
}

#[test]
fn render_without_an_adapter_says_how_to_get_one() {
    let dir = tempfile::tempdir().expect("tempdir");
    let out = dir.path().join("x.png");
    let o = spreadlight_env(
        &[
            "render",
            "patches/gbuffer-spheres.ron",
            "-o",
            out.to_str().expect("utf-8"),
        ],
        &[("WGPU_ADAPTER_NAME", "no-such-gpu-anywhere")],
    );
    assert_eq!(o.status.code(), Some(1));
    let err = text(&o.stderr);
    assert!(
        err.contains("no GPU adapter found") && err.contains("apt-get install mesa-vulkan-drivers"),
        "{err}"
    );
}

#[test]
fn view_renders_any_gltf_and_names_a_broken_one() {
    let dir = tempfile::tempdir().expect("tempdir");
    let model = dir.path().join("triangle.gltf");
    std::fs::write(&model, TRIANGLE_GLTF).expect("write");
    let out = dir.path().join("view.png");
    let o = spreadlight(&[
        "view",
        model.to_str().expect("utf-8"),
        "-o",
        out.to_str().expect("utf-8"),
        "--size",
        "48x48",
        "--channel",
        "Albedo",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    let image = image::open(&out).expect("image").to_rgba8();
    assert!(
        image.pixels().any(|p| p.0[0] > 200),
        "the white triangle is in view"
    );

    let broken = dir.path().join("broken.gltf");
    std::fs::write(&broken, &TRIANGLE_GLTF[..TRIANGLE_GLTF.len() / 2]).expect("write");
    let o = spreadlight(&[
        "view",
        broken.to_str().expect("utf-8"),
        "-o",
        out.to_str().expect("utf-8"),
    ]);
    assert_eq!(o.status.code(), Some(1));
    assert!(
        text(&o.stderr).contains("broken.gltf"),
        "{}",
        text(&o.stderr)
    );
}

#[test]
fn stats_json_shows_passes_and_culling() {
    let o = spreadlight(&[
        "stats",
        "patches/gbuffer-spheres.ron",
        "--json",
        "--size",
        "32x18",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    let json: serde_json::Value = serde_json::from_slice(&o.stdout).expect("JSON");
    let passes: Vec<&str> = json["render"]["passes"]
        .as_array()
        .expect("passes")
        .iter()
        .filter_map(|p| p["name"].as_str())
        .collect();
    assert!(
        passes
            .iter()
            .any(|p| p.ends_with("visibility") || p.ends_with("compute raster")),
        "{passes:?}"
    );
    let culled = json["render"]["culled"].as_array().expect("culled");
    assert!(
        culled
            .iter()
            .any(|c| c.as_str().is_some_and(|c| c.ends_with("resolve motion"))),
        "{culled:?}"
    );
    assert!(json["runtime"]["evaluated"].as_u64().expect("count") > 0);
}

/// A small, short bench: 32x18, one frame of warm-up, three timed.
const SMALL: [&str; 6] = ["--size", "32x18", "--warmup", "1", "--frames", "3"];

/// `spreadlight bench ARGS --json`, which must succeed and print one line: its JSON.
fn bench_json(args: &[&str]) -> serde_json::Value {
    let mut all = vec!["bench"];
    all.extend_from_slice(args);
    all.push("--json");
    let o = spreadlight(&all);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    let stdout = text(&o.stdout);
    assert_eq!(stdout.lines().count(), 1, "{stdout}");
    serde_json::from_str(&stdout).expect("JSON")
}

/// An animated patch's nodes that run every frame are listed by their own
/// CPU, the costliest first.
#[test]
fn bench_lists_the_nodes_that_cost_cpu() {
    let json = bench_json(&[&["patches/gbuffer-spheres.ron"][..], &SMALL].concat());
    let nodes = json["node_cpu_ms_median"]
        .as_array()
        .expect("node_cpu_ms_median");
    let types: Vec<&str> = nodes.iter().filter_map(|n| n["type"].as_str()).collect();
    // The LFO turns the camera: what it feeds runs every frame.
    for moved in ["LFO", "Camera", "MRE"] {
        assert!(types.contains(&moved), "{moved} in {types:?}");
    }
    assert!(!types.contains(&"Output"), "{types:?}");
    assert!(nodes.iter().all(|n| n["evaluated"] == 3), "{nodes:?}");
    let medians: Vec<f64> = nodes
        .iter()
        .filter_map(|n| n["median_ms"].as_f64())
        .collect();
    assert!(medians.is_sorted_by(|a, b| a >= b), "{medians:?}");
}

#[test]
fn bench_prints_one_json_line_with_the_adapter() {
    let json = bench_json(
        &[
            &["patches/bench-gbuffer.ron"][..],
            &SMALL,
            &["--set", "2.Input=5"],
        ]
        .concat(),
    );
    assert_eq!(json["size"], "32x18");
    assert!(json["adapter"].as_str().is_some_and(|a| !a.is_empty()));
    assert!(json["passes"].as_object().is_some());

    // Every pass of the frame is kept, in order, and named in the map.
    let order = json["pass_order"].as_array().expect("pass_order");
    assert!(!order.is_empty());
    assert_eq!(
        order.len(),
        json["passes"].as_object().map_or(0, |m| m.len())
    );
    assert!(json["cpu_eval_ms_median"].as_f64().is_some());
    assert!(json["cpu_record_ms_median"].as_f64().is_some());
    // A still patch: every node but the Output is reused, and no node's own
    // CPU is listed (the Output's is the recording).
    assert_eq!(json["node_cpu_ms_median"], serde_json::json!([]));
    // Each pass's recording time is part of the frame's, and so is the submission after them.
    let record = json["cpu_record_ms_median"].as_f64().unwrap_or(0.0);
    let submit = json["cpu_submit_ms_median"]
        .as_f64()
        .expect("cpu_submit_ms_median");
    assert!((0.0..=record).contains(&submit), "{submit} of {record}");
    // The geometry and skinning lines are timed apart from the graph's recording.
    for pass in order {
        let name = pass["name"].as_str().unwrap_or_default();
        match pass["cpu_ms"].as_f64() {
            Some(cpu) => assert!(cpu >= 0.0 && cpu <= record, "{pass}"),
            None => assert!(name.ends_with("(compute)"), "{name} has no cpu_ms"),
        }
    }
    assert!(order.iter().any(|p| p["cpu_ms"].as_f64().is_some()));
    assert!(json["wall_ms_per_frame"].is_null(), "only with --wall");
    // Where the cold start went, by step: the steps happen one after another in the process, and
    // the first frame of a fresh process compiles its pipelines.
    let cold = &json["cold_start"];
    let ms = |key: &str| {
        cold[key]
            .as_f64()
            .unwrap_or_else(|| panic!("cold_start.{key}: {cold}"))
    };
    assert!(
        cold["pipelines_compiled"].as_u64().is_some_and(|n| n > 0),
        "{cold}"
    );
    // Of opening the GPU (on a thread beside the registry), what the start waited for.
    let steps =
        ms("registry_ms") + ms("gpu_waited_ms") + ms("load_patch_ms") + ms("first_frame_ms");
    assert!(ms("total_ms") >= steps, "{cold}");
    // The finer steps: parts of the registry and of opening the GPU, and what the composing found.
    assert!(ms("registry_nodes_ms") <= ms("registry_ms"), "{cold}");
    assert!(
        ms("shader_folders_ms") >= 0.0 && ms("network_ms") >= 0.0,
        "{cold}"
    );
    let driver = ms("gpu_adapter_ms") + ms("gpu_device_ms") + ms("gpu_pipeline_cache_ms");
    assert!(driver > 0.0 && driver <= ms("open_gpu_ms") + 0.01, "{cold}");
    assert!(ms("renderer_setup_ms") >= 0.0 && ms("before_first_frame_ms") >= 0.0);
    assert!(ms("shader_libraries_ms") >= 0.0, "{cold}");
    let found = cold["permutations_composed"]
        .as_u64()
        .expect("permutations_composed")
        + cold["permutations_ready"]
            .as_u64()
            .expect("permutations_ready");
    assert!(found > 0, "{cold}");
    assert!(
        cold.get("precompose").is_some(),
        "null or what was composed ahead: {cold}"
    );
    let compiling = ms("compose_ms") + ms("shader_modules_ms") + ms("pipelines_ms");
    assert!(
        compiling > 0.0 && ms("first_frame_other_ms") >= 0.0,
        "{cold}"
    );
    // Each timed pass of the frame says how long the GPU idled before it;
    // the first has nothing before it. (The geometry line is timed apart.)
    let idle: Vec<f64> = order
        .iter()
        .filter(|p| !p["gpu_ms"].is_null() && p["name"] != "geometry and particles (compute)")
        .map(|p| p["idle_ms"].as_f64().expect("idle_ms beside gpu_ms"))
        .collect();
    assert!(!idle.is_empty());
    assert_eq!(idle[0], 0.0);
    assert!(idle.iter().all(|&ms| ms >= 0.0), "{idle:?}");

    // --wall times frames in flight, batched recording and frame timing
    // leave the figures' shape alone.
    let json = bench_json(&[
        "patches/bench-gbuffer.ron",
        "--size",
        "32x18",
        "--warmup",
        "1",
        "--frames",
        "2",
        "--wall",
        "--recording",
        "batched",
        "--timing",
        "frame",
    ]);
    assert!(
        json["wall_ms_per_frame"]
            .as_f64()
            .is_some_and(|ms| ms > 0.0)
    );
    // The CPU per frame with frames in flight, split as with timestamps.
    let cpu = json["wall_cpu_ms_median"].as_f64().expect("wall CPU");
    let eval = json["wall_cpu_eval_ms_median"].as_f64().expect("wall eval");
    let record = json["wall_cpu_record_ms_median"]
        .as_f64()
        .expect("wall record");
    assert!(
        cpu > 0.0 && record > 0.0 && eval >= 0.0,
        "{cpu} {eval} {record}"
    );
    // The tail after the last pass with no timestamps, a part of the recording.
    let submit = json["wall_cpu_submit_ms_median"]
        .as_f64()
        .expect("wall submit");
    assert!((0.0..=record).contains(&submit), "{submit} of {record}");
    assert_eq!(json["recording"], "batched");

    let o = spreadlight(&["bench", "patches/bench-gbuffer.ron", "--set", "2.Nope=5"]);
    assert_eq!(o.status.code(), Some(1));
    assert!(
        text(&o.stderr).contains("has no input `Nope`"),
        "{}",
        text(&o.stderr)
    );
}

/// `bench --orbit` turns a camera's position a little more each frame (sun
/// cascades follow it and scroll: docs/shadows.md) and says so in the JSON
/// line; a pin that is not there, or not a number of radians, is an error
/// naming it.
#[test]
fn bench_orbit_turns_a_camera_and_names_a_wrong_pin() {
    let orbit = "43.Position=0.05";
    let json = bench_json(&[
        "patches/shadows.ron",
        "--size",
        "32x18",
        "--warmup",
        "1",
        "--frames",
        "2",
        "--orbit",
        orbit,
    ]);
    assert_eq!(json["orbit"], orbit);
    for (bad, says) in [
        ("43.Nope=0.1", "has no input `Nope`"),
        ("43.Position=fast", "is not a number of radians"),
        ("999.Position=0.1", "has no node #999"),
    ] {
        let o = spreadlight(&["bench", "patches/shadows.ron", "--orbit", bad]);
        assert_eq!(o.status.code(), Some(1), "{bad}");
        assert!(text(&o.stderr).contains(says), "{bad}: {}", text(&o.stderr));
    }
}

#[test]
fn shader_nodes_are_listed_and_a_broken_one_beside_a_patch_is_named_by_check() {
    let out = spreadlight(&["nodes"]);
    let listed = text(&out.stdout);
    assert!(listed.contains("Shader/Filter"), "{listed}");
    assert!(listed.contains("Blur (Shader)"), "{listed}");

    let dir = tempfile::tempdir().expect("tempdir");
    std::fs::create_dir_all(dir.path().join("shaders")).expect("mkdir");
    std::fs::write(
        dir.path().join("shaders/glow.wgsl"),
        "// @target out temporary rgba16float\n// @pass main -> out\nfn main( {\n",
    )
    .expect("write");
    // The node has values and links for the pins the file will have once fixed.
    let patch = dir.path().join("uses-glow.ron");
    std::fs::write(
        &patch,
        r#"(version: 1, nodes: [
            (id: 1, type: "Glow (Shader)", values: {"Radius": Float([2.0]), "Tint": Float([0.5])}),
            (id: 2, type: "Noise (Shader)"),
            (id: 3, type: "Output", values: {"Write": Bool([false])}),
        ], links: [
            (from: (2, "Texture"), to: (1, "Texture")),
            (from: (1, "Texture"), to: (3, "Texture")),
        ])"#,
    )
    .expect("write");
    let out = spreadlight(&["check", patch.to_str().expect("utf-8")]);
    let stdout = text(&out.stdout);
    assert_eq!(out.status.code(), Some(1), "{stdout}");
    assert!(stdout.contains("glow.wgsl:3:"), "{stdout}");
    assert!(stdout.contains("WGSL syntax"), "{stdout}");
    // The cause, once: no error for each value and link the pin-less node keeps.
    assert_eq!(
        stdout.lines().filter(|l| l.starts_with("error")).count(),
        1,
        "{stdout}"
    );
    assert!(
        text(&out.stderr).contains("1 error(s)"),
        "{}",
        text(&out.stderr)
    );
}

/// The pipeline cache kept between runs (crates/render/src/pipeline_cache.rs):
/// the first run starts empty and writes the file (a run leaves without
/// tearing the GPU down, so this is the explicit save in `Evaluator::leave`),
/// the next starts from it and draws the same bytes, and a damaged file is
/// a cold start, not an error, and is written anew. Once the file holds data, a run turns the
/// driver's own disk cache off unless the user set it (`prefer_kept_pipelines`).
/// (On by default on GPUs only; `SPREADLIGHT_PIPELINE_CACHE=on` here.)
#[test]
fn the_pipeline_cache_is_kept_between_runs_and_a_damaged_file_is_a_cold_start() {
    let dir = tempfile::tempdir().expect("temp dir");
    let cache = dir.path().join("cache");
    let cache_dir = cache.to_str().expect("utf-8 path");
    let env = [
        ("SPREADLIGHT_PIPELINE_CACHE", "on"),
        ("SPREADLIGHT_CACHE_DIR", cache_dir),
    ];
    let run_with = |name: &str, driver: &[(&str, &str)]| {
        let image = dir.path().join(name);
        let image = image.to_str().expect("utf-8 path");
        let args = [
            "render",
            "patches/gbuffer-spheres.ron",
            "-o",
            image,
            "--size",
            "32x18",
            "--json",
        ];
        let env: Vec<(&str, &str)> = env.iter().chain(driver).copied().collect();
        let out = spreadlight_env(&args, &env);
        let stdout = text(&out.stdout);
        assert_eq!(out.status.code(), Some(0), "{stdout}{}", text(&out.stderr));
        let done: serde_json::Value = stdout
            .lines()
            .filter_map(|l| serde_json::from_str(l).ok())
            .next_back()
            .expect("a done line");
        let cache = done["cold_start"]["pipeline_cache"].clone();
        let bytes = std::fs::read(image).expect("image written");
        (cache, bytes)
    };
    let run = |name: &str| run_with(name, &[]);
    // What the driver's variable is when the user set none.
    let user_chose = std::env::var_os("__GL_SHADER_DISK_CACHE").is_some();
    let (first, first_image) = run("first.png");
    if first.is_null() {
        panic!("the adapter offers no PIPELINE_CACHE (every Vulkan adapter should)");
    }
    assert_eq!(first["loaded_bytes"], 0, "{first}");
    assert_eq!(
        first["driver_disk_cache_off"], false,
        "no file yet: {first}"
    );
    let file = PathBuf::from(first["path"].as_str().expect("path"));
    assert!(file.starts_with(&cache), "{file:?} outside {cache:?}");
    let saved = std::fs::metadata(&file)
        .expect("saved when the run ended")
        .len();
    assert!(saved > 0);

    let (second, second_image) = run("second.png");
    assert_eq!(second["loaded_bytes"].as_u64(), Some(saved), "{second}");
    assert_eq!(first_image, second_image, "the cache changes no pixel");
    assert_eq!(second["driver_disk_cache_off"], !user_chose, "{second}");
    let (chosen, chosen_image) = run_with("chosen.png", &[("__GL_SHADER_DISK_CACHE", "1")]);
    assert_eq!(
        chosen["driver_disk_cache_off"], false,
        "the user's setting stays: {chosen}"
    );
    assert_eq!(first_image, chosen_image);

    // Damaged, and larger than the driver's data (as a stale file after a
    // driver update may be): the driver refuses it, and the run still saves
    // what it compiled, also when it drops its GPU (the save on drop).
    let damaged = vec![7u8; 4 << 20];
    std::fs::write(&file, &damaged).expect("damage it");
    let (third, third_image) = run_with("third.png", &[("SPREADLIGHT_TEARDOWN", "full")]);
    assert!(!third.is_null(), "{third}");
    assert_eq!(third["loaded_bytes"].as_u64(), Some(damaged.len() as u64));
    let accepted = third["accepted_bytes"].as_u64().expect("accepted bytes");
    assert!(
        accepted < damaged.len() as u64,
        "the driver refused it: {third}"
    );
    assert_eq!(first_image, third_image);
    let rewritten = std::fs::read(&file).expect("still there");
    assert!(
        !rewritten.is_empty() && rewritten != damaged,
        "written anew: {} bytes",
        rewritten.len()
    );
}

/// Composing and creating pipelines ahead (precompose.rs and
/// pipelines_ahead.rs in render): the first run of a patch composes in its
/// first frame and leaves a list of its permutations and compute
/// pipelines; the next composes that list on threads of its own while it
/// starts and creates the pipelines once the device is open, its renderer
/// composes nothing and makes only what the list does not name, and it
/// renders the same bytes; a stale entry is skipped, and a damaged list is
/// a warning naming it and a normal start, and is written anew.
#[test]
fn permutations_are_composed_ahead_from_the_last_runs_list_and_a_damaged_list_recovers() {
    let dir = tempfile::tempdir().expect("temp dir");
    let cache = dir.path().join("cache");
    let cache_dir = cache.to_str().expect("utf-8 path");
    let env = [
        ("SPREADLIGHT_CACHE_DIR", cache_dir),
        ("SPREADLIGHT_PIPELINE_CACHE", "off"),
        // Every listed pipeline made before the first frame: the counts
        // do not depend on how the threads were scheduled.
        ("SPREADLIGHT_PIPELINES_AHEAD", "wait"),
    ];
    let run = |name: &str| {
        let image = dir.path().join(name);
        let image = image.to_str().expect("utf-8 path");
        cold_start_render("patches/gbuffer-spheres.ron", image, &env)
    };
    let lists = || -> Vec<PathBuf> {
        std::fs::read_dir(cache.join("permutations"))
            .map(|d| d.flatten().map(|e| e.path()).collect())
            .unwrap_or_default()
    };
    // A list's permutation lines (two fields) and pipeline lines (three).
    let count = |text: &str, fields: usize| {
        text.lines()
            .skip(1)
            .filter(|l| l.split('\t').count() == fields)
            .count() as u64
    };
    let (first, first_image, _) = run("first.png");
    assert!(first["precompose"].is_null(), "no list yet: {first}");
    assert!(first["pipelines_ahead"].is_null(), "no list yet: {first}");
    // Composed by the frame, or (`ready`) by the threads making the
    // pipelines its passes announced, on the frame's behalf.
    let composed = first["permutations_composed"].as_u64().expect("a count");
    let ready = first["permutations_ready"].as_u64().expect("a count");
    let compiled = first["pipelines_compiled"].as_u64().expect("a count");
    // A first run: every pipeline the frame needs is announced where its
    // pass is declared (the compute raster, the resolve the plan runs, the
    // view) and made on threads; the frame makes only those it asked for
    // before a thread began them (`claimed`), and no announced one goes
    // unused (the resolve's other variants are not made).
    let gathered = &first["pipelines_gathered"];
    let gathered_count = |name: &str| gathered[name].as_u64().expect("a count");
    assert_eq!(gathered_count("listed"), compiled, "{first}");
    assert_eq!(gathered_count("failed"), 0, "{first}");
    assert_eq!(
        gathered_count("created") + gathered_count("claimed"),
        compiled,
        "{first}"
    );
    assert_eq!(
        gathered_count("taken") + gathered_count("waited") + gathered_count("claimed"),
        compiled,
        "every announced pipeline used: {first}"
    );
    assert_eq!(
        first["pipelines_at_frame"].as_u64(),
        Some(gathered_count("claimed")),
        "the frame made none no pass announced: {first}"
    );
    let [list] = lists().try_into().expect("one list, the patch's");
    let text = std::fs::read_to_string(&list).expect("a list");
    // The list is what the first frame used: each composed or found ready.
    let permutations = count(&text, 2);
    assert!(
        permutations > 0 && composed <= permutations && composed + ready >= permutations,
        "the list is what the first frame composed: {text}{first}"
    );
    let pipelines = count(&text, 3);
    assert!(
        pipelines > 0 && pipelines <= compiled,
        "the frame's compute pipelines: {text}{first}"
    );

    let (second, second_image, _) = run("second.png");
    let ahead = &second["precompose"];
    assert_eq!(ahead["listed"].as_u64(), Some(permutations), "{second}");
    assert_eq!(ahead["composed"].as_u64(), Some(permutations), "{second}");
    assert_eq!(second["permutations_composed"], 0, "{second}");
    assert!(
        second["permutations_ready"].as_u64() >= Some(permutations),
        "{second}"
    );
    assert_eq!(
        second["shader_libraries_ms"], 0.0,
        "no composer made: {second}"
    );
    let made = &second["pipelines_ahead"];
    for (count, expected) in [
        ("listed", pipelines),
        ("created", pipelines),
        ("taken", pipelines),
        ("failed", 0),
        ("waited", 0),
        ("claimed", 0),
    ] {
        assert_eq!(made[count].as_u64(), Some(expected), "{count}: {second}");
    }
    assert_eq!(
        second["pipelines_at_frame"].as_u64(),
        Some(compiled - pipelines),
        "the frame made only what the list did not name: {second}"
    );
    assert_eq!(second["pipelines_compiled"].as_u64(), Some(compiled));
    assert_eq!(first_image, second_image, "made ahead, the same bytes");

    // A stale list: an entry point and a shader this build lacks.
    let stale = format!("{text}post/copy.wgsl\t\tno_such_entry\nlighting/gone.wgsl\t\tmain\n");
    std::fs::write(&list, stale).expect("make it stale");
    let (stale, stale_image, stderr) = run("stale.png");
    let made = &stale["pipelines_ahead"];
    assert_eq!(made["listed"].as_u64(), Some(pipelines + 1), "{stale}");
    assert_eq!(made["failed"].as_u64(), Some(1), "{stale}");
    assert_eq!(made["taken"].as_u64(), Some(pipelines), "{stale}");
    assert!(!stderr.contains("error"), "{stderr}");
    assert_eq!(first_image, stale_image, "a stale list, the same bytes");

    std::fs::write(&list, "not a list").expect("damage it");
    let (third, third_image, stderr) = run("third.png");
    assert!(third["precompose"].is_null(), "{third}");
    assert!(third["pipelines_ahead"].is_null(), "{third}");
    assert!(
        stderr.contains("warning:") && stderr.contains(&list.display().to_string()),
        "{stderr}"
    );
    assert_eq!(first_image, third_image);
    let rewritten = std::fs::read_to_string(&list).expect("written anew");
    assert_eq!(rewritten, text, "written anew as the first run wrote it");
}

/// The half chains' passes (every Auto effect of post.ron forced to Half:
/// AO's and SSGI's chains, SSR's upsample) announce their pipelines, so a
/// first run's threads can make them before the frame needs them. (At 1080p
/// and above Auto is Half by default: on the H200 a first 1080p run of
/// post.ron made SSR's upsample in its frame, 844 ms against 674 before the
/// half chains, until the upsample announced itself.)
#[test]
fn the_half_chains_pipelines_are_announced_on_a_first_run() {
    let dir = tempfile::tempdir().expect("temp dir");
    let cache = dir.path().join("cache");
    let image = dir.path().join("half.png");
    let env = [
        ("SPREADLIGHT_CACHE_DIR", cache.to_str().expect("utf-8 path")),
        ("SPREADLIGHT_PIPELINE_CACHE", "off"),
        ("SPREADLIGHT_PIPELINES_AHEAD", "wait"),
        ("SPREADLIGHT_RESOLUTION_AUTO", "half"),
    ];
    let (first, _, _) = cold_start_render(
        "patches/post.ron",
        image.to_str().expect("utf-8 path"),
        &env,
    );
    // A frame may still make an announced pipeline itself when no thread
    // began it yet (`claimed`: lavapipe's machines have few cores); what
    // it must never make is one that no pass announced.
    let gathered = &first["pipelines_gathered"];
    assert_eq!(
        first["pipelines_at_frame"].as_u64(),
        gathered["claimed"].as_u64(),
        "the frame made one no pass announced: {first}"
    );
    assert!(
        gathered["listed"].as_u64() >= first["pipelines_compiled"].as_u64(),
        "all announced: {first}"
    );
}

/// The cold start's lists name what is not a file's permutation too:
/// environment-probe.ron with its light sets fused (a sun with a shadow map
/// and a point light: one generated shader) draws its shadow map, its
/// probe's faces and (on lavapipe) its G-buffer with render pipelines. On a
/// first run every pipeline its frame needs is announced by the pass that
/// uses it (the generated shader and the render pipelines included) and
/// made on threads; the list names the generated shader, so the second run
/// composes it and creates its pipeline ahead with the others, and the
/// frame makes none itself but those it asked for before a thread began
/// them. A stale generated entry (a generator this build lacks, a group
/// its generator refuses) is skipped, and the bytes are those of separate
/// passes.
#[test]
fn generated_light_sets_and_render_pipelines_are_made_ahead_on_a_first_and_a_second_run() {
    let dir = tempfile::tempdir().expect("temp dir");
    let cache = dir.path().join("cache");
    let cache_dir = cache.to_str().expect("utf-8 path");
    let run = |name: &str, fusion: &str| {
        let image = dir.path().join(name);
        let image = image.to_str().expect("utf-8 path");
        let env = [
            ("SPREADLIGHT_CACHE_DIR", cache_dir),
            ("SPREADLIGHT_PIPELINE_CACHE", "off"),
            ("SPREADLIGHT_PIPELINES_AHEAD", "wait"),
            ("SPREADLIGHT_LIGHT_FUSION", fusion),
        ];
        cold_start_render("patches/environment-probe.ron", image, &env)
    };
    let count = |stats: &serde_json::Value, name: &str| stats[name].as_u64().unwrap_or(0);
    let (first, first_image, _) = run("first.png", "fused");
    assert!(first["pipelines_ahead"].is_null(), "no list yet: {first}");
    let compiled = first["pipelines_compiled"].as_u64().expect("a count");
    let gathered = &first["pipelines_gathered"];
    assert_eq!(
        count(gathered, "listed"),
        compiled,
        "all announced: {first}"
    );
    assert_eq!(count(gathered, "failed"), 0, "{first}");
    assert_eq!(
        count(gathered, "taken") + count(gathered, "waited") + count(gathered, "claimed"),
        compiled,
        "every announced pipeline used: {first}"
    );
    assert_eq!(
        first["pipelines_at_frame"].as_u64(),
        Some(count(gathered, "claimed")),
        "the frame made none no pass announced: {first}"
    );
    let [list] = std::fs::read_dir(cache.join("permutations"))
        .expect("a list folder")
        .flatten()
        .map(|e| e.path())
        .collect::<Vec<_>>()
        .try_into()
        .expect("one list, the patch's");
    let text = std::fs::read_to_string(&list).expect("a list");
    let generated: Vec<&str> = text
        .lines()
        .filter(|l| l.starts_with("generated\t"))
        .collect();
    assert!(
        matches!(generated[..], [line] if line.starts_with("generated\tlight_sets\t")
            && line.split('\t').count() == 4),
        "the fused pair, by its two sets' permutations: {text}"
    );
    let entries = text.lines().filter(|l| l.split('\t').count() == 3).count() as u64;
    let permutations = text.lines().filter(|l| l.split('\t').count() == 2).count() as u64;
    // The frame's compute pipelines (the generated one among them); the
    // rest are render pipelines, which a list never names.
    let listed = entries + 1;
    assert!(listed < compiled, "render pipelines too: {text}{first}");

    let (second, second_image, _) = run("second.png", "fused");
    let precomposed = &second["precompose"];
    assert_eq!(count(precomposed, "listed"), permutations + 1, "{second}");
    assert_eq!(count(precomposed, "composed"), permutations + 1, "{second}");
    assert_eq!(second["permutations_composed"], 0, "{second}");
    assert_eq!(
        second["shader_libraries_ms"], 0.0,
        "no composer made, not even for the generated shader: {second}"
    );
    let ahead = &second["pipelines_ahead"];
    for (name, expected) in [
        ("listed", listed),
        ("created", listed),
        ("taken", listed),
        ("failed", 0),
        ("claimed", 0),
    ] {
        assert_eq!(count(ahead, name), expected, "{name}: {second}");
    }
    // The render pipelines, announced again and made on threads.
    let gathered = &second["pipelines_gathered"];
    assert_eq!(count(gathered, "listed"), compiled - listed, "{second}");
    assert_eq!(
        count(gathered, "taken") + count(gathered, "waited") + count(gathered, "claimed"),
        compiled - listed,
        "{second}"
    );
    assert_eq!(
        second["pipelines_at_frame"].as_u64(),
        Some(count(gathered, "claimed")),
        "{second}"
    );
    assert_eq!(second["pipelines_compiled"].as_u64(), Some(compiled));
    assert_eq!(first_image, second_image, "made ahead, the same bytes");

    // Stale: a generator this build lacks (skipped), a group its generator
    // refuses (composed and made by nobody: failed, never an error).
    let stale =
        format!("{text}generated\tno_such_generator\t\t\ngenerated\tlight_sets\tLIGHT_SUN\n");
    std::fs::write(&list, stale).expect("make it stale");
    let (stale, stale_image, stderr) = run("stale.png", "fused");
    let precomposed = &stale["precompose"];
    assert_eq!(count(precomposed, "listed"), permutations + 2, "{stale}");
    assert_eq!(count(precomposed, "composed"), permutations + 1, "{stale}");
    let ahead = &stale["pipelines_ahead"];
    assert_eq!(count(ahead, "listed"), listed + 1, "{stale}");
    assert_eq!(count(ahead, "failed"), 1, "{stale}");
    assert_eq!(count(ahead, "taken"), listed, "{stale}");
    assert!(!stderr.contains("error"), "{stderr}");
    assert_eq!(first_image, stale_image, "a stale list, the same bytes");

    // The same picture as a pass per light set.
    let (_, separate_image, _) = run("separate.png", "separate");
    assert_eq!(
        first_image, separate_image,
        "fused, the bytes of separate passes"
    );
}
