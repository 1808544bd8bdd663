//! What a sequence promises about its images: a chunk after its preroll
//! equals the full run; `--samples` accumulates sub-frames (anti-aliasing
//! and motion blur); video streams through ffmpeg. Renders are 64x36.

use crate::support;

use support::*;

const SPHERES: &str = "patches/gbuffer-spheres.ron";

/// Renders `frames` of `patch` as EXR into `dir`; returns the folder.
fn exr(patch: &str, dir: &std::path::Path, frames: &str, extra: &[&str]) -> std::path::PathBuf {
    exr_told(patch, dir, frames, extra).0
}

/// [`exr`], and what the run said on stderr.
fn exr_told(
    patch: &str,
    dir: &std::path::Path,
    frames: &str,
    extra: &[&str],
) -> (std::path::PathBuf, String) {
    let out = dir.join(format!("{frames}{}", extra.join("")));
    let template = out.join("f_####.exr");
    let mut args = vec![
        "render",
        patch,
        "-o",
        path(&template),
        "--size",
        "64x36",
        "--frames",
        frames,
    ];
    args.extend_from_slice(extra);
    let run = spreadlight(&args);
    ok(&run);
    (out, text(&run.stderr))
}

/// The files under `dir` (in subfolders too), by their path relative to it, sorted.
fn files_under(dir: &std::path::Path) -> Vec<std::path::PathBuf> {
    let mut found = Vec::new();
    let mut folders = vec![dir.to_path_buf()];
    while let Some(folder) = folders.pop() {
        for entry in std::fs::read_dir(&folder).expect("ls") {
            let path = entry.expect("entry").path();
            if path.is_dir() {
                folders.push(path);
            } else {
                found.push(path.strip_prefix(dir).expect("under").to_path_buf());
            }
        }
    }
    found.sort();
    found
}

/// patches/post.ron runs TAA, SSR and SSGI histories over moving balls; its
/// Output declares a 32-frame preroll. A chunk starting at frame 68 (after
/// that preroll) matches frames 68.. of a run from frame 0 within 0.03 in 99% of
/// values and 0.002 on average (linear values; the histories converge
/// geometrically); without the preroll it is over 3x further off. With
/// `--preroll all` a chunk past the declared preroll (frames 33-34) prerolls
/// from frame 0 and its files are byte for byte the full run's. With no
/// temporal node (gbuffer-spheres), a chunk is exact, sub-frames included.
#[test]
fn a_chunk_after_its_preroll_equals_the_full_run() {
    let dir = tempfile::tempdir().expect("tempdir");
    let full = exr("patches/post.ron", dir.path(), "0-71", &[]);
    let chunk = exr("patches/post.ron", dir.path(), "68-71", &[]);
    let cold = exr("patches/post.ron", dir.path(), "68-71", &["--preroll", "0"]);
    for f in 68..72 {
        let name = format!("f_{f:04}.exr");
        let (a, b, c) = (
            rgb(&full.join(&name)),
            rgb(&chunk.join(&name)),
            rgb(&cold.join(&name)),
        );
        let (max, mean, cold) = (
            quantile_difference(&a, &b, 0.99),
            mean_difference(&a, &b),
            mean_difference(&a, &c),
        );
        eprintln!("frame {f}: chunk max {max} mean {mean}; without preroll mean {cold}");
        assert!(
            max < 0.03 && mean < 0.002,
            "frame {f}: max {max}, mean {mean}"
        );
        assert!(
            cold > 3.0 * mean,
            "frame {f}: the preroll matters ({cold} vs {mean})"
        );
    }
    let all = exr(
        "patches/post.ron",
        dir.path(),
        "33-34",
        &["--preroll", "all"],
    );
    assert_eq!(
        files_under(&all),
        ["f_0033.exr", "f_0034.exr"].map(std::path::PathBuf::from)
    );
    for file in files_under(&all) {
        let same = std::fs::read(all.join(&file)).ok() == std::fs::read(full.join(&file)).ok();
        assert!(
            same,
            "{}: the chunk from frame 0 differs from the full run",
            file.display()
        );
    }
    let full = exr(SPHERES, dir.path(), "0-5", &["--samples", "2"]);
    let chunk = exr(SPHERES, dir.path(), "4-5", &["--samples", "2"]);
    for f in 4..6 {
        let name = format!("f_{f:04}.exr");
        assert_eq!(rgb(&full.join(&name)), rgb(&chunk.join(&name)), "frame {f}");
    }
}

/// A patch whose nodes keep state from frame to frame (particles.ron's
/// simulation; shader-nodes.ron's feedback trail and adapting luminance)
/// and whose Outputs declare no Preroll: a chunk prerolls from frame 0 by
/// default, says so, and writes byte for byte the files of a run from frame
/// 0. `--preroll 0` opts out, and its frames differ: the preroll is what
/// makes them equal. shader-nodes.ron runs at 2 frames a second so its noise
/// drifts a few pixels a frame and the feedback's trail shows.
#[test]
fn a_chunk_of_a_stateful_patch_prerolls_from_frame_0_and_equals_the_full_run() {
    let dir = tempfile::tempdir().expect("tempdir");
    let cases: [(&str, &[&str], &str, &str, &str); 2] = [
        ("patches/particles.ron", &[], "0-6", "5-6", "Particles"),
        (
            "patches/shader-nodes.ron",
            &["--fps", "2"],
            "0-4",
            "3-4",
            "Feedback (Shader)",
        ),
    ];
    for (patch, extra, whole, part, stateful) in cases {
        let dir = dir.path().join(patch.trim_start_matches("patches/"));
        let full = exr(patch, &dir, whole, extra);
        let (chunk, said) = exr_told(patch, &dir, part, extra);
        let first = part.split('-').next().expect("first");
        assert!(
            said.contains("prerolling frames 0 to ") && said.contains(stateful),
            "{patch}: no note of the preroll from frame 0 in:\n{said}"
        );
        let cold = exr(patch, &dir, part, &[extra, &["--preroll", "0"]].concat());
        let files = files_under(&chunk);
        assert!(
            !files.is_empty() && files == files_under(&cold),
            "{patch}: {files:?}"
        );
        let mut differ = 0;
        for file in &files {
            let read = |d: &std::path::Path| std::fs::read(d.join(file)).expect("read");
            assert!(
                read(&chunk) == read(&full),
                "{patch}: {} of the chunk from frame {first} differs from the full run",
                file.display()
            );
            differ += usize::from(read(&cold) != read(&full));
        }
        assert!(
            differ > 0,
            "{patch}: without the preroll nothing differs: the test shows nothing"
        );
    }
}

