//! `spreadlight render` as a sequence renderer: frame ranges and name
//! templates, resuming, atomic files, failing frames, several outputs,
//! bad input and progress. Renders are 64x36 (lavapipe in CI is slow).

use crate::support;

use std::path::Path;

use support::*;

const SPHERES: &str = "patches/gbuffer-spheres.ron";

fn render(patch: &str, out: &Path, extra: &[&str]) -> std::process::Output {
    let mut args = vec![
        "render",
        patch,
        "-o",
        path(out),
        "--size",
        "64x36",
        "--json",
    ];
    args.extend_from_slice(extra);
    spreadlight(&args)
}

#[test]
fn a_range_writes_one_padded_file_per_frame_in_steps() {
    let dir = tempfile::tempdir().expect("tempdir");
    let out = render(
        SPHERES,
        &dir.path().join("shot_####.png"),
        &["--frames", "2-8", "--step", "3"],
    );
    ok(&out);
    assert_eq!(
        listing(dir.path()),
        ["shot_0002.png", "shot_0005.png", "shot_0008.png"]
    );
    let written: Vec<(u64, String)> = [2, 5, 8].map(|f| (f, "written".to_owned())).to_vec();
    assert_eq!(statuses(&out), written);
    let events = events(&out);
    assert_eq!(events[0]["event"], "start");
    assert_eq!(events[0]["outputs"], serde_json::json!(["normals"]));
    assert_eq!(done(&out)["written"], 3);
    // Frames move: an animated camera.
    assert_ne!(
        std::fs::read(dir.path().join("shot_0002.png")).expect("read"),
        std::fs::read(dir.path().join("shot_0008.png")).expect("read")
    );

    let out = render(
        SPHERES,
        &dir.path().join("exr/f_{frame}.exr"),
        &["--frames", "4"],
    );
    ok(&out);
    let image = image::open(dir.path().join("exr/f_00004.exr")).expect("an EXR");
    assert_eq!((image.width(), image.height()), (64, 36));

    // One image (no frame number in the name) is rendered anew every time.
    for _ in 0..2 {
        let out = render(SPHERES, &dir.path().join("one.png"), &["--frames", "4"]);
        ok(&out);
        assert_eq!(done(&out)["written"], 1);
    }
}

#[test]
fn a_resumed_run_skips_complete_frames_and_redoes_broken_ones() {
    let dir = tempfile::tempdir().expect("tempdir");
    let template = dir.path().join("shot_####.png");
    ok(&render(SPHERES, &template, &["--frames", "0-3"]));
    let first: Vec<Vec<u8>> = (0..4)
        .map(|f| std::fs::read(dir.path().join(format!("shot_{f:04}.png"))).expect("read"))
        .collect();

    // Frame 1 gone, frame 2 cut short, and a killed writer's partial file of frame 3.
    std::fs::remove_file(dir.path().join("shot_0001.png")).expect("rm");
    std::fs::write(
        dir.path().join("shot_0002.png"),
        &first[2][..first[2].len() / 2],
    )
    .expect("cut");
    let host = std::fs::read_to_string("/proc/sys/kernel/hostname").expect("hostname");
    let partial = dir
        .path()
        .join(format!(".shot_0003.png.{}-4294967295.partial", host.trim()));
    std::fs::write(&partial, b"half a frame").expect("write");

    let dry = render(SPHERES, &template, &["--frames", "0-3", "--dry-run"]);
    ok(&dry);
    let expect = |s: [&str; 4]| -> Vec<(u64, String)> {
        let mut v: Vec<(u64, String)> = (0..4).map(|f| (f, s[f as usize].to_owned())).collect();
        v.sort_by_key(|(f, s)| (s != "skipped", *f));
        v
    };
    assert_eq!(
        statuses(&dry),
        expect(["skipped", "missing", "missing", "skipped"])
    );

    let out = render(SPHERES, &template, &["--frames", "0-3"]);
    ok(&out);
    assert_eq!(
        statuses(&out),
        expect(["skipped", "written", "written", "skipped"])
    );
    assert!(!partial.exists(), "the dead writer's partial file is swept");
    for (f, bytes) in first.iter().enumerate() {
        let now = std::fs::read(dir.path().join(format!("shot_{f:04}.png"))).expect("read");
        assert!(&now == bytes, "frame {f} equals the first run's");
    }

    let out = render(SPHERES, &template, &["--frames", "0-3", "--overwrite"]);
    ok(&out);
    assert_eq!(done(&out)["written"], 4);
}

