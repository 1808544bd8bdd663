//! The one-core cost of encoding a frame as a half-float RGBA EXR, per
//! lossless option of the `exr` crate and per deflate level of
//! `--exr half`'s own ZIP writer (`crates/cli/src/sequence/exr_zip.rs`,
//! compiled in as it is). Times are the encoding thread's own CPU time
//! (`/proc/thread-self/schedstat`), so a loaded machine still measures what
//! a core spends. Every file is read back and compared with the halves.

#[path = "../../../crates/cli/src/sequence/exr_zip.rs"]
mod exr_zip;

use std::io::{Cursor, Write};

use exr::prelude::*;

type Pixel = [f32; 4];

/// This thread's CPU time so far, in seconds.
fn cpu_seconds() -> f64 {
    let stat = std::fs::read_to_string("/proc/thread-self/schedstat").unwrap_or_default();
    let ns: f64 = stat
        .split_whitespace()
        .next()
        .and_then(|v| v.parse().ok())
        .unwrap_or(f64::NAN);
    ns * 1e-9
}

/// The `exr` crate's own writer, as `--exr half` used it.
fn by_the_crate(pixels: &[Pixel], (w, h): (usize, usize), encoding: Encoding) -> Vec<u8> {
    let channels = SpecificChannels::rgba(|Vec2(x, y): Vec2<usize>| {
        let p = pixels[y * w + x];
        let half = f16::from_f32;
        (half(p[0]), half(p[1]), half(p[2]), half(p[3]))
    });
    let layer = Layer::new((w, h), LayerAttributes::default(), encoding, channels);
    let mut bytes = Cursor::new(Vec::new());
    Image::from_layer(layer)
        .write()
        .to_buffered(&mut bytes)
        .expect("the crate writes");
    bytes.into_inner()
}

/// The same ZIP blocks as `exr_zip`'s, deflated by another deflater (rows
/// for comparison only; written plainly, without `exr_zip`'s reused buffers).
fn zip_with(
    pixels: &[Pixel],
    (w, h): (usize, usize),
    deflate: &dyn Fn(&[u8]) -> Vec<u8>,
) -> Vec<u8> {
    use exr::block::chunk::{Chunk, CompressedBlock, CompressedScanLineBlock};
    use exr::block::writer::ChunksWriter;
    use exr::meta::attribute::{ChannelDescription, LineOrder, SampleType};
    use exr::meta::header::Header;
    use exr::meta::{BlockDescription, Headers};
    let channels = ["A", "B", "G", "R"]
        .map(|n| ChannelDescription::named(n, SampleType::F16))
        .into_iter()
        .collect();
    let header = Header::new(Text::from("rgba"), (w, h), channels)
        .with_attributes(LayerAttributes::default())
        .with_encoding(
            Compression::ZIP16,
            BlockDescription::ScanLines,
            LineOrder::Increasing,
        );
    let mut out = Cursor::new(Vec::new());
    exr::block::write(&mut out, Headers::from(vec![header]), true, |_, writer| {
        for (i, top) in (0..h).step_by(16).enumerate() {
            let mut raw = Vec::new();
            for y in top..(top + 16).min(h) {
                for c in [3, 2, 1, 0] {
                    raw.extend(
                        pixels[y * w..(y + 1) * w]
                            .iter()
                            .flat_map(|p| f16::from_f32(p[c]).to_le_bytes()),
                    );
                }
            }
            let mut t: Vec<u8> = raw
                .iter()
                .step_by(2)
                .chain(raw.iter().skip(1).step_by(2))
                .copied()
                .collect();
            let mut previous = t[0];
            for b in t.iter_mut().skip(1) {
                let current = *b;
                *b = current.wrapping_sub(previous).wrapping_add(128);
                previous = current;
            }
            let z = deflate(&t);
            let bytes = if z.len() < raw.len() { z } else { raw };
            writer.write_chunk(
                i,
                Chunk {
                    layer_index: 0,
                    compressed_block: CompressedBlock::ScanLine(CompressedScanLineBlock {
                        y_coordinate: top as i32,
                        compressed_pixels_le: bytes,
                    }),
                },
            )?;
        }
        Ok(())
    })
    .expect("writes");
    out.into_inner()
}

