//! The half-float EXR of `--exr half`, ZIP-compressed by blocks of 16
//! lines (OpenEXR's `ZIP_COMPRESSION`), written here block by block rather
//! than by the `exr` crate's image writer, for one reason: the crate
//! deflates at a fixed level (miniz_oxide's 4), which cost three to four
//! times what a fast level does, and that was what held a 1080p sequence
//! to 34 frames a second on 16 cores (docs/benchmarks.md, "EXR encoding
//! and summed sub-frames"). The blocks are what OpenEXR's ZIP compressor
//! makes: per line the channels in name order (A, B, G, R) as
//! little-endian halves, the bytes split into even and odd halves, each
//! byte stored as its difference to the one before, deflated (zlib); a
//! block that does not shrink is stored raw. Any EXR reader decodes them.
//! They are deflated by libdeflate at level 1 ([`DEFLATE`]): as small as
//! the crate's level 4 for the CPU of miniz's level 1 (docs/benchmarks.md,
//! "Offline throughput by stage"); with miniz at level 4 the file is the
//! crate's own, byte for byte (tested). `tools/exr-bench` measures them.
//!
//! The samples come as 32-bit floats (rounded to halves here) or as the
//! halves a `Rgba16Float` texture held, which are written as they are: the
//! same bytes, without the round trip through floats.
//!
//! The blocks are compressed on rayon's threads, then written in order: the
//! same bytes, but a frame no longer waits for one core to deflate its 68
//! blocks one after another. A sequence's writer threads keep every core
//! busy either way; what this shortens is each frame's latency: the last
//! frames of a sequence (whose encoding the run waits for at its end), a
//! single image, `--threads 1`.

use std::io::Cursor;
use std::time::{Duration, Instant};

use exr::block::chunk::{Chunk, CompressedBlock, CompressedScanLineBlock};
use exr::block::writer::ChunksWriter;
use exr::meta::attribute::{ChannelDescription, LineOrder, SampleType};
use exr::meta::header::{Header, LayerAttributes};
use exr::meta::{BlockDescription, Headers};
use exr::prelude::{Compression, Text, f16};
use half::slice::HalfFloatSliceExt;
use rayon::prelude::*;

/// Lines per block: OpenEXR's ZIP (ZIPS has one).
const LINES: usize = 16;

/// What `--exr half` deflates with (the module's docs say why).
pub const DEFLATE: Deflate = Deflate::Libdeflate(1);

/// A deflater and its level; every one writes zlib streams any reader inflates.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Deflate {
    /// miniz_oxide (what the `exr` crate deflates with, at 4), level 0-10:
    /// what the tests check the blocks against, and tools/exr-bench compares.
    #[allow(dead_code)]
    Miniz(u8),
    /// libdeflate, level 1-12.
    Libdeflate(i32),
}

/// A frame's RGBA samples, top row first: 32-bit floats (rounded to halves
/// here) or the halves a `Rgba16Float` texture held (written as they are).
#[derive(Clone, Copy)]
pub enum Samples<'a> {
    Floats(&'a [[f32; 4]]),
    /// R, G, B, A of each pixel.
    Halves(&'a [f16]),
}

impl Samples<'_> {
    fn pixels(&self) -> usize {
        match self {
            Samples::Floats(p) => p.len(),
            Samples::Halves(v) => v.len() / 4,
        }
    }
}

/// Where a frame's encoding went, summed over its blocks (on whichever
/// threads compressed them): the samples laid out and ZIP's predictor, and
/// the deflating.
#[derive(Clone, Copy, Debug, Default)]
pub struct Spent {
    pub converting: Duration,
    pub compressing: Duration,
}

/// `samples` (`width` x `height`) as the bytes of a half-float EXR file,
/// ZIP-compressed with `deflate`, and where the time went.
pub fn encode(
    samples: Samples,
    (width, height): (usize, usize),
    deflate: Deflate,
) -> Result<(Vec<u8>, Spent), String> {
    let count = samples.pixels();
    if count != width * height
        || count == 0
        || matches!(samples, Samples::Halves(v) if v.len() % 4 != 0)
    {
        return Err(format!(
            "{count} pixels do not make a {width}x{height} image"
        ));
    }
    // Channels in name order, as EXR stores them; `named` picks what the crate's writer picks.
    let channels = ["A", "B", "G", "R"]
        .map(|name| ChannelDescription::named(name, SampleType::F16))
        .into_iter()
        .collect();
    let header = Header::new(Text::from("rgba"), (width, height), channels)
        // No layer name: a single-layer file, as the crate's image writer makes it.
        .with_attributes(LayerAttributes::default())
        .with_encoding(
            Compression::ZIP16,
            BlockDescription::ScanLines,
            LineOrder::Increasing,
        );
    let tops: Vec<usize> = (0..height).step_by(LINES).collect();
    let blocks: Vec<(Vec<u8>, Spent)> = tops
        .par_iter()
        .map_init(Block::default, |block, &top| {
            let lines = top..(top + LINES).min(height);
            block.compress(samples, lines, width, deflate)
        })
        .collect::<Result<_, String>>()?;
    let mut spent = Spent::default();
    let mut out = Cursor::new(Vec::with_capacity(width * height * 3));
    exr::block::write(&mut out, Headers::from(vec![header]), true, |_, writer| {
        for (index, (top, (compressed_pixels_le, block))) in tops.iter().zip(blocks).enumerate() {
            spent.converting += block.converting;
            spent.compressing += block.compressing;
            writer.write_chunk(
                index,
                Chunk {
                    layer_index: 0,
                    compressed_block: CompressedBlock::ScanLine(CompressedScanLineBlock {
                        y_coordinate: i32::try_from(*top).map_err(|_| {
                            exr::error::Error::Invalid("an image taller than 2^31 lines".into())
                        })?,
                        compressed_pixels_le,
                    }),
                },
            )?;
        }
        Ok(())
    })
    .map_err(|e| e.to_string())?;
    Ok((out.into_inner(), spent))
}

