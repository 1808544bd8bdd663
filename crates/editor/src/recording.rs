//! Recording what a viewport shows (the show window's, or the editor's
//! first) to a video file while the patch plays, on the worker's side.
//!
//! Each rendered frame of the viewport is read back and handed to
//! [`spreadlight_video::Recorder`], which encodes on its own thread. Frames
//! are numbered by the patch clock at the recording's rate, so a live
//! recording keeps real time (a frame the patch skipped is held by the
//! player) and a run on a fixed clock records every frame. Live, a full
//! encoder queue drops the frame and counts it (the show goes on); on a
//! fixed clock the worker waits for the encoder instead.

use std::path::PathBuf;

use spreadlight_graph::FrameClock;
use spreadlight_render::GpuContext;
use spreadlight_render::image_io::{Encoding, to_rgba8};
use spreadlight_video::{Pushed, Recorder, RecorderOptions};

/// Frames the encoder's queue holds before a live recording drops one.
const QUEUE: usize = 8;

/// How to record.
#[derive(Clone, Debug, PartialEq)]
pub struct RecordSettings {
    pub path: PathBuf,
    pub fps: f64,
    /// An audio file to mux in (a patch's `AudioFile`).
    pub audio: Option<PathBuf>,
    /// Wait for the encoder rather than drop frames (a fixed clock).
    pub wait: bool,
}

/// What the UI asks of the worker.
#[derive(Clone, Debug, PartialEq)]
pub enum RecordCommand {
    Start(RecordSettings),
    Stop,
}

/// Where a recording stands, for the status bar and `play`'s report.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RecordingStatus {
    pub path: PathBuf,
    pub recording: bool,
    pub frames: u64,
    pub dropped: u64,
    /// The patch frame of its first picture.
    pub first_frame: Option<u64>,
    pub audio: bool,
    pub error: Option<String>,
}

impl RecordingStatus {
    /// One line for people.
    pub fn describe(&self) -> String {
        let path = self.path.display();
        if let Some(e) = &self.error {
            return format!("recording failed: {e}");
        }
        let dropped = if self.dropped > 0 {
            format!(", {} dropped (the encoder fell behind)", self.dropped)
        } else {
            String::new()
        };
        let sound = if self.audio { " with sound" } else { "" };
        if self.recording {
            format!("⏺ recording {path}: {} frames{dropped}", self.frames)
        } else {
            format!("recorded {path}: {} frames{sound}{dropped}", self.frames)
        }
    }
}

/// A recording in progress (started at its first frame, when its size is known).
pub struct Recording {
    settings: RecordSettings,
    recorder: Option<Recorder>,
    size: (u32, u32),
    start: f64,
    pub status: RecordingStatus,
}

impl Recording {
    pub fn new(settings: RecordSettings) -> Self {
        Recording {
            status: RecordingStatus {
                path: settings.path.clone(),
                recording: true,
                ..Default::default()
            },
            settings,
            recorder: None,
            size: (0, 0),
            start: 0.0,
        }
    }

    /// Record the viewport's texture as of `clock`.
    pub fn capture(&mut self, gpu: &GpuContext, texture: &wgpu::Texture, clock: FrameClock) {
        if self.status.error.is_some() {
            return;
        }
        if let Err(e) = self.try_capture(gpu, texture, clock) {
            self.status.error = Some(e);
            self.status.recording = false;
            self.recorder = None;
        }
    }

    fn try_capture(
        &mut self,
        gpu: &GpuContext,
        texture: &wgpu::Texture,
        clock: FrameClock,
    ) -> Result<(), String> {
        let mut image =
            spreadlight_render::readback::read_texture(gpu, texture).map_err(|e| e.to_string())?;
        if self.recorder.is_none() {
            self.size = (image.width, image.height);
            self.start = clock.time;
            self.status.first_frame = Some(clock.frame);
            let recorder = Recorder::start(RecorderOptions {
                path: self.settings.path.clone(),
                width: image.width,
                height: image.height,
                fps: self.settings.fps,
                audio: self.settings.audio.clone(),
                queue: QUEUE,
            })
            .map_err(|e| e.to_string())?;
            self.recorder = Some(recorder);
        }
        if (image.width, image.height) != self.size {
            // The window was resized: the file keeps its first size.
            image = image.resized(self.size);
        }
        let number = ((clock.time - self.start) * self.settings.fps)
            .round()
            .max(0.0) as u64;
        let rgba = to_rgba8(&image, Encoding::Srgb);
        let Some(recorder) = &mut self.recorder else {
            return Ok(());
        };
        if self.settings.wait {
            recorder
                .push_wait(rgba, number)
                .map_err(|e| e.to_string())?;
            self.status.frames += 1;
        } else {
            match recorder.push(rgba, number).map_err(|e| e.to_string())? {
                Pushed::Queued => self.status.frames += 1,
                Pushed::Dropped => {
                    self.status.dropped += 1;
                    if self.status.dropped.is_power_of_two() {
                        eprintln!(
                            "warning: recording {}: the encoder is behind, {} frames dropped",
                            self.settings.path.display(),
                            self.status.dropped
                        );
                    }
                }
            }
        }
        Ok(())
    }

    /// Close the file; the final status.
    pub fn finish(mut self) -> RecordingStatus {
        self.status.recording = false;
        match self.recorder.take().map(Recorder::finish) {
            Some(Ok(summary)) => {
                self.status.frames = summary.frames;
                self.status.audio = summary.audio;
            }
            Some(Err(e)) => self.status.error = Some(e.to_string()),
            None if self.status.error.is_none() => {
                self.status.error = Some("nothing was rendered to record".to_owned())
            }
            None => {}
        }
        self.status
    }
}
