//! A video file through FFmpeg: open, seek, decode to RGBA.
//!
//! Frames are numbered by their presentation time at the stream's average
//! frame rate. Asking for a frame a little ahead of the last one decodes
//! forward; anything else seeks to the key frame before it and decodes
//! forward from there, so every answer is the same frame whichever frame was
//! asked for before (a farm chunk starting mid-file sees what a full run sees).

use std::path::{Path, PathBuf};
use std::sync::Arc;

use ffmpeg::format::Pixel;
use ffmpeg::software::scaling;
use ffmpeg::util::frame::Video as AvFrame;
use ffmpeg_next as ffmpeg;

use crate::error::MediaError;
use crate::frame::{Frame, VideoInfo};

/// How far ahead of the last decoded frame a request still decodes forward
/// rather than seeking: about a GOP of common encodes.
const FORWARD_FRAMES: u64 = 48;

pub struct VideoDecoder {
    path: PathBuf,
    input: ffmpeg::format::context::Input,
    stream: usize,
    decoder: ffmpeg::decoder::Video,
    info: VideoInfo,
    /// Seconds per unit of the stream's timestamps, and its first timestamp.
    time_base: f64,
    start: i64,
    /// The last frame decoded (converted or not), and its number.
    current: Option<(u64, AvFrame)>,
    /// The RGBA of `current`, once converted.
    converted: Option<Arc<Frame>>,
    /// The decoder has given its last frame.
    ended: bool,
}

impl VideoDecoder {
    pub fn open(path: &Path) -> Result<Self, MediaError> {
        crate::init()?;
        if !path.exists() {
            return Err(MediaError::Missing(path.to_path_buf()));
        }
        let open_error = |e: ffmpeg::Error| MediaError::Open {
            path: path.to_path_buf(),
            message: e.to_string(),
        };
        let input = ffmpeg::format::input(&path).map_err(open_error)?;
        let stream = input
            .streams()
            .best(ffmpeg::media::Type::Video)
            .ok_or_else(|| MediaError::NoVideo(path.to_path_buf()))?;
        let index = stream.index();
        let tb = stream.time_base();
        let time_base = f64::from(tb);
        let rate = [stream.avg_frame_rate(), stream.rate()]
            .into_iter()
            .map(f64::from)
            .find(|r| r.is_finite() && *r > 0.0)
            .ok_or_else(|| MediaError::Open {
                path: path.to_path_buf(),
                message: "the video stream has no frame rate".to_owned(),
            })?;
        let start = if stream.start_time() == ffmpeg::ffi::AV_NOPTS_VALUE {
            0
        } else {
            stream.start_time()
        };
        let seconds = if stream.duration() > 0 {
            stream.duration() as f64 * time_base
        } else {
            input.duration().max(0) as f64 / f64::from(ffmpeg::ffi::AV_TIME_BASE)
        };
        let frames = if stream.frames() > 0 {
            stream.frames() as u64
        } else {
            (seconds * rate).round().max(1.0) as u64
        };
        let mut context = ffmpeg::codec::context::Context::from_parameters(stream.parameters())
            .map_err(open_error)?;
        // Frame threads, as many as FFmpeg sees cores: 1080p H.264 decodes
        // about half again as fast on two cores (docs/media.md).
        context.set_threading(ffmpeg::codec::threading::Config {
            kind: ffmpeg::codec::threading::Type::Frame,
            count: 0,
            ..Default::default()
        });
        let decoder = context.decoder().video().map_err(open_error)?;
        let info = VideoInfo {
            width: decoder.width(),
            height: decoder.height(),
            fps: rate,
            frames,
        };
        if info.width == 0 || info.height == 0 {
            return Err(MediaError::Open {
                path: path.to_path_buf(),
                message: "the video stream has no picture size".to_owned(),
            });
        }
        Ok(VideoDecoder {
            path: path.to_path_buf(),
            input,
            stream: index,
            decoder,
            info,
            time_base,
            start,
            current: None,
            converted: None,
            ended: false,
        })
    }

    pub fn info(&self) -> VideoInfo {
        self.info
    }