/// The file's size and RGBA values.
fn read(bytes: &[u8]) -> (Vec2<usize>, Vec<Pixel>) {
    let image = exr::prelude::read()
        .no_deep_data()
        .largest_resolution_level()
        .rgba_channels(
            |size, _| (size, vec![[0.0f32; 4]; size.area()]),
            |(size, px): &mut (Vec2<usize>, Vec<Pixel>),
             at: Vec2<usize>,
             (r, g, b, a): (f32, f32, f32, f32)| {
                px[at.y() * size.width() + at.x()] = [r, g, b, a];
            },
        )
        .first_valid_layer()
        .all_attributes()
        .from_buffered(Cursor::new(bytes))
        .expect("a valid EXR");
    image.layer_data.channel_data.pixels
}

fn main() {
    // One core's cost: exr_zip.rs compresses blocks on rayon's threads, so
    // everything runs inside a pool of one thread, whose CPU time is read.
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("a thread");
    one.install(one_core);
    // The latency of a frame whose blocks spread over every core.
    let args: Vec<String> = std::env::args().collect();
    if let Some(path) = args.get(1) {
        let (size, pixels) = read(&std::fs::read(path).expect("the frame"));
        let size = (size.width(), size.height());
        let mut best = f64::MAX;
        for _ in 0..5 {
            let start = std::time::Instant::now();
            exr_zip::encode(exr_zip::Samples::Floats(&pixels), size, exr_zip::DEFLATE)
                .expect("encodes");
            best = best.min(start.elapsed().as_secs_f64());
        }
        println!(
            "exr_zip.rs {:?} on {} threads: {:.0} ms wall (best of 5)",
            exr_zip::DEFLATE,
            rayon::current_num_threads(),
            best * 1e3
        );
    }
}

