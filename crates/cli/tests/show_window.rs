//! The show window in a real X window under Xvfb (see editor_window.rs):
//! opened from the editor with F11, and `spreadlight play --native`.

use std::path::{Path, PathBuf};
use std::process::Stdio;

// Shared with editor_window.rs, which uses the helpers this file does not.
#[allow(dead_code)]
mod xwindow;

use xwindow::{Input, Xvfb};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The editor on `patches/showcase.ron` (playing) with its show window
/// opened by F11, as a user would.
struct Opened {
    editor: std::process::Child,
    input: Input,
    /// The editor's window and the show window.
    window: u32,
    show: u32,
    /// What the editor prints, shown with any failure.
    log: PathBuf,
}

impl Opened {
    fn printed(&self) -> String {
        std::fs::read_to_string(&self.log).unwrap_or_default()
    }

    /// Wait until `found`; after a minute, fail with a screenshot and the editor's log.
    fn wait_until(&self, what: &str, found: &dyn Fn() -> bool) {
        wait_until(&self.input, &self.log, what, found);
    }
}

fn wait_until(input: &Input, log: &Path, what: &str, found: &dyn Fn() -> bool) {
    let waited = std::time::Instant::now();
    while !found() {
        if waited.elapsed().as_secs() >= 60 {
            let shot = std::env::temp_dir().join("spreadlight-show-window-test.png");
            input.shot(&shot);
            panic!(
                "{what} not within a minute; the screen: {}; the editor printed: {}",
                shot.display(),
                std::fs::read_to_string(log).unwrap_or_default()
            );
        }
        std::thread::sleep(std::time::Duration::from_millis(200));
    }
}

const F11: u32 = 0xffc8;
const ESCAPE: u32 = 0xff1b;

fn open_show_window(x: &Xvfb, dir: &Path) -> Opened {
    let log = dir.join("editor-stderr.txt");
    let editor = x
        .spreadlight(&dir.join("config"))
        .arg("edit")
        .arg(root().join("patches/showcase.ron"))
        .stdout(Stdio::null())
        .stderr(std::fs::File::create(&log).expect("the editor's log"))
        .spawn()
        .expect("the editor starts");
    let input = Input::connect(x);
    wait_until(&input, &log, "the editor window", &|| {
        input.shown_window(400, 300).is_some()
    });
    let window = input.shown_window(400, 300).expect("the editor");
    // Its first frame (the GPU starts, the patch's pipelines compile) comes
    // after the window shows, and a key typed before it is lost: wait until
    // the window has drawn something.
    wait_until(&input, &log, "the editor's first frame", &|| {
        input.region(0, 0, 400, 300).iter().any(|&b| b != 0)
    });
    input.focus(window);
    input.hover(200, 200);
    input.key(F11);
    // On a loaded machine a key can still arrive before egui has the
    // keyboard: type it once more if nothing opened within 20 s.
    let typed = std::time::Instant::now();
    while input.other_windows(window).is_empty() && typed.elapsed().as_secs() < 20 {
        std::thread::sleep(std::time::Duration::from_millis(200));
    }
    if input.other_windows(window).is_empty() {
        input.focus(window);
        input.hover(200, 200);
        input.key(F11);
    }
    wait_until(&input, &log, "a second window", &|| {
        !input.other_windows(window).is_empty()
    });
    let shown = input.other_windows(window);
    assert_eq!(shown.len(), 1, "one show window: {shown:?}");
    let show = shown[0].0;
    Opened {
        editor,
        input,
        window,
        show,
        log,
    }
}

/// F11 in the editor opens the show window: a second top-level window, of
/// the show window's default size (640x360 points, 1 pixel a point here),
/// beside the editor's; Esc in it closes it and the editor stays.
#[test]
fn f11_opens_a_second_window_for_the_output_and_esc_closes_it() {
    let x = Xvfb::start();
    let dir = tempfile::tempdir().expect("tempdir");
    let mut o = open_show_window(&x, dir.path());
    let shown = o.input.other_windows(o.window);
    assert_eq!(shown[0].1, (640, 360), "the show window's size");
    o.input.focus(o.show);
    o.input.key(ESCAPE);
    o.wait_until("the show window closing", &|| {
        o.input.other_windows(o.window).is_empty()
    });
    assert_eq!(
        o.editor.try_wait().expect("status"),
        None,
        "the editor is still running; it printed: {}",
        o.printed()
    );
    o.editor.kill().expect("SIGKILL");
    o.editor.wait().expect("reaped");
}