    /// Frame `index` (or the last one decodable before it, at the end of a
    /// file whose length was estimated).
    pub fn frame(&mut self, index: u64) -> Result<Arc<Frame>, MediaError> {
        let index = index.min(self.info.frames.saturating_sub(1));
        let ahead = self
            .current
            .as_ref()
            .is_some_and(|(at, _)| *at <= index && index - *at <= FORWARD_FRAMES);
        if !ahead {
            self.seek(index)?;
        }
        self.decode_until(index)?;
        // A seek that landed past the frame (a stream whose key frames the
        // index misplaces): start again from the beginning, the one sure place.
        if self.current.as_ref().is_some_and(|(at, _)| *at > index) && index > 0 {
            self.seek(0)?;
            self.decode_until(index)?;
        }
        self.convert()
    }

    fn seek(&mut self, index: u64) -> Result<(), MediaError> {
        let seconds = index as f64 / self.info.fps;
        let target = (seconds * f64::from(ffmpeg::ffi::AV_TIME_BASE)) as i64
            + (self.start as f64 * self.time_base * f64::from(ffmpeg::ffi::AV_TIME_BASE)) as i64;
        self.input
            .seek(target, ..target)
            .map_err(|e| self.error(index, e))?;
        self.decoder.flush();
        self.current = None;
        self.converted = None;
        self.ended = false;
        Ok(())
    }

    /// Decode until the current frame is `index` or past it, or the file ends.
    fn decode_until(&mut self, index: u64) -> Result<(), MediaError> {
        while self.current.as_ref().is_none_or(|(at, _)| *at < index) && !self.ended {
            let mut frame = AvFrame::empty();
            match self.decoder.receive_frame(&mut frame) {
                Ok(()) => {
                    let pts = frame.timestamp().or(frame.pts()).unwrap_or(self.start);
                    let at = ((pts - self.start) as f64 * self.time_base * self.info.fps + 1e-6)
                        .floor()
                        .max(0.0) as u64;
                    self.current = Some((at, frame));
                    self.converted = None;
                }
                Err(ffmpeg::Error::Eof) => self.ended = true,
                Err(ffmpeg::Error::Other { errno }) if errno == ffmpeg::util::error::EAGAIN => {
                    self.feed(index)?
                }
                Err(e) => return Err(self.error(index, e)),
            }
        }
        if self.current.is_none() {
            return Err(self.error(index, "the file has no decodable frame there"));
        }
        Ok(())
    }

    /// Hand the decoder the next packet of the video stream (or the end).
    fn feed(&mut self, index: u64) -> Result<(), MediaError> {
        let mut packet = ffmpeg::Packet::empty();
        loop {
            match packet.read(&mut self.input) {
                Ok(()) if packet.stream() == self.stream => {
                    return match self.decoder.send_packet(&packet) {
                        // A damaged packet: skip it, as players do; a file of
                        // nothing but damage ends with "no decodable frame".
                        Ok(()) | Err(ffmpeg::Error::InvalidData) => Ok(()),
                        Err(e) => Err(self.error(index, e)),
                    };
                }
                Ok(()) => {}
                Err(ffmpeg::Error::Eof) => {
                    return self.decoder.send_eof().map_err(|e| self.error(index, e));
                }
                Err(e) => return Err(self.error(index, e)),
            }
        }
    }

    fn convert(&mut self) -> Result<Arc<Frame>, MediaError> {
        if let Some(frame) = &self.converted {
            return Ok(frame.clone());
        }
        let Some((index, frame)) = &self.current else {
            return Err(self.error(0, "no frame decoded"));
        };
        let (index, format, w, h) = (*index, frame.format(), frame.width(), frame.height());
        // A scaler per picture: FFmpeg's is not `Send`, and the decoder moves
        // to its decode-ahead thread; setting one up for a same-size
        // conversion costs little beside the conversion itself.
        let mut scaler =
            scaling::Context::get(format, w, h, Pixel::RGBA, w, h, scaling::Flags::BILINEAR)
                .map_err(|e| self.error(index, e))?;
        let mut rgba = AvFrame::empty();
        scaler
            .run(frame, &mut rgba)
            .map_err(|e| self.error(index, e))?;
        let stride = rgba.stride(0);
        let data = rgba.data(0);
        let row = w as usize * 4;
        let mut pixels = Vec::with_capacity(row * h as usize);
        for y in 0..h as usize {
            pixels.extend_from_slice(&data[y * stride..y * stride + row]);
        }
        let frame = Arc::new(Frame {
            index,
            width: w,
            height: h,
            rgba: pixels,
        });
        self.converted = Some(frame.clone());
        Ok(frame)
    }

    fn error(&self, frame: u64, e: impl ToString) -> MediaError {
        MediaError::Decode {
            path: self.path.clone(),
            frame,
            message: e.to_string(),
        }
    }
}
