//! Media nodes: video files as textures (`VideoFile`, category "Texture"),
//! and (category "Media") sound from a file or a live input as an `Audio`
//! handle, the analyses that take it (level, spectrum bands, onsets and
//! tempo, envelopes), and MIDI in and out. The decoding, analysis and ports
//! live in `spreadlight-video`, `spreadlight-audio` and `spreadlight-midi`;
//! these files are the pins around them. docs/media.md describes them for users.

pub mod audio_file;
pub mod audio_in;
pub mod beat;
pub mod envelope;
pub mod level;
pub mod midi_in;
pub mod midi_out;
pub mod spectrum;
pub mod video_file;

use std::sync::Arc;

use spreadlight_audio::AudioWindow;
use spreadlight_graph::{EvalContext, In, NodeError, Out, Pins, Registry, Res, ResourceKind};

pub(crate) const CATEGORY: &str = "Media";

/// How media nodes keep up with the clock, a service hosts provide. Live
/// hosts (`spreadlight play`, the editor) provide [`Playback::Live`]: media
/// nodes then decode ahead on a thread and show the last frame rather than
/// wait for a late one. Without it, or with [`Playback::Exact`] (`render`,
/// `eval`, a farm, `play --fps`), every frame is exact: the node waits for
/// the frame the clock asks for.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Playback {
    #[default]
    Exact,
    Live,
}

pub fn register(r: &mut Registry) {
    video_file::register(r);
    audio_file::register(r);
    audio_in::register(r);
    level::register(r);
    spectrum::register(r);
    beat::register(r);
    envelope::register(r);
    midi_in::register(r);
    midi_out::register(r);
}

/// A pin of sound (empty by default), the analysis nodes' first.
pub(crate) fn audio_input(p: &mut Pins<'_>) -> In<Res<AudioWindow>> {
    p.input_resource::<AudioWindow>("Audio", ResourceKind::Audio)
}

/// The sound output of the sources.
pub(crate) fn audio_output(p: &mut Pins<'_>) -> Out<Res<AudioWindow>> {
    p.output_resource::<AudioWindow>("Audio", ResourceKind::Audio)
}

/// The sound on `pin`, one window per slice.
pub(crate) fn audio(
    cx: &EvalContext<'_>,
    pin: In<Res<AudioWindow>>,
) -> Result<Vec<Arc<AudioWindow>>, NodeError> {
    cx.resources(pin)
}

/// Output one window.
pub(crate) fn put_audio(cx: &mut EvalContext<'_>, pin: Out<Res<AudioWindow>>, window: AudioWindow) {
    cx.put_resources(pin, vec![Arc::new(window)]);
}

#[cfg(test)]
mod tests;