fn one_core() {
    let args: Vec<String> = std::env::args().collect();
    let Some(path) = args.get(1) else {
        eprintln!("usage: exr-bench FRAME.exr [REPEATS]");
        std::process::exit(2);
    };
    let repeats: usize = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(3);
    let bytes = std::fs::read(path).expect("the frame");
    let (layer_size, pixels) = read(&bytes);
    let size = (layer_size.width(), layer_size.height());
    let halves: Vec<Pixel> = pixels
        .iter()
        .map(|p| p.map(|v| f16::from_f32(v).to_f32()))
        .collect();
    let raw = size.0 * size.1 * 8;
    println!(
        "{path}: {}x{}, {:.2} MB as halves; one core's CPU ms, best of {repeats}",
        size.0,
        size.1,
        raw as f64 / 1e6
    );
    println!("| option | CPU ms | MB | ratio |\n| --- | ---: | ---: | ---: |");
    let time = |name: &str, encode: &dyn Fn() -> Vec<u8>| {
        let mut best = f64::MAX;
        let mut out = Vec::new();
        for _ in 0..repeats {
            let start = cpu_seconds();
            out = encode();
            best = best.min(cpu_seconds() - start);
        }
        assert!(
            read(&out).1 == halves,
            "{name} does not read back as the halves"
        );
        println!(
            "| {name} | {:.0} | {:.2} | {:.2} |",
            best * 1e3,
            out.len() as f64 / 1e6,
            raw as f64 / out.len() as f64
        );
        let _ = std::io::stdout().flush();
        out
    };
    let lines = |compression| Encoding {
        compression,
        blocks: Blocks::ScanLines,
        line_order: LineOrder::Increasing,
    };
    time("uncompressed (exr crate)", &|| {
        by_the_crate(&pixels, size, lines(Compression::Uncompressed))
    });
    let crate_zip = time("ZIP, 16 lines (exr crate)", &|| {
        by_the_crate(&pixels, size, Encoding::SMALL_LOSSLESS)
    });
    time("ZIPS, 1 line (exr crate)", &|| {
        by_the_crate(&pixels, size, lines(Compression::ZIP1))
    });
    time("RLE (exr crate, scan lines)", &|| {
        by_the_crate(&pixels, size, lines(Compression::RLE))
    });
    time("PIZ (exr crate, scan lines)", &|| {
        by_the_crate(&pixels, size, lines(Compression::PIZ))
    });
    time("PIZ (exr crate, 256x256 tiles)", &|| {
        by_the_crate(&pixels, size, Encoding::SMALL_FAST_LOSSLESS)
    });
    let bits: Vec<f16> = pixels.iter().flatten().map(|&v| f16::from_f32(v)).collect();
    let deflaters = [1u8, 2, 3, 4, 6]
        .map(exr_zip::Deflate::Miniz)
        .into_iter()
        .chain([1, 2, 4, 6].map(exr_zip::Deflate::Libdeflate));
    for deflate in deflaters {
        let what = if deflate == exr_zip::DEFLATE {
            ": what `--exr half` writes"
        } else {
            ""
        };
        let ours = time(
            &format!("ZIP, 16 lines, {deflate:?} (exr_zip.rs{what})"),
            &|| {
                let samples = exr_zip::Samples::Floats(&pixels);
                exr_zip::encode(samples, size, deflate).expect("encodes").0
            },
        );
        if deflate == exr_zip::Deflate::Miniz(4) {
            println!(
                "(level 4 is the exr crate's file byte for byte: {})",
                ours == crate_zip
            );
        }
        // From a texture's halves (no conversion from floats), and where the time went.
        let spent = std::cell::Cell::new(exr_zip::Spent::default());
        let from_halves = time(&format!("ZIP, 16 lines, {deflate:?}, from halves"), &|| {
            let samples = exr_zip::Samples::Halves(&bits);
            let (bytes, s) = exr_zip::encode(samples, size, deflate).expect("encodes");
            spent.set(s);
            bytes
        });
        assert!(from_halves == ours, "the halves give another file");
        println!(
            "(of which converting and the predictor {:.0} ms, deflating {:.0} ms)",
            spent.get().converting.as_secs_f64() * 1e3,
            spent.get().compressing.as_secs_f64() * 1e3
        );
    }
    for level in [1u32, 2, 4] {
        time(&format!("ZIP, 16 lines, zlib-rs level {level}"), &|| {
            zip_with(&pixels, size, &|data| {
                let mut e =
                    flate2::write::ZlibEncoder::new(Vec::new(), flate2::Compression::new(level));
                e.write_all(data).expect("deflates");
                e.finish().expect("deflates")
            })
        });
    }
    time("ZIP, 16 lines, fdeflate", &|| {
        zip_with(&pixels, size, &|data| fdeflate::compress_to_vec(data))
    });
    for level in [1i32, 2, 3, 4, 6] {
        time(&format!("ZIP, 16 lines, libdeflate level {level}"), &|| {
            zip_with(&pixels, size, &|data| {
                let mut c = libdeflater::Compressor::new(
                    libdeflater::CompressionLvl::new(level).expect("a level"),
                );
                let mut out = vec![0; c.zlib_compress_bound(data.len())];
                let n = c.zlib_compress(data, &mut out).expect("deflates");
                out.truncate(n);
                out
            })
        });
    }
    png_rows(&halves, size, repeats);
    readback_rows(&halves, repeats);
}

/// Taking a `Rgba16Float` readback's bytes out of the mapped buffer: decoded
/// to 32-bit floats a pixel at a time (what `readback.rs` did for every
/// frame) against kept as halves (what it does now for such a texture).
fn readback_rows(pixels: &[Pixel], repeats: usize) {
    let bytes: Vec<u8> = pixels
        .iter()
        .flatten()
        .flat_map(|&v| f16::from_f32(v).to_le_bytes())
        .collect();
    let best = |f: &dyn Fn() -> usize| {
        let mut best = f64::MAX;
        for _ in 0..repeats {
            let start = cpu_seconds();
            std::hint::black_box(f());
            best = best.min(cpu_seconds() - start);
        }
        best * 1e3
    };
    let per_pixel = best(&|| {
        let mut out: Vec<Pixel> = Vec::with_capacity(pixels.len());
        for px in bytes.chunks_exact(8) {
            let h = |i: usize| f16::from_le_bytes([px[i], px[i + 1]]).to_f32();
            out.push([h(0), h(2), h(4), h(6)]);
        }
        out.len()
    });
    println!("| readback: to 32-bit floats, a pixel at a time (before) | {per_pixel:.0} | | |");
    let kept = best(&|| {
        let out: Vec<f16> = bytes
            .chunks_exact(2)
            .map(|b| f16::from_le_bytes([b[0], b[1]]))
            .collect();
        out.len()
    });
    println!("| readback: kept as halves (now) | {kept:.0} | | |");
}

