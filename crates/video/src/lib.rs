//! Spreadlight's video in and out, with no GPU and no patch: what the
//! `VideoFile` node and recording stand on.
//!
//! - [`Source`] opens a video file (through FFmpeg's libraries, whatever
//!   codec they decode: H.264, ProRes, VP9, ...) or an image sequence by
//!   pattern (`frames/f_####.png`, through the `image` crate) and gives the
//!   frame shown at a time, exactly: [`Source::frame_at`].
//! - [`DecodeAhead`] runs a source on its own thread for live playback: it
//!   decodes the frames after the one asked for, and the caller takes what
//!   is ready without waiting, counting the frames it had to show late.
//! - [`Recorder`] encodes RGBA frames to a video file on its own thread,
//!   handed over a bounded channel, and muxes an audio file in.

mod ahead;
mod decoder;
mod encoder;
mod error;
mod frame;
mod sequence;
mod source;

#[cfg(test)]
mod tests;

pub use ahead::{DecodeAhead, Taken};
pub use encoder::{Pushed, Recorder, RecorderOptions, RecordingSummary};
pub use error::MediaError;
pub use frame::{Frame, VideoInfo};
pub use sequence::ImageSequence;
pub use source::Source;

/// FFmpeg's libraries, set up once (registering codecs is idempotent but not free).
pub(crate) fn init() -> Result<(), MediaError> {
    static INIT: std::sync::OnceLock<Result<(), String>> = std::sync::OnceLock::new();
    INIT.get_or_init(|| {
        ffmpeg_next::init().map_err(|e| e.to_string())?;
        // FFmpeg prints warnings about every damaged packet to standard error;
        // the errors that matter come back as values and name the file.
        ffmpeg_next::util::log::set_level(ffmpeg_next::util::log::Level::Fatal);
        Ok(())
    })
    .clone()
    .map_err(MediaError::Init)
}
