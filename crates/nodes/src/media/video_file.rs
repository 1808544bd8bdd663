//! `VideoFile`: a video file or an image sequence as a texture, in step
//! with the patch clock.
//!
//! The frame shown is a function of the clock and the pins alone (the video
//! time is Seek + Speed × the patch time while Play is on, Seek while it is
//! off), so `render` and a farm chunk are frame-exact: frame N shows the
//! video frame at that time whichever frame a run started at. Live hosts
//! ([`super::Playback::Live`]) decode on a thread instead and count the frames
//! shown late. Decoding is in `spreadlight_video`.

use std::path::PathBuf;
use std::sync::Arc;
use std::time::SystemTime;

use spreadlight_graph::{EvalContext, In, Node, NodeDef, NodeError, Out, Registry, Res};
use spreadlight_render::TextureRef;
use spreadlight_render::static_texture::StaticTexture;
use spreadlight_render::texture::GpuTexture;
use spreadlight_video::{DecodeAhead, Frame, MediaError, Source, VideoInfo};

use super::Playback;
use crate::gpu::renderer;
use crate::post::texture_output;

pub fn register(r: &mut Registry) {
    r.add(
        NodeDef::new(
            "VideoFile",
            "Texture",
            "Plays a video file (H.264, ProRes, VP9, ... through FFmpeg) or an image sequence \
             (a file name with #s where the frame number stands: `frames/f_####.png`, PNG or EXR) \
             as a texture. The video time is Seek + Speed × the patch time while Play is on, and \
             Seek (seconds) while it is off; Loop wraps it around, otherwise the ends hold. In \
             `render` every frame is exact; live (play, editor) it decodes ahead on a thread and \
             shows the last frame when the decoder is late (Dropped counts those). The sound of \
             the file is not played. Duration in seconds, Frame is the frame shown, Decode ms the \
             average cost of a decoded frame.",
        )
        .time_dependent()
        .with_pins_node(|p| {
            let filename = p.input("Filename", String::new());
            let play = p.input("Play", true);
            let looping = p.input("Loop", true);
            let speed = p.input("Speed", 1.0f32);
            let seek = p.input("Seek", 0.0f32);
            let sequence_fps = p.input("Sequence FPS", 30.0f32);
            p.range(0.001, 1000.0);
            let pins = VideoPins {
                filename,
                play,
                looping,
                speed,
                seek,
                sequence_fps,
                srgb: p.input("sRGB", true),
                texture: texture_output(p, "Texture"),
                duration: p.output::<f32>("Duration"),
                frame: p.output::<i64>("Frame"),
                dropped: p.output::<i64>("Dropped"),
                decode_ms: p.output::<f32>("Decode ms"),
            };
            move || VideoFile {
                pins,
                opened: None,
                player: None,
                failed: None,
                uploaded: None,
                dropped: 0,
                exact_cost: (0, 0.0),
            }
        }),
    );
}

#[derive(Clone, Copy)]
struct VideoPins {
    filename: In<String>,
    play: In<bool>,
    looping: In<bool>,
    speed: In<f32>,
    seek: In<f32>,
    sequence_fps: In<f32>,
    srgb: In<bool>,
    texture: Out<Res<TextureRef>>,
    duration: Out<f32>,
    frame: Out<i64>,
    dropped: Out<i64>,
    decode_ms: Out<f32>,
}

/// How the file is being read: exactly on the evaluating thread, or ahead on one of its own.
enum Player {
    Exact(Box<Source>),
    Live(DecodeAhead),
}

/// What was opened: the file (and its modification time, so a replaced file
/// is opened again) and the sequence rate.
#[derive(Clone, Debug, PartialEq)]
struct Opened {
    path: PathBuf,
    modified: Option<SystemTime>,
    sequence_fps: f32,
    live: bool,
}

