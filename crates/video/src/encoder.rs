//! Recording: RGBA frames encoded to a video file (H.264 in MP4 or MKV) on
//! the encoder's own thread, with an audio file's sound muxed in.
//!
//! The caller hands frames over a bounded channel and never waits for the
//! encoder: when the channel is full, [`Recorder::push`] drops the frame and
//! says so ([`Pushed::Dropped`]), and the summary counts the drops, so an
//! encoder that falls behind is visible instead of slowing the show.
//! [`Recorder::push_wait`] waits instead, for runs on a fixed clock where
//! every frame must be in the file.

use std::path::{Path, PathBuf};
use std::sync::mpsc::{Receiver, SyncSender, TrySendError, sync_channel};
use std::thread::JoinHandle;

use ffmpeg::format::{Pixel, Sample, sample};
use ffmpeg::software::{resampling, scaling};
use ffmpeg::util::frame::{Audio as AvAudio, Video as AvFrame};
use ffmpeg::{ChannelLayout, Dictionary, Rational, codec, encoder, media};
use ffmpeg_next as ffmpeg;

use crate::error::MediaError;

#[derive(Clone, Debug)]
pub struct RecorderOptions {
    /// The file to write; its extension picks the container (`.mp4`, `.mkv`, `.mov`).
    pub path: PathBuf,
    pub width: u32,
    pub height: u32,
    pub fps: f64,
    /// An audio file to mux in (its first audio stream, encoded as AAC, cut
    /// to the video's length).
    pub audio: Option<PathBuf>,
    /// Frames the channel holds before [`Recorder::push`] drops one.
    pub queue: usize,
}

/// What [`Recorder::push`] did with a frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Pushed {
    Queued,
    /// The encoder is behind (the channel is full): the frame is not recorded.
    Dropped,
}

/// A finished recording.
#[derive(Clone, Debug, PartialEq)]
pub struct RecordingSummary {
    pub path: PathBuf,
    /// Frames in the file.
    pub frames: u64,
    /// Frames dropped because the encoder was behind.
    pub dropped: u64,
    /// Whether sound was muxed in.
    pub audio: bool,
}

struct Picture {
    rgba: Vec<u8>,
    /// Its frame number at the recording's rate.
    number: u64,
}

/// A recording in progress (finish it with [`Recorder::finish`]; dropping it
/// finishes it too, ignoring errors).
pub struct Recorder {
    options: RecorderOptions,
    sender: Option<SyncSender<Picture>>,
    thread: Option<JoinHandle<Result<(u64, bool), MediaError>>>,
    dropped: u64,
    last: Option<u64>,
}

impl Recorder {
    /// Open the file and the encoders (errors come back here, naming the
    /// file), then start the encoder thread.
    pub fn start(options: RecorderOptions) -> Result<Recorder, MediaError> {
        crate::init()?;
        let (sender, receiver) = sync_channel(options.queue.max(1));
        let (opened, opening) = sync_channel(1);
        let thread_options = options.clone();
        let thread = std::thread::Builder::new()
            .name("spreadlight recorder".to_owned())
            .spawn(move || {
                let encoding = Encoding::open(&thread_options);
                match encoding {
                    Ok(mut encoding) => {
                        let _ = opened.send(Ok(()));
                        encoding.run(&receiver)
                    }
                    Err(e) => {
                        let _ = opened.send(Err(e.clone()));
                        Err(e)
                    }
                }
            })
            .map_err(|e| encode_error(&options.path, e))?;
        match opening.recv() {
            Ok(Ok(())) => Ok(Recorder {
                options,
                sender: Some(sender),
                thread: Some(thread),
                dropped: 0,
                last: None,
            }),
            Ok(Err(e)) => Err(e),
            Err(_) => Err(encode_error(&options.path, "the encoder thread stopped")),
        }
    }

    pub fn options(&self) -> &RecorderOptions {
        &self.options
    }

    /// Frames dropped so far because the encoder was behind.
    pub fn dropped(&self) -> u64 {
        self.dropped
    }

    /// Hand over the picture of frame `number` (at the recording's rate; a
    /// number already recorded is skipped) without waiting. `rgba` is
    /// width × height × 4 bytes.
    pub fn push(&mut self, rgba: Vec<u8>, number: u64) -> Result<Pushed, MediaError> {
        if self.last.is_some_and(|last| number <= last) {
            return Ok(Pushed::Queued);
        }
        self.check(&rgba)?;
        let Some(sender) = &self.sender else {
            return Err(encode_error(
                &self.options.path,
                "the recording is finished",
            ));
        };
        match sender.try_send(Picture { rgba, number }) {
            Ok(()) => {
                self.last = Some(number);
                Ok(Pushed::Queued)
            }
            Err(TrySendError::Full(_)) => {
                self.dropped += 1;
                Ok(Pushed::Dropped)
            }
            Err(TrySendError::Disconnected(_)) => Err(self.stopped()),
        }
    }

