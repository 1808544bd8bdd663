//! What can go wrong with a media file: every error names the file.

use std::path::PathBuf;

use thiserror::Error;

#[derive(Debug, Clone, PartialEq, Error)]
pub enum MediaError {
    #[error("cannot set up FFmpeg: {0}")]
    Init(String),
    #[error("{}: no such file", .0.display())]
    Missing(PathBuf),
    #[error("{}: not a video FFmpeg can read ({message})", path.display())]
    Open { path: PathBuf, message: String },
    #[error("{}: has no video stream", .0.display())]
    NoVideo(PathBuf),
    #[error("{}: cannot decode frame {frame} ({message})", path.display())]
    Decode {
        path: PathBuf,
        frame: u64,
        message: String,
    },
    #[error("{}: no files match the pattern (frames are numbered where the #s stand)", .0.display())]
    EmptySequence(PathBuf),
    #[error("{}: {message}", path.display())]
    Image { path: PathBuf, message: String },
    #[error("{}: cannot record ({message})", path.display())]
    Encode { path: PathBuf, message: String },
}