/// Both windows resized again and again while the showcase plays: each
/// resize makes eframe configure a surface, in its event loop or while
/// drawing the show window, as the patch's worker renders on the same queue.
/// wgpu refuses a configure that meets another thread's submission, and the
/// editor then died ("Surface is not configured for presentation"); the
/// submission gate (`crates/render/src/submission_gate.rs`) keeps them apart.
/// A stress run by hand (tens of seconds; `SPREADLIGHT_RESIZES`, default 60):
/// `cargo test -p spreadlight-cli --test show_window -- --ignored resiz`.
#[test]
#[ignore = "a stress run by hand: tens of seconds"]
fn resizing_both_windows_while_the_showcase_plays_keeps_the_editor_running() {
    let resizes: u16 = std::env::var("SPREADLIGHT_RESIZES")
        .ok()
        .and_then(|n| n.parse().ok())
        .unwrap_or(60);
    let x = Xvfb::start();
    let dir = tempfile::tempdir().expect("tempdir");
    let mut o = open_show_window(&x, dir.path());
    let sizes = |i: u16| {
        let step = i % 6;
        (
            (1200 + 40 * step, 700 + 30 * step),
            (400 + 50 * step, 240 + 30 * step),
        )
    };
    for i in 0..resizes {
        let (editor, show) = sizes(i);
        o.input.resize(o.window, editor.0, editor.1);
        o.input.resize(o.show, show.0, show.1);
        std::thread::sleep(std::time::Duration::from_millis(150));
        if o.editor.try_wait().expect("status").is_some() {
            break;
        }
    }
    if o.editor.try_wait().expect("status").is_none() {
        // The resizes took: both windows have the last sizes asked for.
        let (editor, show) = sizes(resizes.saturating_sub(1));
        let size = |w: u32| {
            let (_, _, width, height) = o.input.geometry(w);
            (width as u16, height as u16)
        };
        o.wait_until("the last sizes", &|| {
            size(o.window) == editor && size(o.show) == show
        });
    }
    assert_eq!(
        o.editor.try_wait().expect("status"),
        None,
        "the editor died; it printed: {}",
        o.printed()
    );
    assert!(
        !o.printed().contains("warning: GPU"),
        "a device error: {}",
        o.printed()
    );
    o.editor.kill().expect("SIGKILL");
    o.editor.wait().expect("reaped");
}

/// `spreadlight play --native`: the window takes the Output texture's own
/// pixel size (a 200x120 image file) instead of its 320x180, and the
/// screenshot is the image itself, pixel for pixel. Without `--native` the
/// screenshot comes as soon as the image is shown.
#[test]
fn play_native_sizes_the_window_to_the_texture_one_to_one() {
    let x = Xvfb::start();
    let dir = tempfile::tempdir().expect("tempdir");
    let png = dir.path().join("native.png");
    // Only 0 and 255, which any colour transfer keeps, in a pattern that any
    // scaling or shift by a pixel would break.
    let on = |b: bool| if b { 255 } else { 0 };
    let source = image::RgbaImage::from_fn(200, 120, |x, y| {
        image::Rgba([
            on((x * 7 + y * 3) % 5 < 2),
            on(x % 2 == 0),
            on((x / 3 + y) % 2 == 0),
            255,
        ])
    });
    source.save(&png).expect("png");
    let mut p = spreadlight_graph::Patch::default();
    p.add(
        spreadlight_graph::NodeDoc::new(1, "FileTexture")
            .with("Filename", vec!["native.png".to_owned()]),
    );
    p.add(spreadlight_graph::NodeDoc::new(2, "Output").with("Write", vec![false]));
    p.link(1, "Texture", 2, "Texture");
    let patch = dir.path().join("native.ron");
    spreadlight_graph::format::save(&p, &patch).expect("save");
    let shot = dir.path().join("shot.png");
    let out = x
        .spreadlight(dir.path())
        .arg("play")
        .arg(&patch)
        .args(["--size", "320x180", "--native", "--measure-frames", "5"])
        .arg("--screenshot")
        .arg(&shot)
        .output()
        .expect("play runs");
    assert!(
        out.status.success(),
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    let image = image::open(&shot).expect("a PNG").to_rgba8();
    assert_eq!(image.dimensions(), (200, 120), "the texture's own size");
    // 1:1: each pixel comes back.
    let off = image
        .pixels()
        .zip(source.pixels())
        .filter(|(a, b)| (0..3).any(|c| a[c].abs_diff(b[c]) > 2))
        .count();
    assert_eq!(
        off,
        0,
        "pixels that differ from the image, e.g. at (10, 10) {:?} for {:?}, at (150, 100) {:?} for {:?}",
        image.get_pixel(10, 10),
        source.get_pixel(10, 10),
        image.get_pixel(150, 100),
        source.get_pixel(150, 100)
    );

    // Not native: the window keeps its size and shows the image in it. The
    // screenshot waited for the image to be the viewport's size, which an
    // image file's never is, until its 300 s timeout: thousands of frames.
    let out = x
        .spreadlight(dir.path())
        .arg("play")
        .arg(&patch)
        .args(["--size", "320x180", "--measure-frames", "5"])
        .arg("--screenshot")
        .arg(&shot)
        .output()
        .expect("play runs");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{stdout}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(
        image::image_dimensions(&shot).expect("a PNG"),
        (320, 180),
        "the window's size"
    );
    let frames: u64 = stdout
        .split("\"frames\": ")
        .nth(1)
        .and_then(|rest| rest.split(',').next())
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("no frame count in {stdout}"));
    assert!(
        frames < 500,
        "{frames} frames before the screenshot: {stdout}"
    );
}

