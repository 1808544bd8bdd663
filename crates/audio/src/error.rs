//! What can go wrong with audio: a file that cannot be read or decoded, a
//! machine without an input device. Messages name the file or the device.

use std::path::PathBuf;

use thiserror::Error;

#[derive(Debug, Error)]
pub enum AudioError {
    #[error("{}: cannot open: {source}", path.display())]
    Open {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("{}: not an audio file this build reads (WAV, FLAC, MP3, Ogg Vorbis): {message}", path.display())]
    Format { path: PathBuf, message: String },
    #[error("{}: cannot decode: {message}", path.display())]
    Decode { path: PathBuf, message: String },
    #[error(
        "{}: truncated: its header promises {expected} sample frames, the file holds {got}",
        path.display()
    )]
    Truncated {
        path: PathBuf,
        expected: u64,
        got: u64,
    },
    #[error("{}: holds no audio", path.display())]
    Empty { path: PathBuf },
    /// No input device, or none that opens: CI machines and servers have no sound card.
    #[error("no audio device: {0}")]
    NoDevice(String),
}
