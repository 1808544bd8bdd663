//! A source of frames: a video file or an image sequence, chosen by the name.

use std::path::Path;
use std::sync::Arc;

use crate::decoder::VideoDecoder;
use crate::error::MediaError;
use crate::frame::{Frame, VideoInfo};
use crate::sequence::ImageSequence;

pub enum Source {
    Video(Box<VideoDecoder>),
    Sequence(ImageSequence),
}

impl Source {
    /// Open `path`: an image sequence when its file name has `#`s (played at
    /// `sequence_fps`), otherwise a video file.
    pub fn open(path: &Path, sequence_fps: f64) -> Result<Source, MediaError> {
        if ImageSequence::is_pattern(path) {
            Ok(Source::Sequence(ImageSequence::open(path, sequence_fps)?))
        } else {
            Ok(Source::Video(Box::new(VideoDecoder::open(path)?)))
        }
    }

    pub fn info(&self) -> VideoInfo {
        match self {
            Source::Video(d) => d.info(),
            Source::Sequence(s) => s.info(),
        }
    }

    /// Frame `index`, clamped to the last.
    pub fn frame(&mut self, index: u64) -> Result<Arc<Frame>, MediaError> {
        match self {
            Source::Video(d) => d.frame(index),
            Source::Sequence(s) => s.frame(index),
        }
    }

    /// The frame shown at `time` seconds ([`VideoInfo::frame_at`]).
    pub fn frame_at(&mut self, time: f64, looping: bool) -> Result<Arc<Frame>, MediaError> {
        let index = self.info().frame_at(time, looping);
        self.frame(index)
    }
}