    /// Like [`Recorder::push`], but wait while the encoder is behind.
    pub fn push_wait(&mut self, rgba: Vec<u8>, number: u64) -> Result<(), MediaError> {
        if self.last.is_some_and(|last| number <= last) {
            return Ok(());
        }
        self.check(&rgba)?;
        let Some(sender) = &self.sender else {
            return Err(encode_error(
                &self.options.path,
                "the recording is finished",
            ));
        };
        match sender.send(Picture { rgba, number }) {
            Ok(()) => {
                self.last = Some(number);
                Ok(())
            }
            Err(_) => Err(self.stopped()),
        }
    }

    /// Encode what is queued, mux the sound, close the file.
    pub fn finish(mut self) -> Result<RecordingSummary, MediaError> {
        self.close()
    }

    fn close(&mut self) -> Result<RecordingSummary, MediaError> {
        self.sender = None;
        let (frames, audio) = match self.thread.take() {
            Some(thread) => thread
                .join()
                .map_err(|_| encode_error(&self.options.path, "the encoder thread panicked"))??,
            None => {
                return Err(encode_error(
                    &self.options.path,
                    "the recording is finished",
                ));
            }
        };
        Ok(RecordingSummary {
            path: self.options.path.clone(),
            frames,
            dropped: self.dropped,
            audio,
        })
    }

    fn check(&self, rgba: &[u8]) -> Result<(), MediaError> {
        let want = self.options.width as usize * self.options.height as usize * 4;
        if rgba.len() == want {
            Ok(())
        } else {
            Err(encode_error(
                &self.options.path,
                format!(
                    "a frame of {} bytes, not {}x{} RGBA ({want} bytes)",
                    rgba.len(),
                    self.options.width,
                    self.options.height
                ),
            ))
        }
    }

    /// Why the thread stopped: its error.
    fn stopped(&mut self) -> MediaError {
        self.sender = None;
        match self.thread.take().map(|t| t.join()) {
            Some(Ok(Err(e))) => e,
            _ => encode_error(&self.options.path, "the encoder thread stopped"),
        }
    }
}

impl Drop for Recorder {
    fn drop(&mut self) {
        if self.thread.is_some() {
            let _ = self.close();
        }
    }
}

fn encode_error(path: &Path, e: impl ToString) -> MediaError {
    MediaError::Encode {
        path: path.to_path_buf(),
        message: e.to_string(),
    }
}

/// The encoder thread's side: the file, the video encoder, the sound.
struct Encoding {
    path: PathBuf,
    output: ffmpeg::format::context::Output,
    video: encoder::Video,
    scaler: scaling::Context,
    time_base: Rational,
    size: (u32, u32),
    sound: Option<Sound>,
    frames: u64,
    last_number: Option<u64>,
    fps: f64,
}