/// A half's bits as a round trip through a 32-bit float leaves them: a NaN
/// comes back quiet (its quiet bit set, its payload kept), every other half
/// as it was. So a signalling NaN a texture held is written as its float
/// would be, and the file is the same either way.
fn quieted(bits: u16) -> u16 {
    if bits & 0x7fff > 0x7c00 {
        bits | 0x0200
    } else {
        bits
    }
}

/// One block's buffers, kept from block to block.
#[derive(Default)]
struct Block {
    floats: Vec<f32>,
    halves: Vec<f16>,
    /// The block's halves in the order EXR stores them: per line, A, B, G, R.
    plane: Vec<u16>,
    /// Their low bytes, then their high bytes (ZIP's split).
    split: Vec<u8>,
    /// The same after ZIP's predictor.
    predicted: Vec<u8>,
    /// libdeflate's compressor (its tables), made once per thread.
    libdeflate: Option<(i32, libdeflater::Compressor)>,
}

impl Block {
    /// The bytes of the block of `lines` (of `width` pixels).
    fn compress(
        &mut self,
        samples: Samples,
        lines: std::ops::Range<usize>,
        width: usize,
        deflate: Deflate,
    ) -> Result<(Vec<u8>, Spent), String> {
        let started = Instant::now();
        self.plane.clear();
        for y in lines {
            for channel in [3, 2, 1, 0] {
                match samples {
                    Samples::Floats(pixels) => {
                        let line = &pixels[y * width..(y + 1) * width];
                        self.floats.clear();
                        self.floats.extend(line.iter().map(|p| p[channel]));
                        self.halves.resize(width, f16::ZERO);
                        // A slice at a time: F16C where the CPU has it.
                        self.halves.convert_from_f32_slice(&self.floats);
                        self.plane.extend(self.halves.iter().map(|h| h.to_bits()));
                    }
                    // The texture's halves as they are: what rounding their floats gives back.
                    Samples::Halves(values) => self.plane.extend(
                        values[y * width * 4..(y + 1) * width * 4]
                            .chunks_exact(4)
                            .map(|p| quieted(p[channel].to_bits())),
                    ),
                }
            }
        }
        // ZIP's predictor over the little-endian bytes: the even bytes (each half's low byte)
        // then the odd ones, each stored as its difference to the one before, plus 128.
        let n = self.plane.len();
        self.split.resize(2 * n, 0);
        let (low, high) = self.split.split_at_mut(n);
        for ((l, h), v) in low.iter_mut().zip(high.iter_mut()).zip(&self.plane) {
            [*l, *h] = v.to_le_bytes();
        }
        self.predicted.resize(2 * n, 0);
        if let (Some(first), Some(to)) = (self.split.first(), self.predicted.first_mut()) {
            *to = *first;
        }
        for (to, pair) in self.predicted[1..].iter_mut().zip(self.split.windows(2)) {
            *to = pair[1].wrapping_sub(pair[0]).wrapping_add(128);
        }
        let predicted = Instant::now();
        let compressed = match deflate {
            Deflate::Miniz(level) => {
                miniz_oxide::deflate::compress_to_vec_zlib(&self.predicted, level)
            }
            Deflate::Libdeflate(level) => {
                let compressor = match &mut self.libdeflate {
                    Some((made, compressor)) if *made == level => compressor,
                    slot => {
                        let lvl = libdeflater::CompressionLvl::new(level)
                            .map_err(|_| format!("no libdeflate level {level}"))?;
                        &mut slot.insert((level, libdeflater::Compressor::new(lvl))).1
                    }
                };
                let mut out = vec![0; compressor.zlib_compress_bound(self.predicted.len())];
                let n = compressor
                    .zlib_compress(&self.predicted, &mut out)
                    .map_err(|e| format!("deflating a block: {e}"))?;
                out.truncate(n);
                out
            }
        };
        let spent = Spent {
            converting: predicted - started,
            compressing: predicted.elapsed(),
        };
        // A block that does not shrink is stored as it is.
        let bytes = if compressed.len() < 2 * n {
            compressed
        } else {
            self.plane.iter().flat_map(|v| v.to_le_bytes()).collect()
        };
        Ok((bytes, spent))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use exr::prelude::{
        Encoding, Image, Layer, ReadChannels, ReadLayers, SpecificChannels, Vec2, WritableImage,
    };

    /// A frame with smooth areas, edges and noise, 37 lines (a last block of 5).
    fn frame() -> (Vec<[f32; 4]>, (usize, usize)) {
        let (width, height) = (53, 37);
        let mut seed = 7u32;
        let pixels = (0..width * height)
            .map(|i| {
                seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
                let noise = (seed >> 8) as f32 / (1 << 24) as f32 * 0.1;
                let (x, y) = ((i % width) as f32, (i / width) as f32);
                let edge = if x > 20.0 { 3.5 } else { 0.25 };
                [x / 53.0 + noise, y / 37.0, edge - noise, 1.0]
            })
            .collect();
        (pixels, (width, height))
    }

    /// What the `exr` crate's own image writer makes of the same pixels.
    fn by_the_crate(pixels: &[[f32; 4]], (width, height): (usize, usize)) -> Vec<u8> {
        let channels = SpecificChannels::rgba(|Vec2(x, y): Vec2<usize>| {
            let p = pixels[y * width + x];
            let half = f16::from_f32;
            (half(p[0]), half(p[1]), half(p[2]), half(p[3]))
        });
        let layer = Layer::new(
            (width, height),
            LayerAttributes::default(),
            Encoding::SMALL_LOSSLESS,
            channels,
        );
        let mut bytes = Cursor::new(Vec::new());
        Image::from_layer(layer)
            .write()
            .to_buffered(&mut bytes)
            .expect("the crate writes");
        bytes.into_inner()
    }

    /// The file's RGBA values, read with the `exr` crate.
    fn read(bytes: &[u8]) -> Vec<f32> {
        let image = exr::prelude::read()
            .no_deep_data()
            .largest_resolution_level()
            .rgba_channels(
                |size, _| (size.width(), vec![[0.0f32; 4]; size.area()]),
                |(width, pixels): &mut (usize, Vec<[f32; 4]>),
                 at: Vec2<usize>,
                 (r, g, b, a): (f32, f32, f32, f32)| {
                    pixels[at.y() * *width + at.x()] = [r, g, b, a];
                },
            )
            .first_valid_layer()
            .all_attributes()
            .from_buffered(Cursor::new(bytes))
            .expect("a valid EXR");
        image
            .layer_data
            .channel_data
            .pixels
            .1
            .into_iter()
            .flatten()
            .collect()
    }

    #[test]
    fn halves_are_laid_out_as_their_floats_round_back() {
        for bits in 0..=u16::MAX {
            let round_trip = f16::from_f32(f16::from_bits(bits).to_f32()).to_bits();
            assert_eq!(quieted(bits), round_trip, "{bits:#06x}");
        }
    }

    #[test]
    fn at_the_crates_level_the_bytes_are_the_crates() {
        let (pixels, size) = frame();
        let ours = encode(Samples::Floats(&pixels), size, Deflate::Miniz(4)).expect("encodes");
        assert_eq!(ours.0, by_the_crate(&pixels, size));
    }

    #[test]
    fn every_level_reads_back_as_the_halves_of_the_pixels() {
        let (pixels, size) = frame();
        let expected: Vec<f32> = pixels
            .iter()
            .flatten()
            .map(|&v| f16::from_f32(v).to_f32())
            .collect();
        let halves: Vec<f16> = pixels.iter().flatten().map(|&v| f16::from_f32(v)).collect();
        let deflaters = [0, 1, 4, 9]
            .map(Deflate::Miniz)
            .into_iter()
            .chain([1, 6, 12].map(Deflate::Libdeflate))
            .chain([DEFLATE]);
        for deflate in deflaters {
            let (bytes, _) = encode(Samples::Floats(&pixels), size, deflate).expect("encodes");
            assert_eq!(read(&bytes), expected, "{deflate:?}");
            // From the halves themselves: the same file.
            let (same, _) = encode(Samples::Halves(&halves), size, deflate).expect("encodes");
            assert!(
                same == bytes,
                "{deflate:?}: halves and their floats give other files"
            );
        }
        let taller = (size.0, size.1 + 1);
        assert!(encode(Samples::Floats(&pixels), taller, DEFLATE).is_err());
        assert!(encode(Samples::Halves(&halves), taller, DEFLATE).is_err());
        assert!(encode(Samples::Halves(&halves[1..]), size, DEFLATE).is_err());
        assert!(encode(Samples::Floats(&pixels), size, Deflate::Libdeflate(13)).is_err());
    }
}