/// A source shader that fills its target with one colour.
fn fill_shader(rgb: &str) -> String {
    format!(
        "// @target shown temporary rgba16float scale=1
// @pass fill -> shown
@group(0) @binding(0) var shown: texture_storage_2d<rgba16float, write>;
@compute @workgroup_size(8, 8)
fn fill(@builtin(global_invocation_id) id: vec3<u32>) {{
    let size = textureDimensions(shown);
    if (id.x >= size.x || id.y >= size.y) {{ return; }}
    textureStore(shown, id.xy, vec4<f32>({rgb}, 1.0));
}}
"
    )
}

/// `spreadlight play` reloads a shader file saved while the show runs, as the
/// editor does: the window turns from the file's red to its green.
#[test]
fn play_shows_a_shader_file_saved_while_it_runs() {
    let x = Xvfb::start();
    let dir = tempfile::tempdir().expect("tempdir");
    let shaders = dir.path().join("shaders");
    std::fs::create_dir_all(&shaders).expect("mkdir");
    let file = shaders.join("fill.wgsl");
    std::fs::write(&file, fill_shader("1.0, 0.0, 0.0")).expect("write");
    let mut p = spreadlight_graph::Patch::default();
    p.add(spreadlight_graph::NodeDoc::new(1, "Fill (Shader)"));
    p.add(spreadlight_graph::NodeDoc::new(2, "Output").with("Write", vec![false]));
    p.link(1, "Texture", 2, "Texture");
    let patch = dir.path().join("fill.ron");
    spreadlight_graph::format::save(&p, &patch).expect("save");
    let log = dir.path().join("play-stderr.txt");
    let mut play = x
        .spreadlight(&dir.path().join("config"))
        .arg("play")
        .arg(&patch)
        .args(["--size", "160x90"])
        .stdout(Stdio::null())
        .stderr(std::fs::File::create(&log).expect("the log"))
        .spawn()
        .expect("play starts");
    let input = Input::connect(&x);
    wait_until(&input, &log, "the show window", &|| {
        input.shown_window(160, 90).is_some()
    });
    let window = input.shown_window(160, 90).expect("the show window");
    let (wx, wy, w, h) = input.geometry(window);
    // The middle pixel as (r, g, b): the screen is 24-bit, 4 bytes a pixel, BGRX.
    let middle = || {
        let d = input.region(wx + w / 2, wy + h / 2, 1, 1);
        (d[2], d[1], d[0])
    };
    wait_until(&input, &log, "the file's red", &|| middle() == (255, 0, 0));
    // A different length, so the change shows within the file system's time resolution.
    std::fs::write(&file, fill_shader("0.0, 1.0, 0.0") + "// saved again\n").expect("write");
    wait_until(&input, &log, "the saved file's green", &|| {
        middle() == (0, 255, 0)
    });
    assert_eq!(
        play.try_wait().expect("status"),
        None,
        "play still runs; it printed: {}",
        std::fs::read_to_string(&log).unwrap_or_default()
    );
    play.kill().expect("SIGKILL");
    play.wait().expect("reaped");
}