#[test]
fn a_killed_run_leaves_only_whole_frames_and_resumes() {
    let dir = tempfile::tempdir().expect("tempdir");
    let template = dir.path().join("shot_####.png");
    let mut child = command(&[
        "render",
        SPHERES,
        "-o",
        path(&template),
        "--size",
        "64x36",
        "--frames",
        "0-100000",
    ])
    .stderr(std::process::Stdio::null())
    .spawn()
    .expect("spawn");
    let started = std::time::Instant::now();
    while listing(dir.path())
        .iter()
        .filter(|n| n.ends_with(".png"))
        .count()
        < 4
    {
        assert!(started.elapsed().as_secs() < 120, "no frames written");
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    child.kill().expect("SIGKILL");
    child.wait().expect("wait");
    let names = listing(dir.path());
    let frames: Vec<&String> = names.iter().filter(|n| !n.starts_with('.')).collect();
    for name in &frames {
        let image =
            image::open(dir.path().join(name)).unwrap_or_else(|e| panic!("{name} is whole: {e}"));
        assert_eq!((image.width(), image.height()), (64, 36));
    }
    // Everything else is a partial file, never a frame's own name.
    assert!(
        names
            .iter()
            .filter(|n| n.starts_with('.'))
            .all(|n| n.ends_with(".partial")),
        "{names:?}"
    );

    let last = frames.len() as u64 + 1;
    let out = render(SPHERES, &template, &["--frames", &format!("0-{last}")]);
    ok(&out);
    assert_eq!(done(&out)["skipped"], frames.len());
    assert_eq!(done(&out)["written"], 2);
    for name in listing(dir.path()) {
        // `.shot_NNNN.png.HOST-PID.partial`
        let frame: u64 = name.get(6..10).and_then(|f| f.parse().ok()).unwrap_or(0);
        assert!(
            !name.starts_with('.') || frame > last,
            "a partial file of a rendered frame is left: {name}"
        );
    }
}

/// Fault injection (`SPREADLIGHT_TEST_KILL_AT`, read by the writer alone):
/// the run aborts, with no cleanup, between writing frame 3's temporary file
/// and renaming it, and in another run between frames 3 and 4. What it left
/// is the whole frames before (frames are renamed in order, however many
/// are in flight), that temporary file and at most temporary files of later
/// frames; the resumed run removes them and ends with exactly the files of
/// an uninterrupted run, byte for byte.
#[test]
fn a_run_killed_between_write_and_rename_or_between_frames_resumes_to_the_same_files() {
    use std::os::unix::process::ExitStatusExt;
    let dir = tempfile::tempdir().expect("tempdir");
    let frames = ["--frames", "0-5"];
    let whole = dir.path().join("whole");
    ok(&render(SPHERES, &whole.join("shot_####.png"), &frames));
    let expected = listing(&whole);
    assert_eq!(expected.len(), 6, "{expected:?}");
    for (point, left, partial) in [("after-write:3", 3, true), ("between-frames:3", 4, false)] {
        let out = dir.path().join(point.replace(':', "-"));
        let template = out.join("shot_####.png");
        let patch = root().join(SPHERES);
        let killed = command(&[
            "render",
            path(&patch),
            "-o",
            path(&template),
            "--size",
            "64x36",
            "--frames",
            "0-5",
        ])
        // Where a core dump of the abort would go, if the system writes one: not the repository.
        .current_dir(dir.path())
        .env("SPREADLIGHT_TEST_KILL_AT", point)
        .output()
        .expect("runs");
        assert_eq!(
            killed.status.signal(),
            Some(6),
            "{point}: not aborted (SIGABRT): {:?}\n{}",
            killed.status,
            text(&killed.stderr)
        );
        let names = listing(&out);
        let (partials, files): (Vec<&String>, Vec<&String>) =
            names.iter().partition(|n| n.starts_with('.'));
        assert_eq!(
            files,
            expected[..left].iter().collect::<Vec<_>>(),
            "{point}"
        );
        // Later frames were in flight (encoded on other threads, waiting for their turn to be
        // renamed): their temporary files may be there, never a file under a frame's own name.
        let frame_of = |name: &str| -> u64 {
            name.strip_prefix(".shot_")
                .and_then(|n| n.get(..4))
                .and_then(|n| n.parse().ok())
                .unwrap_or_else(|| panic!("{point}: not a partial file of a frame: {name}"))
        };
        for name in &partials {
            assert!(name.ends_with(".partial"), "{point}: {names:?}");
            assert!(frame_of(name) >= left as u64, "{point}: {names:?}");
        }
        let own: Vec<&&String> = partials.iter().filter(|n| frame_of(n) == 3).collect();
        if partial {
            assert_eq!(own.len(), 1, "{point}: {names:?}");
            // Written and synced before the abort: the whole frame, under its temporary name.
            let bytes = std::fs::read(out.join(own[0])).expect("read");
            assert_eq!(
                bytes,
                std::fs::read(whole.join(&expected[3])).expect("read")
            );
        } else {
            assert!(own.is_empty(), "{point}: {names:?}");
        }

        let resumed = render(SPHERES, &template, &frames);
        ok(&resumed);
        assert_eq!(done(&resumed)["skipped"], left, "{point}");
        assert_eq!(done(&resumed)["written"], 6 - left, "{point}");
        assert_eq!(
            listing(&out),
            expected,
            "{point}: the files of an uninterrupted run"
        );
        for name in &expected {
            let read = |d: &Path| std::fs::read(d.join(name)).expect("read");
            assert!(
                read(&out) == read(&whole),
                "{point}: {name} differs from the uninterrupted run"
            );
        }
    }
    let bad = command(&["render", SPHERES, "-o", path(&dir.path().join("x_#.png"))])
        .env("SPREADLIGHT_TEST_KILL_AT", "sometime")
        .output()
        .expect("runs");
    assert_eq!(
        bad.status.code(),
        Some(2),
        "a kill point it cannot read is bad input"
    );
}

/// Several frames in flight (read back, encoded and written on other
/// threads, renamed in order) make the same bytes as frames rendered one by
/// one in runs of their own, PNG and EXR, with and without sub-frames; a
/// file that cannot be put in place fails its frame alone and leaves no
/// temporary file behind.
#[test]
fn frames_in_flight_write_the_bytes_of_single_frame_runs_and_fail_alone() {
    let dir = tempfile::tempdir().expect("tempdir");
    let read = |p: std::path::PathBuf| {
        std::fs::read(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
    };
    let seq = dir.path().join("seq");
    ok(&render(
        SPHERES,
        &seq.join("f_#.png"),
        &["--frames", "0-3", "--threads", "3"],
    ));
    for f in [0, 3] {
        let one = dir.path().join(format!("one_{f}.png"));
        ok(&render(SPHERES, &one, &["--frames", &f.to_string()]));
        assert!(
            read(one) == read(seq.join(format!("f_{f}.png"))),
            "frame {f}: the sequence's PNG differs from a run of its own"
        );
    }
    let exr = dir.path().join("exr");
    ok(&render(
        SPHERES,
        &exr.join("f_#.exr"),
        &["--frames", "0-2", "--samples", "2", "--threads", "2"],
    ));
    let one = dir.path().join("one_2.exr");
    ok(&render(SPHERES, &one, &["--frames", "2", "--samples", "2"]));
    assert!(
        read(one) == read(exr.join("f_2.exr")),
        "frame 2 of 2 sub-frames: the sequence's EXR differs from a run of its own"
    );

    // `--exr half`: the same frame as ZIP-compressed half floats, read back as the float frame's
    // values rounded to halves; whole, so a second run skips it.
    let half = dir.path().join("half/f_#.exr");
    let args = ["--frames", "2", "--samples", "2", "--exr", "half"];
    ok(&render(SPHERES, &half, &args));
    let halves = rgb(&dir.path().join("half/f_2.exr"));
    let floats: Vec<f32> = rgb(&exr.join("f_2.exr"))
        .into_iter()
        .map(|v| exr::prelude::f16::from_f32(v).to_f32())
        .collect();
    assert!(
        halves == floats,
        "the half EXR is not the float frame in halves"
    );
    assert!(
        read(dir.path().join("half/f_2.exr")).len() < read(exr.join("f_2.exr")).len() / 2,
        "half floats, compressed"
    );
    assert_eq!(done(&render(SPHERES, &half, &args))["skipped"], 1);

    // Frame 1's name is taken by a folder: its temporary file is written, the rename fails.
    let blocked = dir.path().join("blocked");
    std::fs::create_dir_all(blocked.join("f_1.png")).expect("mkdir");
    std::fs::write(blocked.join("f_1.png/keep"), b"x").expect("write");
    let out = render(SPHERES, &blocked.join("f_#.png"), &["--frames", "0-2"]);
    assert_eq!(out.status.code(), Some(1), "{}", text(&out.stderr));
    assert_eq!(done(&out)["failed"], serde_json::json!([1]));
    assert_eq!(done(&out)["written"], 2);
    assert_eq!(listing(&blocked), ["f_0.png", "f_1.png", "f_2.png"]);
    assert!(blocked.join("f_1.png").is_dir());
    assert!(
        text(&out.stderr).contains("cannot write") && text(&out.stderr).contains("f_1.png"),
        "{}",
        text(&out.stderr)
    );
}

/// The Output's texture holds halves, which the writers encode as they are (no round trip through
/// 32-bit floats): a half EXR sequence's frame is the file of a run of that frame alone, and reads
/// back as the 32-bit EXR's values rounded to halves. The `done` line says where the time went.
#[test]
fn sequence_frames_are_the_files_of_single_frame_runs_in_every_format() {
    let dir = tempfile::tempdir().expect("tempdir");
    let read = |p: std::path::PathBuf| {
        std::fs::read(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
    };
    let seq = render(
        SPHERES,
        &dir.path().join("seq/f_#.exr"),
        &["--frames", "0-2", "--threads", "2", "--exr", "half"],
    );
    ok(&seq);
    let one = dir.path().join("one/f_#.exr");
    ok(&render(SPHERES, &one, &["--frames", "2", "--exr", "half"]));
    let half = read(dir.path().join("seq/f_2.exr"));
    assert!(
        half == read(dir.path().join("one/f_2.exr")),
        "frame 2: the sequence's half EXR differs from a run of its own"
    );
    let float = dir.path().join("float.exr");
    ok(&render(SPHERES, &float, &["--frames", "2"]));
    let halves: Vec<f32> = rgb(&float)
        .into_iter()
        .map(|v| exr::prelude::f16::from_f32(v).to_f32())
        .collect();
    assert!(
        rgb(&dir.path().join("seq/f_2.exr")) == halves,
        "the half EXR is not the float frame in halves"
    );
    // Every stage is reported, as a mean per frame.
    let stages = &done(&seq)["stages"];
    assert_eq!(
        (stages["frames"].clone(), stages["threads"].clone()),
        (3.into(), 2.into())
    );
    for key in [
        "evaluate_ms",
        "submit_wait_ms",
        "commit_ms",
        "readback_wait_ms",
        "readback_copy_ms",
        "convert_ms",
        "compress_ms",
        "write_ms",
        "sync_ms",
        "writer_busy_ms",
        "writer_utilization",
        "fps_after_first",
    ] {
        let value = stages[key].as_f64();
        assert!(value.is_some_and(|v| v >= 0.0), "{key}: {stages}");
    }
    assert!(stages["compress_ms"].as_f64() > Some(0.0), "{stages}");
    assert!(stages["sync_ms"].as_f64() > Some(0.0), "{stages}");
}

/// `--samples 3` adds its sub-frames up on the GPU and reads the sum back once: the frame is the
/// CPU's f32 sum of the three sub-frames rendered alone (`--sub-frame K`), added in order and
/// divided once, bit for bit; against the f64 average the CPU made before, it differs by the f32
/// rounding of the sum only.
#[test]
fn samples_summed_on_the_gpu_are_the_average_of_the_sub_frames() {
    let dir = tempfile::tempdir().expect("tempdir");
    let rgba = |p: &Path| -> Vec<f32> {
        image::open(p)
            .unwrap_or_else(|e| panic!("{}: {e}", p.display()))
            .to_rgba32f()
            .into_raw()
    };
    let frame = ["--frames", "2", "--samples", "3"];
    let summed = dir.path().join("summed.exr");
    let out = render(SPHERES, &summed, &frame);
    ok(&out);
    assert_eq!(
        done(&out)["sub_frames"],
        serde_json::json!({"summed_on_gpu": 1, "averaged_on_cpu": 0})
    );
    let subs: Vec<Vec<f32>> = (0..3)
        .map(|k| {
            let one = dir.path().join(format!("sub_{k}.exr"));
            let k = k.to_string();
            ok(&render(
                SPHERES,
                &one,
                &[&frame[..], &["--sub-frame", &k]].concat(),
            ));
            rgba(&one)
        })
        .collect();
    let gpu = rgba(&summed);
    assert_eq!(gpu.len(), 64 * 36 * 4);
    // The sub-frames differ (each has its own sub-pixel offset), so the average means something.
    assert!(max_difference(&subs[0], &subs[1]) > 0.01);
    assert!(max_difference(&gpu, &subs[0]) > 0.001);
    let in_f32: Vec<f32> = (0..gpu.len())
        .map(|i| f64::from(0.0 + subs[0][i] + subs[1][i] + subs[2][i]) / 3.0)
        .map(|v| v as f32)
        .collect();
    let same = gpu
        .iter()
        .zip(&in_f32)
        .filter(|(a, b)| a.to_bits() == b.to_bits())
        .count();
    assert_eq!(
        same,
        gpu.len(),
        "the GPU's sum is the f32 sum of the sub-frames"
    );
    let in_f64: Vec<f32> = (0..gpu.len())
        .map(|i| ((0..3).map(|k| f64::from(subs[k][i])).sum::<f64>() / 3.0) as f32)
        .collect();
    // Two f32 roundings of the sum (each within half a unit of the partial sum's last place)
    // and one of the result: within EPSILON x (the sum of magnitudes / 3 + the result).
    for (i, (a, b)) in gpu.iter().zip(&in_f64).enumerate() {
        let magnitudes: f32 = (0..3).map(|k| subs[k][i].abs()).sum();
        let bound = f32::EPSILON * (magnitudes / 3.0 + b.abs());
        assert!((a - b).abs() <= bound, "value {i}: {a} against {b}");
    }
    // As 8-bit sRGB, a value changes only where the f64 average sits at a rounding step: by one.
    let png = dir.path().join("summed.png");
    ok(&render(SPHERES, &png, &frame));
    let bytes = |image: image::DynamicImage| image.to_rgba8().into_raw();
    let gpu_png = bytes(image::open(&png).expect("a PNG"));
    let average = spreadlight_render::readback::ImageF32 {
        width: 64,
        height: 36,
        pixels: in_f64
            .chunks_exact(4)
            .map(|p| [p[0], p[1], p[2], p[3]])
            .collect(),
    };
    let encoded = spreadlight_render::image_io::encode_image(
        &average,
        spreadlight_render::image_io::Encoding::Srgb,
        false,
    )
    .expect("encodes");
    let cpu_png = bytes(image::load_from_memory(&encoded).expect("decodes"));
    let steps: Vec<u8> = gpu_png
        .iter()
        .zip(&cpu_png)
        .map(|(a, b)| a.abs_diff(*b))
        .collect();
    assert!(steps.iter().all(|&d| d <= 1));
    eprintln!(
        "GPU sum against the f64 average: max abs difference {:e}; {} of {} PNG values differ (by 1)",
        max_difference(&gpu, &in_f64),
        steps.iter().filter(|&&d| d > 0).count(),
        steps.len()
    );

    let out = render(
        SPHERES,
        &dir.path().join("x.exr"),
        &[&frame[..], &["--sub-frame", "3"]].concat(),
    );
    assert_eq!(out.status.code(), Some(2), "{}", text(&out.stderr));
    assert!(
        text(&out.stderr).contains("--sub-frame 3"),
        "{}",
        text(&out.stderr)
    );
}

#[test]
fn a_failing_frame_is_reported_and_the_rest_go_on() {
    let dir = tempfile::tempdir().expect("tempdir");
    // The LFO drives the camera's FOV: from frame 5 on (phase 0.5 at 10 fps) it is out of range.
    let patch = spheres_variant(
        dir.path(),
        "fov.ron",
        &[
            ("\"Period\": Float([10.0])", "\"Period\": Float([1.0])"),
            ("to: (6, \"Yaw\")", "to: (6, \"FOV\")"),
        ],
    );
    let out = render(
        path(&patch),
        &dir.path().join("out/f_##.png"),
        &["--frames", "1-6", "--fps", "10"],
    );
    assert_eq!(out.status.code(), Some(1), "{}", text(&out.stderr));
    assert_eq!(
        listing(&dir.path().join("out")),
        ["f_01.png", "f_02.png", "f_03.png", "f_04.png"]
    );
    assert_eq!(done(&out)["failed"], serde_json::json!([5, 6]));
    let errors: Vec<serde_json::Value> = events(&out)
        .into_iter()
        .filter(|e| e["event"] == "error")
        .collect();
    assert!(
        errors.iter().any(|e| e["frame"] == 5
            && e["message"]
                .as_str()
                .is_some_and(|m| m.contains("#6") && m.contains("FOV"))),
        "{errors:?}"
    );
    assert!(
        text(&out.stderr).contains("frame 5:"),
        "{}",
        text(&out.stderr)
    );
}

#[test]
fn several_outputs_write_several_sequences_named_by_their_name_pin() {
    let dir = tempfile::tempdir().expect("tempdir");
    let patch = two_outputs(dir.path());
    ok(&render(
        path(&patch),
        &dir.path().join("a/shot_####.png"),
        &["--frames", "0-1"],
    ));
    assert_eq!(listing(&dir.path().join("a")), ["copy", "normals"]);
    for name in ["copy", "normals"] {
        assert_eq!(
            listing(&dir.path().join("a").join(name)),
            ["shot_0000.png", "shot_0001.png"]
        );
    }
    ok(&render(
        path(&patch),
        &dir.path().join("b/{name}_##.png"),
        &["--frames", "3"],
    ));
    assert_eq!(
        listing(&dir.path().join("b")),
        ["copy_03.png", "normals_03.png"]
    );
    ok(&render(
        path(&patch),
        &dir.path().join("c/s_#.png"),
        &["--frames", "3", "--output-name", "copy"],
    ));
    assert_eq!(listing(&dir.path().join("c")), ["s_3.png"]);
}

#[test]
fn bad_input_exits_2_naming_what_is_wrong() {
    let dir = tempfile::tempdir().expect("tempdir");
    let o = |name: &str| dir.path().join(name).to_string_lossy().into_owned();
    let cases: [(Vec<String>, &str); 7] = [
        (vec![SPHERES.into(), "-o".into(), o("x.jpg")], ".png, .exr"),
        (
            vec![
                SPHERES.into(),
                "-o".into(),
                o("x.png"),
                "--frames".into(),
                "0-3".into(),
            ],
            "add `####`",
        ),
        (
            vec![
                SPHERES.into(),
                "-o".into(),
                o("x_#.png"),
                "--frames".into(),
                "5-2".into(),
            ],
            "before the first",
        ),
        (
            vec!["patches/no-such.ron".into(), "-o".into(), o("x.png")],
            "no-such.ron",
        ),
        (
            vec!["patches/lfo-sine.ron".into(), "-o".into(), o("x.png")],
            "no `Output` node",
        ),
        (
            vec![
                "patches/bad/01-malformed-ron.ron".into(),
                "-o".into(),
                o("x.png"),
            ],
            "01-malformed-ron.ron",
        ),
        (
            vec![
                SPHERES.into(),
                "-o".into(),
                o("x.png"),
                "--output-name".into(),
                "nope".into(),
            ],
            "`nope`",
        ),
    ];
    for (args, says) in cases {
        let mut all = vec!["render".to_owned()];
        all.extend(args);
        let all: Vec<&str> = all.iter().map(String::as_str).collect();
        let out = spreadlight(&all);
        assert_eq!(out.status.code(), Some(2), "{all:?}: {}", text(&out.stderr));
        assert!(
            text(&out.stderr).contains(says),
            "{all:?} should say {says}: {}",
            text(&out.stderr)
        );
    }
    // A patch that loads with errors renders nothing.
    let broken = spheres_variant(
        dir.path(),
        "broken.ron",
        &[("to: (9, \"Texture\")", "to: (9, \"Nope\")")],
    );
    let out = spreadlight(&["render", path(&broken), "-o", &o("y.png")]);
    assert_eq!(out.status.code(), Some(2), "{}", text(&out.stderr));
    assert!(
        text(&out.stderr).contains("Nope") && text(&out.stderr).contains("the patch has errors"),
        "{}",
        text(&out.stderr)
    );
    assert_eq!(
        listing(dir.path()),
        ["broken.ron"],
        "bad input writes nothing"
    );
}

#[test]
fn a_terminal_gets_a_progress_bar_and_a_pipe_gets_lines() {
    let dir = tempfile::tempdir().expect("tempdir");
    let out = spreadlight(&[
        "render",
        SPHERES,
        "-o",
        path(&dir.path().join("p_#.png")),
        "--size",
        "64x36",
        "--frames",
        "0-2",
    ]);
    ok(&out);
    let err = text(&out.stderr);
    assert!(
        err.contains("frame 2: wrote") && err.contains("3 written, 0 skipped"),
        "{err}"
    );

    // `script` gives the command a terminal: indicatif draws its bar there.
    let render = format!(
        "{} render {SPHERES} -o {} --size 64x36 --frames 0-2 --overwrite",
        env!("CARGO_BIN_EXE_spreadlight"),
        path(&dir.path().join("p_#.png"))
    );
    let out = std::process::Command::new("script")
        .args(["-qec", &render, "/dev/null"])
        .current_dir(root())
        .output()
        .expect("script (util-linux) runs");
    ok(&out);
    let tty = text(&out.stdout);
    assert!(tty.contains("frames") && tty.contains("ETA"), "{tty}");
}

/// A video on a lit surface (patches/video-surface.ron, issue 37): a chunk
/// that starts mid-run writes the same bytes as the full run for its
/// frames, because the VideoFile shows the frame at the clock's time
/// whichever frame came before; and the video moves from frame to frame.
#[test]
fn a_video_texture_renders_the_same_bytes_in_a_chunk_as_in_a_full_run() {
    let dir = tempfile::tempdir().expect("tempdir");
    let patch = "patches/video-surface.ron";
    ok(&render(
        patch,
        &dir.path().join("full/f_####.png"),
        &["--frames", "0-4"],
    ));
    ok(&render(
        patch,
        &dir.path().join("chunk/f_####.png"),
        &["--frames", "3-4"],
    ));
    let read = |run: &str, frame: u32| {
        std::fs::read(dir.path().join(format!("{run}/f_{frame:04}.png"))).expect("read")
    };
    for frame in [3, 4] {
        assert_eq!(read("full", frame), read("chunk", frame), "frame {frame}");
    }
    assert_ne!(read("full", 3), read("full", 4), "the video moves");
}