pub struct VideoFile {
    pins: VideoPins,
    opened: Option<Opened>,
    player: Option<Player>,
    /// Why the file could not be opened (kept so a bad file is not probed every frame).
    failed: Option<MediaError>,
    /// The frame uploaded last and its texture.
    uploaded: Option<(Arc<Frame>, TextureRef)>,
    dropped: i64,
    /// Decoding done on the evaluating thread: frames and seconds.
    exact_cost: (u64, f64),
}

impl VideoFile {
    fn open(&mut self, want: Opened, path: &std::path::Path) -> Result<VideoInfo, MediaError> {
        if self.opened.as_ref() != Some(&want) {
            self.player = None;
            self.uploaded = None;
            self.failed = None;
            self.dropped = 0;
            self.exact_cost = (0, 0.0);
            let live = want.live;
            self.opened = Some(want.clone());
            match Source::open(path, f64::from(want.sequence_fps)) {
                Ok(source) if live => self.player = Some(Player::Live(DecodeAhead::new(source))),
                Ok(source) => self.player = Some(Player::Exact(Box::new(source))),
                Err(e) => self.failed = Some(e),
            }
        }
        if let Some(e) = &self.failed {
            return Err(e.clone());
        }
        match &self.player {
            Some(Player::Exact(source)) => Ok(source.info()),
            Some(Player::Live(ahead)) => Ok(ahead.info()),
            None => Err(MediaError::Missing(path.to_path_buf())),
        }
    }
}

