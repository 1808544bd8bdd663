//! The half-float EXR of `--exr half`, ZIP-compressed by blocks of 16
//! lines (OpenEXR's `ZIP_COMPRESSION`), written here block by block rather
//! than by the `exr` crate's image writer, for one reason: the crate
//! deflates at a fixed level (miniz_oxide's 4), which costs three to four
//! times what level 1 does for a tenth fewer bytes, and that was what held
//! a 1080p sequence to 34 frames a second on 16 cores (docs/benchmarks.md,
//! "EXR encoding and summed sub-frames"). The blocks are what OpenEXR's ZIP
//! compressor makes: per line the channels in name order (A, B, G, R) as
//! little-endian halves, the bytes split into even and odd halves, each
//! byte stored as its difference to the one before, deflated (zlib); a
//! block that does not shrink is stored raw. Any EXR reader decodes them;
//! only the deflate level differs from the crate's (at its level, 4, the
//! bytes are the crate's own: tested). `tools/exr-bench` measures it.
//!
//! The blocks are compressed on rayon's threads, then written in order: the
//! same bytes, but a frame no longer waits for one core to deflate its 68
//! blocks one after another. A sequence's writer threads keep every core
//! busy either way; what this shortens is each frame's latency: the last
//! frames of a sequence (whose encoding the run waits for at its end), a
//! single image, `--threads 1`.

use std::io::Cursor;

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

/// The deflate level `--exr half` writes with (miniz_oxide's 1: its
/// fastest that still searches for matches); see the module's docs.
pub const LEVEL: u8 = 1;

/// `pixels` (RGBA, `width` x `height`, top row first) as the bytes of a
/// half-float EXR file, ZIP-compressed at deflate `level` (0-10).
pub fn encode(
    pixels: &[[f32; 4]],
    (width, height): (usize, usize),
    level: u8,
) -> Result<Vec<u8>, String> {
    if pixels.len() != width * height || pixels.is_empty() {
        return Err(format!(
            "{} pixels do not make a {width}x{height} image",
            pixels.len()
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
    let blocks: Vec<Vec<u8>> = tops
        .par_iter()
        .map_init(Block::default, |block, &top| {
            let lines = &pixels[top * width..(top + LINES).min(height) * width];
            block.compress(lines, width, level)
        })
        .collect();
    let mut out = Cursor::new(Vec::with_capacity(width * height * 3));
    exr::block::write(&mut out, Headers::from(vec![header]), true, |_, writer| {
        for (index, (top, compressed_pixels_le)) in tops.iter().zip(blocks).enumerate() {
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
    Ok(out.into_inner())
}

/// One block's buffers, kept from block to block.
#[derive(Default)]
struct Block {
    floats: Vec<f32>,
    halves: Vec<f16>,
    /// The block as EXR stores it uncompressed.
    raw: Vec<u8>,
    /// The same after ZIP's predictor.
    predicted: Vec<u8>,
}

impl Block {
    /// The bytes of the block of `lines` (whole lines of `width` pixels).
    fn compress(&mut self, lines: &[[f32; 4]], width: usize, level: u8) -> Vec<u8> {
        self.raw.clear();
        for line in lines.chunks_exact(width) {
            for channel in [3, 2, 1, 0] {
                self.floats.clear();
                self.floats.extend(line.iter().map(|p| p[channel]));
                self.halves.resize(width, f16::ZERO);
                // A slice at a time: F16C where the CPU has it.
                self.halves.convert_from_f32_slice(&self.floats);
                self.raw
                    .extend(self.halves.iter().flat_map(|h| h.to_le_bytes()));
            }
        }
        // ZIP's predictor: even bytes then odd bytes, each as its difference to the one before.
        let raw = &self.raw;
        self.predicted.clear();
        self.predicted
            .extend(raw.iter().step_by(2).chain(raw.iter().skip(1).step_by(2)));
        let mut previous = self.predicted.first().copied().unwrap_or(0);
        for byte in self.predicted.iter_mut().skip(1) {
            let current = *byte;
            *byte = current.wrapping_sub(previous).wrapping_add(128);
            previous = current;
        }
        let compressed = miniz_oxide::deflate::compress_to_vec_zlib(&self.predicted, level);
        if compressed.len() < raw.len() {
            compressed
        } else {
            raw.clone()
        }
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
    fn at_the_crates_level_the_bytes_are_the_crates() {
        let (pixels, size) = frame();
        assert_eq!(encode(&pixels, size, 4), Ok(by_the_crate(&pixels, size)));
    }

    #[test]
    fn every_level_reads_back_as_the_halves_of_the_pixels() {
        let (pixels, size) = frame();
        let expected: Vec<f32> = pixels
            .iter()
            .flatten()
            .map(|&v| f16::from_f32(v).to_f32())
            .collect();
        for level in [0, LEVEL, 4, 9] {
            let bytes = encode(&pixels, size, level).expect("encodes");
            assert_eq!(read(&bytes), expected, "level {level}");
        }
        assert!(encode(&pixels, (size.0, size.1 + 1), LEVEL).is_err());
    }
}