/// The ffmpeg command (or ffprobe) on `args`; its standard output. CI installs both.
fn ff(program: &str, args: &[&str]) -> String {
    let out = std::process::Command::new(program)
        .args(args)
        .output()
        .unwrap_or_else(|e| panic!("{program}: {e}"));
    assert!(
        out.status.success(),
        "{program} {args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

fn mean_difference(a: &image::RgbaImage, b: &image::RgbaImage) -> f64 {
    assert_eq!(a.dimensions(), b.dimensions());
    let sum: u64 = a
        .pixels()
        .zip(b.pixels())
        .map(|(p, q)| (0..3).map(|c| u64::from(p[c].abs_diff(q[c]))).sum::<u64>())
        .sum();
    sum as f64 / (f64::from(a.width() * a.height()) * 3.0)
}

/// `play --record` (issue 37): 3 seconds at 30 fps on the fixed clock make
/// a file of 90 frames (ffprobe counts them), each the patch's render of
/// that frame (frame 45 decoded back is closest to `spreadlight render`'s
/// frame of the same clock), with the sound of the patch's AudioFile muxed in.
#[test]
fn play_records_three_seconds_frame_for_frame_with_the_audio_files_sound() {
    let x = Xvfb::start();
    let dir = tempfile::tempdir().expect("tempdir");
    let d = |name: &str| dir.path().join(name).to_string_lossy().into_owned();
    ff(
        "ffmpeg",
        &[
            "-hide_banner",
            "-loglevel",
            "error",
            "-y",
            "-f",
            "lavfi",
            "-i",
            "sine=frequency=440:duration=4",
            &d("tone.wav"),
        ],
    );
    let video = root().join("patches/assets/testsrc-64x36.mp4");
    let mut p = spreadlight_graph::Patch::default();
    p.add(
        spreadlight_graph::NodeDoc::new(1, "VideoFile")
            .with("Filename", vec![video.to_string_lossy().into_owned()]),
    );
    p.add(spreadlight_graph::NodeDoc::new(2, "Output").with("Write", vec![false]));
    p.link(1, "Texture", 2, "Texture");
    p.add(
        spreadlight_graph::NodeDoc::new(3, "AudioFile")
            .with("Filename", vec!["tone.wav".to_owned()]),
    );
    let patch = dir.path().join("recorded.ron");
    spreadlight_graph::format::save(&p, &patch).expect("save");
    let recording = dir.path().join("out.mp4");
    let out = x
        .spreadlight(&dir.path().join("config"))
        .arg("play")
        .arg(&patch)
        .args([
            "--size",
            "64x36",
            "--fps",
            "30",
            "--measure-frames",
            "90",
            "--record",
        ])
        .arg(&recording)
        .output()
        .expect("play runs");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{stdout}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    // The run's report: its first JSON line (the window may draw once more
    // while it closes, and report again with the recording gone).
    let report: serde_json::Value = stdout
        .lines()
        .find_map(|l| serde_json::from_str(l).ok())
        .unwrap_or_else(|| panic!("no JSON report: {stdout}"));
    assert_eq!(report["recording_error"], "", "{report}");
    assert_eq!(report["recorded_frames"], 90, "{report}");
    assert_eq!(report["recording_dropped"], 0, "{report}");
    let first = report["recording_first_frame"]
        .as_u64()
        .expect("a first frame");
    let rec = recording.to_string_lossy().into_owned();
    let streams = ff(
        "ffprobe",
        &[
            "-v",
            "error",
            "-count_frames",
            "-show_entries",
            "stream=codec_type,width,height,nb_read_frames",
            "-of",
            "csv=p=0",
            &rec,
        ],
    );
    let lines: Vec<&str> = streams.lines().map(str::trim).collect();
    assert_eq!(lines.len(), 2, "{streams}");
    assert_eq!(lines[0], "video,64,36,90", "{streams}");
    assert!(lines[1].starts_with("audio"), "{streams}");
    // Recorded frame 45 against the render of the patch frame it was: closer
    // to it than to the renders of the frames beside it.
    let recorded = dir.path().join("recorded-45.png");
    ff(
        "ffmpeg",
        &[
            "-hide_banner",
            "-loglevel",
            "error",
            "-y",
            "-i",
            &rec,
            "-vf",
            "select=eq(n\\,45)",
            "-frames:v",
            "1",
            &recorded.to_string_lossy(),
        ],
    );
    let recorded = image::open(&recorded).expect("png").to_rgba8();
    let rendered = |frame: u64| {
        let png = dir.path().join(format!("render-{frame}.png"));
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_spreadlight"))
            .arg("render")
            .arg(&patch)
            .args([
                "--size",
                "64x36",
                "--fps",
                "30",
                "--allow-unknown",
                "--frames",
            ])
            .arg(frame.to_string())
            .arg("-o")
            .arg(&png)
            .output()
            .expect("render runs");
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        image::open(&png).expect("png").to_rgba8()
    };
    let at = first + 45;
    let same = mean_difference(&recorded, &rendered(at));
    assert!(
        same < 6.0,
        "recorded frame 45 differs from patch frame {at} by {same}"
    );
    // Small frames of colour bars lose their chroma edges to 4:2:0 and
    // H.264 alike, so the difference is never 0; what tells the frames apart
    // is that the right one is the closest.
    for other in [at - 3, at + 3] {
        let differs = mean_difference(&recorded, &rendered(other));
        assert!(
            differs > same,
            "frame {other}: {differs}, frame {at}: {same}"
        );
    }
}
