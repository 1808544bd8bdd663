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
use spreadlight_graph::{EvalContext, NodeError, PinType, Registry, ResourceKind, Spread};

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

/// The pin type of sound.
pub(crate) const AUDIO: PinType = PinType::Resource(ResourceKind::Audio);

/// An empty Audio spread: the default of an analysis node's input.
pub(crate) fn no_audio() -> Spread {
    Spread::Resource(ResourceKind::Audio, Vec::new())
}

/// The sound on input `pin`, one window per slice.
pub(crate) fn audio(cx: &EvalContext<'_>, pin: usize) -> Result<Vec<Arc<AudioWindow>>, NodeError> {
    crate::gpu::resources::<AudioWindow>(cx, pin)
}

/// One window as an Audio spread.
pub(crate) fn audio_spread(window: AudioWindow) -> Spread {
    crate::gpu::resource_spread(ResourceKind::Audio, vec![Arc::new(window)])
}

/// The first slice of a Float pin, or `default` when empty.
pub(crate) fn first_f32(cx: &EvalContext<'_>, pin: usize, default: f32) -> Result<f32, NodeError> {
    Ok(cx.slices::<f32>(pin)?.first().copied().unwrap_or(default))
}

/// The first slice of an Int pin, or `default` when empty.
pub(crate) fn first_i64(cx: &EvalContext<'_>, pin: usize, default: i64) -> Result<i64, NodeError> {
    Ok(cx.slices::<i64>(pin)?.first().copied().unwrap_or(default))
}

#[cfg(test)]
mod tests;
