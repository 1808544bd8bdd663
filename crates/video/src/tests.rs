//! The crate's tests, on small clips the ffmpeg command makes (CI installs it).

use std::path::{Path, PathBuf};
use std::process::Command;

use crate::{DecodeAhead, MediaError, Recorder, RecorderOptions, Source};

/// Run the ffmpeg command with `args`, quietly; panics with its output on failure.
pub(crate) fn ffmpeg(args: &[&str]) {
    let out = Command::new("ffmpeg")
        .args(["-hide_banner", "-loglevel", "error", "-y"])
        .args(args)
        .output()
        .expect("the ffmpeg command (apt install ffmpeg)");
    assert!(
        out.status.success(),
        "ffmpeg {args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// A 64x36 H.264 clip of `seconds` at 30 fps, a key frame a second.
pub(crate) fn clip(dir: &Path, seconds: u32) -> PathBuf {
    let path = dir.join("clip.mp4");
    let source = format!("testsrc=size=64x36:rate=30:duration={seconds}");
    ffmpeg(&[
        "-f",
        "lavfi",
        "-i",
        &source,
        "-c:v",
        "libx264",
        "-g",
        "30",
        "-pix_fmt",
        "yuv420p",
        path.to_str().expect("utf-8 path"),
    ]);
    path
}

fn mean_difference(a: &[u8], b: &[u8]) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .map(|(x, y)| f64::from(x.abs_diff(*y)))
        .sum::<f64>()
        / a.len() as f64
}

#[test]
fn any_frame_decodes_the_same_whichever_frame_came_before() {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = clip(dir.path(), 3);
    let mut source = Source::open(&path, 30.0).expect("opens");
    let info = source.info();
    assert_eq!((info.width, info.height, info.frames), (64, 36, 90));
    assert!((info.fps - 30.0).abs() < 1e-9);
    let sequential: Vec<Vec<u8>> = (0..90)
        .map(|n| source.frame(n).expect("decodes").rgba.clone())
        .collect();
    assert_ne!(sequential[0], sequential[45], "testsrc moves");
    // Out of order, as a farm chunk or a scrub asks: the same bytes.
    let mut fresh = Source::open(&path, 30.0).expect("opens");
    for n in [75u64, 12, 89, 0, 31, 30, 29, 60] {
        let frame = fresh.frame(n).expect("decodes");
        assert_eq!(frame.index, n);
        assert_eq!(frame.rgba, sequential[n as usize], "frame {n}");
    }
    // The frame shown at a time: 2.5 s is frame 75.
    let at = fresh.frame_at(2.5, false).expect("decodes");
    assert_eq!(at.rgba, sequential[75]);
    // The ffmpeg command's own frame 45 looks the same (its RGB conversion
    // may differ in the last bits).
    let png = dir.path().join("f45.png");
    ffmpeg(&[
        "-i",
        path.to_str().expect("utf-8"),
        "-vf",
        "select=eq(n\\,45)",
        "-frames:v",
        "1",
        png.to_str().expect("utf-8"),
    ]);
    let theirs = image::open(&png).expect("png").to_rgba8();
    assert!(mean_difference(theirs.as_raw(), &sequential[45]) < 6.0);
}

#[test]
fn image_sequences_follow_the_numbers_of_the_pattern() {
    let dir = tempfile::tempdir().expect("tempdir");
    let frames = dir.path().join("frames");
    std::fs::create_dir(&frames).expect("dir");
    for (n, grey) in [(10u8, 10u8), (9, 90), (11, 110)] {
        image::RgbaImage::from_pixel(4, 2, image::Rgba([grey, grey, grey, 255]))
            .save(frames.join(format!("f_{n:04}.png")))
            .expect("write");
    }
    std::fs::write(frames.join("notes.txt"), "not a frame").expect("write");
    let mut source = Source::open(&frames.join("f_####.png"), 24.0).expect("opens");
    let info = source.info();
    assert_eq!((info.width, info.height, info.frames), (4, 2, 3));
    assert_eq!(source.frame(0).expect("frame").rgba[0], 90, "f_0009 first");
    assert_eq!(source.frame(2).expect("frame").rgba[0], 110);
    assert_eq!(
        source.frame_at(1.0 / 24.0, false).expect("frame").rgba[0],
        10
    );
    assert_eq!(source.frame(7).expect("held").rgba[0], 110);
    let empty = Source::open(&frames.join("g_##.png"), 24.0).err();
    assert!(
        matches!(empty, Some(MediaError::EmptySequence(_))),
        "{empty:?}"
    );
}

#[test]
fn missing_truncated_and_garbage_files_are_errors_naming_the_file() {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = clip(dir.path(), 1);
    let bytes = std::fs::read(&path).expect("read");
    let truncated = dir.path().join("truncated.mp4");
    std::fs::write(&truncated, &bytes[..bytes.len() / 2]).expect("write");
    let garbage = dir.path().join("garbage.mp4");
    std::fs::write(
        &garbage,
        (0..4096u32)
            .map(|i| (i * 7919 % 251) as u8)
            .collect::<Vec<_>>(),
    )
    .expect("write");
    for (file, what) in [
        (dir.path().join("missing.mp4"), "no such file"),
        (truncated, "not a video"),
        (garbage, "not a video"),
    ] {
        let message = match Source::open(&file, 30.0) {
            Ok(_) => panic!("{} opened", file.display()),
            Err(e) => e.to_string(),
        };
        assert!(message.contains(&*file.to_string_lossy()), "{message}");
        assert!(message.contains(what), "{message}");
    }
}

#[test]
fn decoding_ahead_gives_the_exact_frames_once_ready_and_counts_late_ones() {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = clip(dir.path(), 2);
    let mut exact = Source::open(&path, 30.0).expect("opens");
    let mut ahead = DecodeAhead::new(Source::open(&path, 30.0).expect("opens"));
    let mut late = 0;
    for n in [0u64, 1, 2, 3, 40, 41, 5] {
        let waited = std::time::Instant::now();
        loop {
            let taken = ahead.take(n, true).expect("decodes");
            if !taken.late {
                let frame = taken.frame.expect("a frame");
                assert_eq!(frame.index, n);
                assert_eq!(
                    frame.rgba,
                    exact.frame(n).expect("decodes").rgba,
                    "frame {n}"
                );
                break;
            }
            late += 1;
            // A late frame keeps showing the last one on time.
            assert!(taken.frame.is_none_or(|f| f.index != n));
            assert!(waited.elapsed().as_secs() < 60, "frame {n} never came");
            std::thread::sleep(std::time::Duration::from_millis(2));
        }
    }
    assert!(
        late >= 1,
        "the first frame cannot be ready before it is asked for"
    );
    assert!(ahead.cost().0 >= 7);
}

#[test]
fn a_recording_has_its_frames_and_the_sound_of_the_audio_file() {
    let dir = tempfile::tempdir().expect("tempdir");
    let tone = dir.path().join("tone.wav");
    ffmpeg(&[
        "-f",
        "lavfi",
        "-i",
        "sine=frequency=440:duration=3",
        tone.to_str().expect("utf-8"),
    ]);
    let path = dir.path().join("out.mp4");
    let mut recorder = Recorder::start(RecorderOptions {
        path: path.clone(),
        width: 64,
        height: 36,
        fps: 30.0,
        audio: Some(tone),
        queue: 4,
    })
    .expect("starts");
    for n in 0..30u64 {
        let grey = (n * 8) as u8;
        let rgba: Vec<u8> = (0..64 * 36)
            .flat_map(|_| [grey, 255 - grey, 128, 255])
            .collect();
        recorder.push_wait(rgba, n).expect("queued");
    }
    let summary = recorder.finish().expect("finished");
    assert_eq!(
        (summary.frames, summary.dropped, summary.audio),
        (30, 0, true)
    );
    let mut back = Source::open(&path, 30.0).expect("reads back");
    assert_eq!(back.info().frames, 30);
    let frame = back.frame(20).expect("decodes");
    let px = &frame.rgba[(18 * 64 + 32) * 4..][..3];
    for (got, want) in px.iter().zip([160u8, 95, 128]) {
        assert!(got.abs_diff(want) <= 4, "{px:?}");
    }
    let probe = Command::new("ffprobe")
        .args([
            "-v",
            "error",
            "-show_entries",
            "stream=codec_type",
            "-of",
            "csv=p=0",
        ])
        .arg(&path)
        .output()
        .expect("ffprobe");
    let streams = String::from_utf8_lossy(&probe.stdout);
    assert_eq!(
        streams.split_whitespace().collect::<Vec<_>>(),
        ["video", "audio"],
        "{streams}"
    );
    let bad = Recorder::start(RecorderOptions {
        path: dir.path().join("no.such-format"),
        width: 64,
        height: 36,
        fps: 30.0,
        audio: None,
        queue: 4,
    });
    assert!(
        bad.err()
            .is_some_and(|e| e.to_string().contains("no.such-format"))
    );
}

/// Decode throughput and seek latency at 1080p, for docs/media.md:
/// `cargo test -p spreadlight-video --lib -- --ignored --nocapture throughput`.
/// A 10-second 1920x1080 H.264 clip (testsrc2, 30 fps, a key frame every 2 s,
/// x264's medium preset) is made in the temporary folder first.
#[test]
#[ignore = "a measurement, not a test: run it by hand"]
fn throughput_and_seek_latency_at_1080p() {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = dir.path().join("1080p.mp4");
    ffmpeg(&[
        "-f",
        "lavfi",
        "-i",
        "testsrc2=size=1920x1080:rate=30:duration=10",
        "-c:v",
        "libx264",
        "-g",
        "60",
        "-pix_fmt",
        "yuv420p",
        path.to_str().expect("utf-8"),
    ]);
    let mut source = Source::open(&path, 30.0).expect("opens");
    let frames = source.info().frames;
    let started = std::time::Instant::now();
    for n in 0..frames {
        source.frame(n).expect("decodes");
    }
    let seconds = started.elapsed().as_secs_f64();
    println!(
        "sequential: {frames} frames in {seconds:.2} s = {:.1} frames/s (decode + RGBA)",
        frames as f64 / seconds
    );
    // Seeks to scattered frames (a fixed sequence, each far from the last).
    let targets: Vec<u64> = (0..20u64).map(|k| (k * 137 + 61) % frames).collect();
    let mut latencies = Vec::new();
    for &n in &targets {
        let mut fresh = Source::open(&path, 30.0).expect("opens");
        fresh.frame(frames - 1).expect("decodes");
        let started = std::time::Instant::now();
        fresh.frame(n).expect("decodes");
        latencies.push(started.elapsed().as_secs_f64() * 1e3);
    }
    latencies.sort_by(f64::total_cmp);
    let mean = latencies.iter().sum::<f64>() / latencies.len() as f64;
    println!(
        "seek: mean {mean:.1} ms, median {:.1} ms, worst {:.1} ms over {} seeks (key frame every 2 s)",
        latencies[latencies.len() / 2],
        latencies[latencies.len() - 1],
        latencies.len()
    );
}