impl Node for VideoFile {
    fn evaluate(&mut self, cx: &mut EvalContext<'_>) -> Result<(), NodeError> {
        let pins = self.pins;
        let name = cx.get(pins.filename)?.first().cloned().unwrap_or_default();
        if name.is_empty() {
            self.opened = None;
            self.player = None;
            self.uploaded = None;
            cx.put_resources(pins.texture, Vec::new());
            return Ok(());
        }
        let play = cx.first(pins.play, true)?;
        let looping = cx.first(pins.looping, true)?;
        let speed = f64::from(cx.first(pins.speed, 1.0f32)?);
        let seek = f64::from(cx.first(pins.seek, 0.0f32)?);
        let sequence_fps = cx.first(pins.sequence_fps, 30.0f32)?.clamp(0.001, 1000.0);
        let srgb = cx.first(pins.srgb, true)?;
        let renderer = renderer(cx)?;
        let path = cx.resolve_path(&name);
        let want = Opened {
            modified: std::fs::metadata(&path).and_then(|m| m.modified()).ok(),
            path: path.clone(),
            sequence_fps,
            live: cx
                .service::<Playback>()
                .is_some_and(|p| *p == Playback::Live),
        };
        let info = self
            .open(want, &path)
            .map_err(|e| cx.error(pins.filename, e.to_string()))?;
        let time = if play {
            seek + speed * cx.clock.time
        } else {
            seek
        };
        let index = info.frame_at(time, looping);
        let frame = match &mut self.player {
            Some(Player::Exact(_))
                if self
                    .uploaded
                    .as_ref()
                    .is_some_and(|(f, _)| f.index == index) =>
            {
                self.uploaded.as_ref().map(|(f, _)| f.clone())
            }
            Some(Player::Exact(source)) => {
                let started = std::time::Instant::now();
                let frame = source
                    .frame(index)
                    .map_err(|e| cx.error(pins.filename, e.to_string()))?;
                if self
                    .uploaded
                    .as_ref()
                    .is_none_or(|(f, _)| !Arc::ptr_eq(f, &frame))
                {
                    self.exact_cost.0 += 1;
                    self.exact_cost.1 += started.elapsed().as_secs_f64();
                }
                Some(frame)
            }
            Some(Player::Live(ahead)) => {
                let taken = ahead
                    .take(index, looping)
                    .map_err(|e| cx.error(pins.filename, e.to_string()))?;
                if taken.late {
                    self.dropped += 1;
                }
                taken.frame
            }
            None => None,
        };
        let (decoded, seconds) = match &self.player {
            Some(Player::Live(ahead)) => ahead.cost(),
            _ => self.exact_cost,
        };
        if let Some(frame) = frame {
            let fresh = self
                .uploaded
                .as_ref()
                .is_none_or(|(f, _)| !Arc::ptr_eq(f, &frame));
            if fresh {
                let texture = GpuTexture::frame_rgba8(
                    &renderer.gpu,
                    (frame.width, frame.height),
                    &frame.rgba,
                    srgb,
                    &name,
                );
                let texture = StaticTexture::new(texture).texture_ref();
                self.uploaded = Some((frame, texture));
            }
        }
        let textures: Vec<Arc<TextureRef>> = self
            .uploaded
            .as_ref()
            .map(|(_, t)| Arc::new(t.clone()))
            .into_iter()
            .collect();
        let shown = self.uploaded.as_ref().map_or(-1, |(f, _)| f.index as i64);
        cx.put_resources(pins.texture, textures);
        cx.put(pins.duration, vec![info.duration() as f32]);
        cx.put(pins.frame, vec![shown]);
        cx.put(pins.dropped, vec![self.dropped]);
        let ms = if decoded > 0 {
            seconds * 1e3 / decoded as f64
        } else {
            0.0
        };
        cx.put(pins.decode_ms, vec![ms as f32]);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use std::path::{Path, PathBuf};
    use std::sync::Arc;

    use spreadlight_graph::{
        FrameClock, NodeDoc, NodeId, NodeRun, Patch, PatchDir, Runtime, Spread,
    };

    use crate::media::Playback;

    /// A 64x36 H.264 clip of 2 seconds at 30 fps from the ffmpeg command (CI installs it).
    fn clip(dir: &Path) -> PathBuf {
        let path = dir.join("clip.mp4");
        let out = std::process::Command::new("ffmpeg")
            .args(["-hide_banner", "-loglevel", "error", "-y", "-f", "lavfi"])
            .args([
                "-i",
                "testsrc=size=64x36:rate=30:duration=2",
                "-c:v",
                "libx264",
            ])
            .args(["-g", "30", "-pix_fmt", "yuv420p"])
            .arg(&path)
            .output()
            .expect("the ffmpeg command");
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        path
    }

    /// VideoFile (#1) on `file` with `values`, its Frame probed when `probed`,
    /// beside an LFO (#3) probed too: the rest of the patch.
    fn runtime(dir: &Path, file: &str, values: &[(&str, Spread)], probed: bool) -> Runtime {
        let mut patch = Patch::default();
        let mut video = NodeDoc::new(1, "VideoFile").with("Filename", vec![file.to_owned()]);
        for (pin, value) in values {
            video.values.insert((*pin).into(), value.clone());
        }
        patch.add(video);
        patch.add(NodeDoc::new(3, "LFO"));
        patch.add(NodeDoc::new(4, "Probe"));
        patch.link(3, "Output", 4, "Input");
        if probed {
            patch.add(NodeDoc::new(2, "Probe"));
            patch.link(1, "Frame", 2, "Input");
        }
        let mut runtime = Runtime::new(crate::registry());
        crate::gpu::provide_renderer(&mut runtime, spreadlight_render::renderer::test_renderer());
        runtime.provide(Arc::new(PatchDir(dir.to_path_buf())));
        assert!(runtime.load(&patch).is_empty());
        runtime
    }

    fn ints(runtime: &Runtime, pin: &str) -> Vec<i64> {
        match runtime.output(NodeId(1), pin).map(|s| (**s).clone()) {
            Some(Spread::Int(v)) => v,
            other => panic!("{pin}: {other:?}"),
        }
    }

    #[test]
    fn the_frame_shown_is_the_clocks_exactly_from_any_start() {
        let dir = tempfile::tempdir().expect("tempdir");
        clip(dir.path());
        let mut full = runtime(dir.path(), "clip.mp4", &[], true);
        let frames: Vec<i64> = (0..6)
            .map(|n| {
                full.evaluate(FrameClock::fixed(n, 30.0));
                ints(&full, "Frame")[0]
            })
            .collect();
        assert_eq!(frames, [0, 1, 2, 3, 4, 5]);
        assert!(full.node_errors().next().is_none());
        match full.output(NodeId(1), "Duration").map(|s| (**s).clone()) {
            Some(Spread::Float(d)) => assert!((d[0] - 2.0).abs() < 1e-6, "{d:?}"),
            other => panic!("{other:?}"),
        }
        // Twice as fast from half a second, looping: 2.1 s of video is frame 3.
        let fast = [
            ("Speed", Spread::Float(vec![2.0])),
            ("Seek", Spread::Float(vec![0.5])),
        ];
        let mut chunk = runtime(dir.path(), "clip.mp4", &fast, true);
        for (n, want) in [(4u64, 23i64), (24, 3), (2, 19)] {
            chunk.evaluate(FrameClock::fixed(n, 30.0));
            assert_eq!(ints(&chunk, "Frame"), [want], "frame {n}");
        }
        let paused = [
            ("Play", Spread::Bool(vec![false])),
            ("Seek", Spread::Float(vec![1.0])),
        ];
        let mut still = runtime(dir.path(), "clip.mp4", &paused, true);
        still.evaluate(FrameClock::fixed(17, 30.0));
        assert_eq!(ints(&still, "Frame"), [30]);
    }

    #[test]
    fn live_playback_decodes_ahead_and_counts_the_frames_it_showed_late() {
        let dir = tempfile::tempdir().expect("tempdir");
        clip(dir.path());
        let mut live = runtime(dir.path(), "clip.mp4", &[], true);
        live.provide(Arc::new(Playback::Live));
        let waited = std::time::Instant::now();
        loop {
            live.evaluate(FrameClock::fixed(0, 30.0));
            assert!(live.node_errors().next().is_none());
            if ints(&live, "Frame") == [0] {
                break;
            }
            // Nothing decoded yet: no frame to show, and the patch went on.
            assert_eq!(ints(&live, "Frame"), [-1]);
            assert!(waited.elapsed().as_secs() < 60, "no frame within a minute");
            std::thread::sleep(std::time::Duration::from_millis(5));
        }
        assert!(
            ints(&live, "Dropped")[0] >= 1,
            "the first frame is always late"
        );
    }

    #[test]
    fn bad_files_are_errors_naming_them_and_unneeded_ones_are_never_opened() {
        let dir = tempfile::tempdir().expect("tempdir");
        let good = std::fs::read(clip(dir.path())).expect("read");
        std::fs::write(dir.path().join("truncated.mp4"), &good[..good.len() / 3]).expect("write");
        std::fs::write(dir.path().join("garbage.mp4"), vec![0x5a; 2048]).expect("write");
        for file in ["truncated.mp4", "garbage.mp4", "missing.mp4"] {
            let mut runtime = runtime(dir.path(), file, &[], true);
            runtime.evaluate(FrameClock::default());
            let errors: Vec<(NodeId, String)> = runtime
                .node_errors()
                .map(|(n, e)| (n, e.to_string()))
                .collect();
            assert_eq!(errors.len(), 1, "{errors:?}");
            assert_eq!(errors[0].0, NodeId(1));
            assert!(errors[0].1.contains(file), "{errors:?}");
            assert!(errors[0].1.contains("Filename"), "{errors:?}");
            // The rest of the patch keeps running.
            assert!(
                runtime
                    .output(NodeId(3), "Output")
                    .is_some_and(|s| s.len() == 1)
            );
            // Feeding no sink, the node does not run: the garbage is never opened.
            let mut unneeded = self::runtime(dir.path(), file, &[], false);
            unneeded.evaluate(FrameClock::default());
            assert!(unneeded.node_errors().next().is_none());
            let run = unneeded.stats().node(NodeId(1)).map(|n| n.run);
            assert_eq!(run, Some(NodeRun::Skipped));
        }
    }
}
