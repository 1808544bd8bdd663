//! Spreadlight's audio: sound from a file or a live input as an [`AudioWindow`]
//! (the samples up to a moment), and the analyses the media nodes offer on
//! it: [`level`] (RMS and peak), [`spectrum`] (an FFT grouped into bands),
//! [`beat`] (onsets and tempo) and [`envelope`] (attack/release followers).
//!
//! Every analysis is a function of a window's samples alone, with no state
//! carried from frame to frame: what a frame shows depends only on where the
//! play head is, so an offline render is deterministic and a chunk of frames
//! equals the same frames of a full run. No GPU, no patch: the node library
//! (`crates/nodes/src/media/`) wraps these in nodes.

pub mod beat;
pub mod decode;
pub mod envelope;
pub mod error;
pub mod input;
pub mod level;
pub mod spectrum;
pub mod window;

pub use decode::{Clip, decode_file};
pub use error::AudioError;
pub use window::AudioWindow;

#[cfg(test)]
pub(crate) mod tones;
