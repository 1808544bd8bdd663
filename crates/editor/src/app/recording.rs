//! Recording from the UI: the toolbar's ⏺ Record button and Ctrl+R (in the
//! editor and the show window) start and stop a recording of the first
//! viewport, which the worker encodes (`crate::recording`). The sound of the
//! patch's `AudioFile`, when it has one, goes into the file.

use std::time::{SystemTime, UNIX_EPOCH};

use super::*;
use crate::recording::{RecordCommand, RecordSettings, RecordingStatus};

/// The rate of a live recording: the editor's frames come at the display's pace.
const LIVE_FPS: f64 = 60.0;

impl EditorApp {
    /// Ctrl+R, in the editor and the show window.
    pub(super) fn recording_shortcut(&mut self, ctx: &egui::Context) {
        let ctrl_r = KeyboardShortcut::new(Modifiers::COMMAND, Key::R);
        if ctx.input_mut(|i| i.consume_shortcut(&ctrl_r)) {
            self.toggle_recording();
        }
    }

    /// The toolbar's button.
    pub(super) fn recording_button(&mut self, ui: &mut Ui) {
        let (label, hint) = match &self.recording {
            Some(path) => (
                "⏹ Stop recording",
                format!("recording {} (Ctrl+R)", path.display()),
            ),
            None => (
                "⏺ Record",
                "record the viewport to a video file beside the patch (Ctrl+R)".to_owned(),
            ),
        };
        if ui.button(label).on_hover_text(hint).clicked() {
            self.toggle_recording();
        }
    }

    pub(super) fn toggle_recording(&mut self) {
        if self.recording.is_some() {
            self.stop_recording();
        } else {
            let path = self
                .record_to
                .take()
                .unwrap_or_else(|| self.default_recording_path());
            self.start_recording(path);
        }
    }

    fn start_recording(&mut self, path: PathBuf) {
        let settings = RecordSettings {
            path: path.clone(),
            fps: self
                .transport
                .fixed_step
                .map_or(LIVE_FPS, |step| 1.0 / step),
            audio: self.audio_file(),
            wait: self.transport.fixed_step.is_some(),
        };
        self.worker.submit(Request {
            record: Some(RecordCommand::Start(settings)),
            ..Default::default()
        });
        self.status = format!("⏺ recording {}", path.display());
        if self.show_mode {
            eprintln!("{}", self.status);
        }
        self.recording = Some(path);
    }

    /// Stop the recording and wait for its file to be closed; its status.
    pub(super) fn stop_recording(&mut self) -> Option<RecordingStatus> {
        self.recording.take()?;
        let seq = self.worker.submit(Request {
            record: Some(RecordCommand::Stop),
            ..Default::default()
        });
        self.worker.wait(seq, FrameWait::Always);
        let status = self.worker.latest().and_then(|f| f.recording.clone());
        if let Some(status) = &status {
            self.status = status.describe();
            if self.show_mode {
                eprintln!("{}", self.status);
            }
        }
        status
    }

    /// `NAME-recording-SECONDS.mp4` beside the patch (in the config folder for an unsaved one).
    fn default_recording_path(&self) -> PathBuf {
        let dir = self
            .path
            .as_ref()
            .and_then(|p| p.parent())
            .map_or_else(|| self.options.config_dir.clone(), Path::to_path_buf);
        let stem = self.path.as_ref().and_then(|p| p.file_stem()).map_or_else(
            || "untitled".to_owned(),
            |s| s.to_string_lossy().into_owned(),
        );
        let seconds = SystemTime::now()
            .duration_since(UNIX_EPOCH)
            .map_or(0, |d| d.as_secs());
        dir.join(format!("{stem}-recording-{seconds}.mp4"))
    }

    /// The file of the patch's first `AudioFile` node, resolved beside the patch.
    fn audio_file(&self) -> Option<PathBuf> {
        let patch = self.doc.top();
        let node = patch.nodes.iter().find(|n| n.type_name == "AudioFile")?;
        let Some(Spread::String(names)) = self.doc.input_value(&self.registry, node.id, "Filename")
        else {
            return None;
        };
        let name = names.first().filter(|n| !n.is_empty())?;
        let path = Path::new(name);
        Some(match self.path.as_ref().and_then(|p| p.parent()) {
            Some(dir) if path.is_relative() => dir.join(path),
            _ => path.to_path_buf(),
        })
    }
}