/// `--samples 16 --shutter 0`: sub-pixel jitter only, so the frame comes
/// closer to the same frame rendered 8x8 larger and box-downsampled (64
/// samples a pixel) than one sample does. `--samples 8 --shutter 1`: the
/// frame comes close to the average of 8 renders at the instants across the
/// frame (a fresh render at frame 3 and `--fps 3/t` is the instant t), far
/// closer than the sharp frame.
#[test]
fn samples_accumulate_jittered_sub_frames_across_the_shutter() {
    let dir = tempfile::tempdir().expect("tempdir");
    let at = |extra: &[&str]| rgb(&exr(SPHERES, dir.path(), "3", extra).join("f_0003.exr"));
    let one = at(&["--fps", "2"]);
    let aa = at(&["--fps", "2", "--samples", "16", "--shutter", "0"]);
    let big = dir.path().join("big.exr");
    ok(&spreadlight(&[
        "render",
        SPHERES,
        "-o",
        path(&big),
        "--size",
        "512x288",
        "--frames",
        "3",
        "--fps",
        "2",
    ]));
    let truth = downsampled(&rgb(&big), 512, 8);
    let (e1, e16) = (rmse(&one, &truth), rmse(&aa, &truth));
    eprintln!("vs 64 samples a pixel: RMSE 1 sample {e1}, 16 samples {e16}");
    assert!(
        e16 < 0.6 * e1,
        "16 jittered samples come closer to the supersampled frame: {e1} -> {e16}"
    );

    // Frame 3 at 2 fps is t = 1.5 s; the open shutter spans 1.25..1.75 s.
    let blur = at(&["--fps", "2", "--samples", "8", "--shutter", "1"]);
    let mut instants = vec![0.0f32; one.len()];
    for k in 0..8 {
        let t = 1.5 + ((f64::from(k) + 0.5) / 8.0 - 0.5) * 0.5;
        let image = at(&["--fps", &format!("{}", 3.0 / t)]);
        for (sum, v) in instants.iter_mut().zip(image) {
            *sum += v / 8.0;
        }
    }
    let (sharp, blurred) = (rmse(&one, &instants), rmse(&blur, &instants));
    eprintln!("vs the average of 8 instants: RMSE sharp frame {sharp}, --samples 8 {blurred}");
    assert!(
        blurred < 0.5 * sharp,
        "sub-frames across the shutter blur like the instants: {sharp} -> {blurred}"
    );
    assert_eq!(
        at(&["--fps", "2", "--samples", "1", "--shutter", "1"]),
        one,
        "one sample is the plain frame"
    );
}

#[test]
fn video_streams_frames_to_ffmpeg() {
    let dir = tempfile::tempdir().expect("tempdir");
    for (name, codec) in [("clip.mp4", "h264"), ("clip.mov", "prores")] {
        let video = dir.path().join(name);
        let out = spreadlight(&[
            "render",
            SPHERES,
            "-o",
            path(&video),
            "--size",
            "64x36",
            "--frames",
            "0-4",
        ]);
        ok(&out);
        let probe = std::process::Command::new("ffprobe")
            .args(["-v", "error", "-count_frames", "-select_streams", "v:0"])
            .args([
                "-show_entries",
                "stream=codec_name,nb_read_frames,width,height",
                "-of",
                "csv=p=0",
            ])
            .arg(&video)
            .output()
            .expect("ffprobe (Debian's ffmpeg package; .ci/run installs it)");
        let probed = text(&probe.stdout);
        assert_eq!(
            probed.trim(),
            format!("{codec},64,36,5"),
            "{name}: {}",
            text(&probe.stderr)
        );
    }
    assert_eq!(
        listing(dir.path()),
        ["clip.mov", "clip.mp4"],
        "no partial video is left"
    );

    // A video is made in one go: a second run renders it again.
    let out = spreadlight(&[
        "render",
        SPHERES,
        "-o",
        path(&dir.path().join("clip.mp4")),
        "--size",
        "64x36",
        "--frames",
        "0-4",
        "--json",
    ]);
    ok(&out);
    assert_eq!(done(&out)["written"], 5);
}

#[test]
fn video_without_ffmpeg_names_the_debian_package() {
    let dir = tempfile::tempdir().expect("tempdir");
    let out = command(&[
        "render",
        SPHERES,
        "-o",
        path(&dir.path().join("v.mp4")),
        "--size",
        "64x36",
        "--frames",
        "0-2",
    ])
    .env("SPREADLIGHT_FFMPEG", dir.path().join("no-ffmpeg-here"))
    .output()
    .expect("runs");
    assert_eq!(out.status.code(), Some(2), "{}", text(&out.stderr));
    let err = text(&out.stderr);
    assert!(
        err.contains("Debian's `ffmpeg` package") && err.contains("apt-get install ffmpeg"),
        "{err}"
    );
    assert!(listing(dir.path()).is_empty());
}