/// PNG of the same frame (sRGB 8-bit, as `spreadlight` writes it): the
/// conversion per value against a table over every half, and the
/// compression settings `png` offers.
fn png_rows(halves: &[Pixel], (w, h): (usize, usize), repeats: usize) {
    let srgb = |c: f32| {
        let c = c.clamp(0.0, 1.0);
        let v = if c <= 0.003_130_8 {
            c * 12.92
        } else {
            1.055 * c.powf(1.0 / 2.4) - 0.055
        };
        (v * 255.0 + 0.5) as u8
    };
    let alpha = |c: f32| (c.clamp(0.0, 1.0) * 255.0 + 0.5) as u8;
    let best = |f: &dyn Fn() -> Vec<u8>| {
        let mut best = f64::MAX;
        let mut out = Vec::new();
        for _ in 0..repeats {
            let start = cpu_seconds();
            out = f();
            best = best.min(cpu_seconds() - start);
        }
        (best * 1e3, out)
    };
    let (ms, per_value) = best(&|| {
        halves
            .iter()
            .flat_map(|p| [srgb(p[0]), srgb(p[1]), srgb(p[2]), alpha(p[3])])
            .collect()
    });
    println!("| to 8-bit sRGB, per value (powf) | {ms:.0} | | |");
    let bits: Vec<u16> = halves
        .iter()
        .flatten()
        .map(|&v| f16::from_f32(v).to_bits())
        .collect();
    let (ms, table) = best(&|| {
        let lut: Vec<[u8; 2]> = (0..=u16::MAX)
            .map(|b| {
                let v = f16::from_bits(b).to_f32();
                [srgb(v), alpha(v)]
            })
            .collect();
        bits.chunks_exact(4)
            .flat_map(|p| {
                [
                    lut[p[0] as usize][0],
                    lut[p[1] as usize][0],
                    lut[p[2] as usize][0],
                    lut[p[3] as usize][1],
                ]
            })
            .collect()
    });
    println!("| to 8-bit sRGB, a table of every half (built each time) | {ms:.0} | | |");
    assert!(table == per_value, "the table gives other bytes");
    let raw = (w * h * 4) as f64;
    for (name, compression, filter) in [
        (
            "Balanced (flate2 level 6), adaptive: image's default",
            png::Compression::Balanced,
            png::Filter::Adaptive,
        ),
        (
            "Fast (fdeflate), adaptive",
            png::Compression::Fast,
            png::Filter::Adaptive,
        ),
        (
            "Fast (fdeflate), Up",
            png::Compression::Fast,
            png::Filter::Up,
        ),
        (
            "Fast (fdeflate), Paeth",
            png::Compression::Fast,
            png::Filter::Paeth,
        ),
    ] {
        let (ms, out) = best(&|| {
            let mut out = Vec::new();
            let mut e = png::Encoder::new(&mut out, w as u32, h as u32);
            e.set_color(png::ColorType::Rgba);
            e.set_depth(png::BitDepth::Eight);
            e.set_compression(compression);
            e.set_filter(filter);
            let mut writer = e.write_header().expect("header");
            writer.write_image_data(&table).expect("png");
            writer.finish().expect("png");
            out
        });
        println!(
            "| PNG {name} | {ms:.0} | {:.2} | {:.2} |",
            out.len() as f64 / 1e6,
            raw / out.len() as f64
        );
    }
    for level in [1u8, 2] {
        let (ms, out) = best(&|| {
            let mut out = Vec::new();
            let mut e = png::Encoder::new(&mut out, w as u32, h as u32);
            e.set_color(png::ColorType::Rgba);
            e.set_depth(png::BitDepth::Eight);
            e.set_deflate_compression(png::DeflateCompression::Level(level));
            e.set_filter(png::Filter::Adaptive);
            let mut writer = e.write_header().expect("header");
            writer.write_image_data(&table).expect("png");
            writer.finish().expect("png");
            out
        });
        println!(
            "| PNG flate2 level {level}, adaptive | {ms:.0} | {:.2} | {:.2} |",
            out.len() as f64 / 1e6,
            raw / out.len() as f64
        );
    }
}