impl Encoding {
    fn open(options: &RecorderOptions) -> Result<Encoding, MediaError> {
        let path = &options.path;
        let fail = |e: ffmpeg::Error| encode_error(path, e);
        if options.width == 0 || options.height == 0 {
            return Err(encode_error(
                path,
                "a recording needs a picture of at least 1x1",
            ));
        }
        if !(options.fps.is_finite() && options.fps > 0.0) {
            return Err(encode_error(
                path,
                format!("frame rate {} is not positive", options.fps),
            ));
        }
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir).map_err(|e| encode_error(path, e))?;
        }
        let mut output = ffmpeg::format::output(path).map_err(fail)?;
        let global_header = output
            .format()
            .flags()
            .contains(ffmpeg::format::Flags::GLOBAL_HEADER);
        // x264 where the libraries have it (Debian's do); FFmpeg's own MPEG-4 part 2 otherwise.
        let codec = encoder::find_by_name("libx264")
            .or_else(|| encoder::find(codec::Id::H264))
            .or_else(|| encoder::find(codec::Id::MPEG4))
            .ok_or_else(|| encode_error(path, "FFmpeg has no H.264 or MPEG-4 encoder"))?;
        // 4:2:0 wants even sizes: the picture is scaled to the even size at or above it.
        let size = ((options.width + 1) & !1, (options.height + 1) & !1);
        let rate = Rational::from(options.fps).reduce();
        let time_base = rate.invert();
        let mut stream = output.add_stream(codec).map_err(fail)?;
        let mut video = codec::context::Context::new_with_codec(codec)
            .encoder()
            .video()
            .map_err(fail)?;
        video.set_width(size.0);
        video.set_height(size.1);
        video.set_format(Pixel::YUV420P);
        video.set_frame_rate(Some(rate));
        video.set_time_base(time_base);
        if global_header {
            video.set_flags(codec::Flags::GLOBAL_HEADER);
        }
        let mut settings = Dictionary::new();
        // Fast enough to keep up with a show on a laptop, visually lossless.
        settings.set("preset", "veryfast");
        settings.set("crf", "16");
        let video = video.open_with(settings).map_err(fail)?;
        stream.set_parameters(&video);
        stream.set_time_base(time_base);
        let scaler = scaling::Context::get(
            Pixel::RGBA,
            options.width,
            options.height,
            Pixel::YUV420P,
            size.0,
            size.1,
            scaling::Flags::BILINEAR,
        )
        .map_err(fail)?;
        let sound = match &options.audio {
            Some(audio) => Some(Sound::open(audio, &mut output, global_header)?),
            None => None,
        };
        output.write_header().map_err(fail)?;
        Ok(Encoding {
            path: path.clone(),
            output,
            video,
            scaler,
            time_base,
            size: (options.width, options.height),
            sound,
            frames: 0,
            last_number: None,
            fps: options.fps,
        })
    }

    /// Encode pictures until the channel closes, then the sound; the frame count and whether there was sound.
    fn run(&mut self, pictures: &Receiver<Picture>) -> Result<(u64, bool), MediaError> {
        let path = self.path.clone();
        let fail = |e: ffmpeg::Error| encode_error(&path, e);
        let mut first = None::<u64>;
        for picture in pictures {
            let start = *first.get_or_insert(picture.number);
            let mut rgba = AvFrame::new(Pixel::RGBA, self.size.0, self.size.1);
            let stride = rgba.stride(0);
            let row = self.size.0 as usize * 4;
            let data = rgba.data_mut(0);
            for (y, src) in picture.rgba.chunks_exact(row).enumerate() {
                data[y * stride..y * stride + row].copy_from_slice(src);
            }
            let mut yuv = AvFrame::empty();
            self.scaler.run(&rgba, &mut yuv).map_err(fail)?;
            let number = picture.number - start;
            yuv.set_pts(Some(number as i64));
            self.video.send_frame(&yuv).map_err(fail)?;
            self.frames += 1;
            self.last_number = Some(number);
            self.write_video_packets()?;
        }
        self.video.send_eof().map_err(fail)?;
        self.write_video_packets()?;
        let seconds = self.last_number.map_or(0.0, |n| (n + 1) as f64 / self.fps);
        let audio = match self.sound.take() {
            Some(mut sound) => {
                sound.encode(&mut self.output, seconds)?;
                true
            }
            None => false,
        };
        self.output.write_trailer().map_err(fail)?;
        Ok((self.frames, audio))
    }

    fn write_video_packets(&mut self) -> Result<(), MediaError> {
        let stream_tb = self
            .output
            .stream(0)
            .map(|s| s.time_base())
            .unwrap_or(self.time_base);
        let mut packet = ffmpeg::Packet::empty();
        while self.video.receive_packet(&mut packet).is_ok() {
            packet.set_stream(0);
            packet.rescale_ts(self.time_base, stream_tb);
            packet
                .write_interleaved(&mut self.output)
                .map_err(|e| encode_error(&self.path, e))?;
        }
        Ok(())
    }
}

/// An audio file on its way into the recording as AAC.
struct Sound {
    path: PathBuf,
    input: ffmpeg::format::context::Input,
    stream: usize,
    decoder: ffmpeg::decoder::Audio,
    encoder: encoder::Audio,
    out_stream: usize,
    rate: u32,
}

