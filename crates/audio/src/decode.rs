//! Decoding a whole audio file into memory, mixed down to mono: what
//! `AudioFile` plays. symphonia (pure Rust) reads WAV, FLAC, MP3 and Ogg
//! Vorbis. A file is decoded once, when a node first needs it; a minute of
//! 44.1 kHz sound is 10 MB of samples.

use std::path::Path;
use std::sync::Arc;

use symphonia::core::audio::SampleBuffer;
use symphonia::core::codecs::{CODEC_TYPE_NULL, DecoderOptions};
use symphonia::core::errors::Error as SymphoniaError;
use symphonia::core::formats::FormatOptions;
use symphonia::core::io::MediaSourceStream;
use symphonia::core::meta::MetadataOptions;
use symphonia::core::probe::Hint;

use crate::error::AudioError;

/// A decoded file: its samples mixed to mono, at the file's own rate.
#[derive(Clone, Debug)]
pub struct Clip {
    pub samples: Arc<[f32]>,
    pub rate: u32,
    /// The channels the file had before the mix-down.
    pub channels: usize,
}

impl Clip {
    /// The length in seconds.
    pub fn duration(&self) -> f64 {
        self.samples.len() as f64 / f64::from(self.rate.max(1))
    }
}

/// Whether a symphonia error is the end of the stream (how its readers say "no more packets").
fn is_end(e: &SymphoniaError) -> bool {
    matches!(e, SymphoniaError::IoError(io) if io.kind() == std::io::ErrorKind::UnexpectedEof)
}

