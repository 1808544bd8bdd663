//! `AudioFile`: a sound file (WAV, FLAC, MP3, Ogg Vorbis) played by the
//! patch clock. The file is decoded whole, once, the first time a sink
//! needs the node (nothing decodes for a node that feeds no sink); each
//! frame then only moves the play head and hands the analysis nodes a
//! window onto the decoded samples, without copying them.
//!
//! The play head follows the clock: with Play on it is Seek + Speed × time
//! from the clock's start, so frame N of `render` hears the sound at N/fps
//! whatever chunk it falls in. Changing Play, Speed or Seek while running
//! continues from where the head is (Seek jumps to its value).

use std::path::PathBuf;
use std::time::SystemTime;

use spreadlight_audio::{AudioWindow, Clip, decode_file};
use spreadlight_graph::{EvalContext, In, Node, NodeDef, NodeError, Out, Registry, Res};

use super::{CATEGORY, audio_output, put_audio};

pub fn register(r: &mut Registry) {
    r.add(
        NodeDef::new(
            "AudioFile",
            CATEGORY,
            "Plays a sound file (WAV, FLAC, MP3, Ogg Vorbis; a relative Filename is relative to \
             the patch's folder) by the patch clock, for the analysis nodes (Level, Spectrum, \
             Beat, Envelope). With Play on the position is Seek + Speed × time, so renders are \
             deterministic; Loop repeats it, else it falls silent at the end. Decoded whole, \
             mixed to mono, the first time a sink needs it. Nothing is played to speakers.",
        )
        .time_dependent()
        .with_pins_node(|p| {
            let pins = AudioFilePins {
                filename: p.input("Filename", String::new()),
                play: p.input("Play", true),
                looping: p.input("Loop", false),
                speed: p.input("Speed", 1.0f32),
                seek: p.input("Seek", 0.0f32),
                audio: audio_output(p),
                position: p.output::<f32>("Position"),
                duration: p.output::<f32>("Duration"),
                rate: p.output::<i64>("Sample Rate"),
            };
            move || AudioFile {
                pins,
                loaded: None,
                head: None,
            }
        }),
    );
}

#[derive(Clone, Copy)]
struct AudioFilePins {
    filename: In<String>,
    play: In<bool>,
    looping: In<bool>,
    speed: In<f32>,
    seek: In<f32>,
    audio: Out<Res<AudioWindow>>,
    position: Out<f32>,
    duration: Out<f32>,
    rate: Out<i64>,
}

/// Where the play head is, as a function of the clock and the pins.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Head {
    play: bool,
    speed: f64,
    seek: f64,
    /// The head was at `pos` when the clock read `time`.
    time: f64,
    pos: f64,
}

impl Head {
    fn at(&self, time: f64) -> f64 {
        if self.play {
            self.pos + self.speed * (time - self.time)
        } else {
            self.pos
        }
    }

    /// The head for this frame: from the clock's start at first (so a run
    /// that starts late, a render chunk, agrees with one from frame 0),
    /// re-anchored where pins change.
    fn next(previous: Option<Head>, play: bool, speed: f64, seek: f64, time: f64) -> Head {
        let start = Head {
            play,
            speed,
            seek,
            time: 0.0,
            pos: seek,
        };
        match previous {
            // A clock that went back (a restart) starts over.
            Some(p) if time < p.time => start,
            None => start,
            Some(p) if p.seek != seek => Head {
                time,
                pos: seek,
                ..start
            },
            Some(p) if p.play != play || p.speed != speed => Head {
                time,
                pos: p.at(time),
                ..start
            },
            Some(p) => p,
        }
    }
}

struct AudioFile {
    pins: AudioFilePins,
    /// The decoded file (or why it could not be), by path and modification time.
    loaded: Option<(PathBuf, Option<SystemTime>, Result<Clip, String>)>,
    head: Option<Head>,
}

impl AudioFile {
    /// The decoded file at `path`, decoding it again only when it changed on disk.
    fn clip(&mut self, cx: &EvalContext<'_>, name: &str) -> Result<&Clip, NodeError> {
        let path = cx.resolve_path(name);
        let modified = std::fs::metadata(&path).and_then(|m| m.modified()).ok();
        let stale = self
            .loaded
            .as_ref()
            .is_none_or(|(p, m, _)| *p != path || *m != modified);
        if stale {
            let decoded = decode_file(&path).map_err(|e| e.to_string());
            self.loaded = Some((path, modified, decoded));
        }
        match &self.loaded {
            Some((_, _, Ok(clip))) => Ok(clip),
            Some((_, _, Err(e))) => Err(cx.error(self.pins.filename, e.clone())),
            None => Err(cx.error(self.pins.filename, format!("{name}: not loaded"))),
        }
    }
}

impl Node for AudioFile {
    fn evaluate(&mut self, cx: &mut EvalContext<'_>) -> Result<(), NodeError> {
        let pins = self.pins;
        let name = cx.get(pins.filename)?.first().cloned().unwrap_or_default();
        let play = cx.first(pins.play, false)?;
        let looping = cx.first(pins.looping, false)?;
        let speed = f64::from(cx.first(pins.speed, 1.0)?);
        let seek = f64::from(cx.first(pins.seek, 0.0)?);
        if name.is_empty() {
            self.loaded = None;
            return Ok(());
        }
        let time = cx.clock.time;
        let head = Head::next(self.head, play, speed, seek, time);
        self.head = Some(head);
        let delta = cx.clock.delta;
        let clip = self.clip(cx, &name)?.clone();
        let rate = f64::from(clip.rate);
        let position = head.at(time);
        let end = (position * rate).round() as i64;
        // How far the head moved since the previous frame, from the clock alone.
        let step = if play {
            (speed * delta * rate).round() as i64
        } else {
            0
        };
        let duration = clip.duration();
        let shown = if looping && duration > 0.0 {
            position.rem_euclid(duration)
        } else {
            position.clamp(0.0, duration)
        };
        let window =
            AudioWindow::new(clip.samples.clone(), clip.rate, end, looping).with_step(step);
        put_audio(cx, pins.audio, window);
        cx.put(pins.position, vec![shown as f32]);
        cx.put(pins.duration, vec![duration as f32]);
        cx.put(pins.rate, vec![i64::from(clip.rate)]);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::Head;

    #[test]
    fn the_play_head_follows_the_clock_from_its_start_and_continues_across_pin_changes() {
        // A first evaluation late in the run (a render chunk) agrees with a run from 0.
        let late = Head::next(None, true, 2.0, 1.0, 10.0);
        assert_eq!(late.at(10.0), 21.0);
        // Pausing at 10 s holds the head; playing again continues from there.
        let paused = Head::next(Some(late), false, 2.0, 1.0, 10.0);
        assert_eq!(paused.at(12.0), 21.0);
        let resumed = Head::next(Some(paused), true, 2.0, 1.0, 12.0);
        assert_eq!(resumed.at(13.0), 23.0);
        // Half speed from 13 s.
        let slower = Head::next(Some(resumed), true, 0.5, 1.0, 13.0);
        assert_eq!(slower.at(15.0), 24.0);
        // Seek jumps.
        let sought = Head::next(Some(slower), true, 0.5, 3.0, 15.0);
        assert_eq!(sought.at(17.0), 4.0);
        // The clock restarting starts over.
        let restarted = Head::next(Some(sought), true, 0.5, 3.0, 0.0);
        assert_eq!(restarted.at(2.0), 4.0);
        assert_eq!(restarted.time, 0.0);
    }
}