impl Sound {
    fn open(
        path: &Path,
        output: &mut ffmpeg::format::context::Output,
        global_header: bool,
    ) -> Result<Sound, MediaError> {
        if !path.exists() {
            return Err(MediaError::Missing(path.to_path_buf()));
        }
        let fail = |e: ffmpeg::Error| MediaError::Open {
            path: path.to_path_buf(),
            message: e.to_string(),
        };
        let input = ffmpeg::format::input(&path).map_err(fail)?;
        let stream = input
            .streams()
            .best(media::Type::Audio)
            .ok_or_else(|| MediaError::Open {
                path: path.to_path_buf(),
                message: "no audio stream".to_owned(),
            })?;
        let index = stream.index();
        let decoder = codec::context::Context::from_parameters(stream.parameters())
            .map_err(fail)?
            .decoder()
            .audio()
            .map_err(fail)?;
        let codec = encoder::find(codec::Id::AAC)
            .ok_or_else(|| encode_error(path, "FFmpeg has no AAC encoder"))?;
        let out_stream = output.add_stream(codec).map_err(fail)?.index();
        let mut encoder = codec::context::Context::new_with_codec(codec)
            .encoder()
            .audio()
            .map_err(fail)?;
        let rate = decoder.rate();
        encoder.set_rate(rate as i32);
        encoder.set_channel_layout(ChannelLayout::STEREO);
        encoder.set_channels(2);
        encoder.set_format(Sample::F32(sample::Type::Planar));
        encoder.set_bit_rate(192_000);
        encoder.set_time_base(Rational(1, rate as i32));
        if global_header {
            encoder.set_flags(codec::Flags::GLOBAL_HEADER);
        }
        let encoder = encoder.open_as(codec).map_err(fail)?;
        if let Some(mut out) = output.stream_mut(out_stream) {
            out.set_parameters(&encoder);
            out.set_time_base(Rational(1, rate as i32));
        }
        Ok(Sound {
            path: path.to_path_buf(),
            input,
            stream: index,
            decoder,
            encoder,
            out_stream,
            rate,
        })
    }

    /// Decode the file, convert to stereo float, encode the first `seconds` of it.
    fn encode(
        &mut self,
        output: &mut ffmpeg::format::context::Output,
        seconds: f64,
    ) -> Result<(), MediaError> {
        let path = self.path.clone();
        let fail = |e: ffmpeg::Error| encode_error(&path, e);
        let limit = (seconds * f64::from(self.rate)).round() as usize;
        let mut left: Vec<f32> = Vec::new();
        let mut right: Vec<f32> = Vec::new();
        let mut resampler: Option<resampling::Context> = None;
        let mut packet = ffmpeg::Packet::empty();
        let mut ended = false;
        while left.len() < limit && !ended {
            match packet.read(&mut self.input) {
                Ok(()) if packet.stream() == self.stream => {
                    self.decoder.send_packet(&packet).map_err(fail)?
                }
                Ok(()) => continue,
                Err(ffmpeg::Error::Eof) => {
                    self.decoder.send_eof().map_err(fail)?;
                    ended = true;
                }
                Err(e) => return Err(fail(e)),
            }
            let mut decoded = AvAudio::empty();
            while self.decoder.receive_frame(&mut decoded).is_ok() {
                let mut layout = decoded.channel_layout();
                if layout.is_empty() {
                    layout = ChannelLayout::default(i32::from(decoded.channels()));
                    decoded.set_channel_layout(layout);
                }
                if resampler.is_none() {
                    resampler = Some(
                        resampling::Context::get(
                            decoded.format(),
                            layout,
                            decoded.rate(),
                            Sample::F32(sample::Type::Planar),
                            ChannelLayout::STEREO,
                            self.rate,
                        )
                        .map_err(fail)?,
                    );
                }
                let mut stereo = AvAudio::empty();
                if let Some(r) = &mut resampler {
                    r.run(&decoded, &mut stereo).map_err(fail)?;
                }
                let n = stereo.samples();
                left.extend_from_slice(&stereo.plane::<f32>(0)[..n]);
                right.extend_from_slice(&stereo.plane::<f32>(1)[..n]);
            }
        }
        left.truncate(limit);
        right.truncate(limit);
        let size = (self.encoder.frame_size() as usize).max(1);
        let mut written = 0usize;
        while written < left.len() {
            let n = size.min(left.len() - written);
            let mut frame = AvAudio::new(
                Sample::F32(sample::Type::Planar),
                size,
                ChannelLayout::STEREO,
            );
            frame.set_rate(self.rate);
            for (plane, source) in [(0, &left), (1, &right)] {
                let out = frame.plane_mut::<f32>(plane);
                out[..n].copy_from_slice(&source[written..written + n]);
                out[n..].fill(0.0);
            }
            frame.set_pts(Some(written as i64));
            self.encoder.send_frame(&frame).map_err(fail)?;
            self.write_packets(output)?;
            written += n;
        }
        self.encoder.send_eof().map_err(fail)?;
        self.write_packets(output)
    }

    fn write_packets(
        &mut self,
        output: &mut ffmpeg::format::context::Output,
    ) -> Result<(), MediaError> {
        let stream_tb = output
            .stream(self.out_stream)
            .map(|s| s.time_base())
            .unwrap_or(Rational(1, self.rate as i32));
        let mut packet = ffmpeg::Packet::empty();
        while self.encoder.receive_packet(&mut packet).is_ok() {
            packet.set_stream(self.out_stream);
            packet.rescale_ts(Rational(1, self.rate as i32), stream_tb);
            packet
                .write_interleaved(output)
                .map_err(|e| encode_error(&self.path, e))?;
        }
        Ok(())
    }
}