/// Decode `path` whole. A missing file, a file of no known format, one that
/// fails to decode and one shorter than its header says (truncated) are
/// errors naming the file.
pub fn decode_file(path: &Path) -> Result<Clip, AudioError> {
    let file = std::fs::File::open(path).map_err(|source| AudioError::Open {
        path: path.to_path_buf(),
        source,
    })?;
    let format_error = |e: SymphoniaError| AudioError::Format {
        path: path.to_path_buf(),
        message: e.to_string(),
    };
    let decode_error = |message: String| AudioError::Decode {
        path: path.to_path_buf(),
        message,
    };
    let stream = MediaSourceStream::new(Box::new(file), Default::default());
    let mut hint = Hint::new();
    if let Some(ext) = path.extension().and_then(|e| e.to_str()) {
        hint.with_extension(ext);
    }
    let probed = symphonia::default::get_probe()
        .format(
            &hint,
            stream,
            &FormatOptions::default(),
            &MetadataOptions::default(),
        )
        .map_err(format_error)?;
    let mut format = probed.format;
    let track = format
        .tracks()
        .iter()
        .find(|t| t.codec_params.codec != CODEC_TYPE_NULL)
        .ok_or_else(|| AudioError::Empty {
            path: path.to_path_buf(),
        })?;
    let (track_id, params) = (track.id, track.codec_params.clone());
    let mut decoder = symphonia::default::get_codecs()
        .make(&params, &DecoderOptions::default())
        .map_err(format_error)?;

    let mut mono: Vec<f32> = Vec::new();
    let mut rate = params.sample_rate.unwrap_or(0);
    let mut channels = params.channels.map_or(0, |c| c.count());
    let mut frames: u64 = 0;
    let (mut good, mut bad) = (0usize, 0usize);
    let mut buffer: Option<SampleBuffer<f32>> = None;
    loop {
        let packet = match format.next_packet() {
            Ok(p) => p,
            Err(e) if is_end(&e) => break,
            Err(e) => return Err(decode_error(e.to_string())),
        };
        if packet.track_id() != track_id {
            continue;
        }
        let decoded = match decoder.decode(&packet) {
            Ok(d) => d,
            // A damaged packet is skipped, as players do; a file of nothing but is an error below.
            Err(SymphoniaError::DecodeError(_)) => {
                bad += 1;
                continue;
            }
            Err(e) if is_end(&e) => break,
            Err(e) => return Err(decode_error(e.to_string())),
        };
        good += 1;
        let spec = *decoded.spec();
        rate = spec.rate;
        channels = spec.channels.count().max(1);
        let needed = decoded.capacity() as u64;
        let buf = match &mut buffer {
            Some(b) if b.capacity() as u64 >= needed * channels as u64 => b,
            _ => buffer.insert(SampleBuffer::new(needed, spec)),
        };
        buf.copy_interleaved_ref(decoded);
        let scale = 1.0 / channels as f32;
        mono.extend(
            buf.samples()
                .chunks_exact(channels)
                .map(|frame| frame.iter().sum::<f32>() * scale),
        );
        frames += (buf.samples().len() / channels) as u64;
    }
    if good == 0 && bad > 0 {
        return Err(decode_error(format!("all {bad} packets are damaged")));
    }
    if mono.is_empty() || rate == 0 {
        return Err(AudioError::Empty {
            path: path.to_path_buf(),
        });
    }
    // Readers stop quietly at the end of what is there: a file cut short
    // shows only as fewer frames than its header announced. One packet of
    // slack allows for decoders that trim priming samples.
    if let Some(expected) = params.n_frames {
        let slack = params.max_frames_per_packet.unwrap_or(4096);
        if frames + slack < expected {
            return Err(AudioError::Truncated {
                path: path.to_path_buf(),
                expected,
                got: frames,
            });
        }
    }
    Ok(Clip {
        samples: Arc::from(mono),
        rate,
        channels,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tones::{sine, write_wav};

    #[test]
    fn a_stereo_wav_decodes_to_mono_at_its_rate() {
        let dir = tempfile::tempdir().expect("tempdir");
        let path = dir.path().join("tone.wav");
        let left = sine(440.0, 0.5, 8000, 0.25);
        // Right is the same tone inverted at half level: the mix is a quarter of the left.
        let right: Vec<f32> = left.iter().map(|s| -0.5 * s).collect();
        write_wav(&path, &[left.clone(), right], 8000);
        let clip = decode_file(&path).expect("decodes");
        assert_eq!(clip.rate, 8000);
        assert_eq!(clip.channels, 2);
        assert_eq!(clip.samples.len(), left.len());
        for (got, l) in clip.samples.iter().zip(&left) {
            assert!((got - 0.25 * l).abs() < 1e-3, "{got} vs {}", 0.25 * l);
        }
        assert!((clip.duration() - 0.25).abs() < 1e-9);
    }

    #[test]
    fn missing_truncated_and_garbage_files_are_errors_naming_the_file() {
        let dir = tempfile::tempdir().expect("tempdir");
        let missing = dir.path().join("missing.wav");
        let e = decode_file(&missing).expect_err("missing");
        assert!(matches!(e, AudioError::Open { .. }), "{e}");
        assert!(e.to_string().contains("missing.wav"), "{e}");

        let garbage = dir.path().join("garbage.wav");
        std::fs::write(
            &garbage,
            b"this is not a sound at all, only words".repeat(50),
        )
        .expect("write");
        let e = decode_file(&garbage).expect_err("garbage");
        assert!(matches!(e, AudioError::Format { .. }), "{e}");
        assert!(e.to_string().contains("garbage.wav"), "{e}");

        let whole = dir.path().join("whole.wav");
        write_wav(&whole, &[sine(440.0, 0.5, 8000, 1.0)], 8000);
        let bytes = std::fs::read(&whole).expect("read");
        let cut = dir.path().join("cut.wav");
        std::fs::write(&cut, &bytes[..bytes.len() / 2]).expect("write");
        let e = decode_file(&cut).expect_err("truncated");
        assert!(matches!(e, AudioError::Truncated { .. }), "{e}");
        assert!(e.to_string().contains("cut.wav"), "{e}");
    }
}
