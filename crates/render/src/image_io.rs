//! Writing rendered images: PNG (8-bit; sRGB-encoded unless asked not to)
//! or OpenEXR (32-bit float, linear), by file extension; from 32-bit floats
//! or, byte for byte the same files, from a texture's half floats.

use std::path::Path;

use crate::error::RenderError;
use crate::readback::{ImageF16, ImageF32, Pixels, linear_to_srgb};

/// How 8-bit output encodes linear values.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Encoding {
    /// sRGB transfer (for colour a person looks at).
    Srgb,
    /// Values as they are, clamped to 0..1 (for data such as normals).
    Linear,
}

/// Write `image` to `path`: EXR when the extension is `.exr`, PNG otherwise.
/// Written to a temporary file and renamed, so a failed write never leaves half an image.
pub fn write_image(image: &ImageF32, path: &Path, encoding: Encoding) -> Result<(), RenderError> {
    let err = |message: String| RenderError::ImageWrite {
        path: path.display().to_string(),
        message,
    };
    let is_exr = is_exr(path);
    let tmp = path.with_extension(if is_exr { "tmp.exr" } else { "tmp.png" });
    let bytes = encode_image(image, encoding, is_exr).map_err(err)?;
    std::fs::write(&tmp, bytes).map_err(|e| err(e.to_string()))?;
    std::fs::rename(&tmp, path).map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        err(e.to_string())
    })
}

/// Whether `path` names an OpenEXR file (by extension, any case).
pub fn is_exr(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("exr"))
}

/// `image` as the bytes of a file: 32-bit float OpenEXR when `exr`, else 8-bit PNG.
pub fn encode_image(image: &ImageF32, encoding: Encoding, exr: bool) -> Result<Vec<u8>, String> {
    if !exr {
        return encode_png(image.width, image.height, &to_rgba8(image, encoding));
    }
    let mut bytes = std::io::Cursor::new(Vec::new());
    let data: Vec<f32> = image.pixels.iter().flatten().copied().collect();
    image::Rgba32FImage::from_raw(image.width, image.height, data)
        .ok_or("pixel count does not match the size")?
        .write_to(&mut bytes, image::ImageFormat::OpenExr)
        .map_err(|e| e.to_string())?;
    Ok(bytes.into_inner())
}

/// 8-bit RGBA rows as the bytes of a PNG file. Compressed with `png`'s
/// `Fast` setting (fdeflate, a deflate made for PNG's filtered rows) and
/// the adaptive filter: lossless like any PNG, about a tenth of the CPU of
/// the default (zlib level 6) for files about a quarter larger (a 1080p
/// frame of `patches/post.ron`: 13 ms against 137 on one core, 1.16 MB
/// against 0.93; docs/benchmarks.md, "Offline throughput by stage").
pub fn encode_png(width: u32, height: u32, rgba: &[u8]) -> Result<Vec<u8>, String> {
    use image::ImageEncoder;
    use image::codecs::png::{CompressionType, FilterType, PngEncoder};
    // The encoder panics on a buffer of another length.
    if rgba.len() as u64 != u64::from(width) * u64::from(height) * 4 {
        return Err("pixel count does not match the size".to_owned());
    }
    let mut bytes = Vec::new();
    PngEncoder::new_with_quality(&mut bytes, CompressionType::Fast, FilterType::Adaptive)
        .write_image(rgba, width, height, image::ExtendedColorType::Rgba8)
        .map_err(|e| e.to_string())?;
    Ok(bytes)
}

/// `pixels` as the bytes of a file, as [`encode_image`] makes of their
/// 32-bit floats, byte for byte: a texture's halves are mapped to 8 bits
/// through a table of every half (the same function, evaluated once per
/// half rather than once per value) and widened exactly for a float EXR.
pub fn encode_pixels(pixels: &Pixels, encoding: Encoding, exr: bool) -> Result<Vec<u8>, String> {
    match pixels {
        Pixels::Half(image) if !exr => {
            encode_png(image.width, image.height, &halves_to_rgba8(image, encoding))
        }
        Pixels::Half(image) => encode_image(&image.to_f32(), encoding, exr),
        Pixels::Float(image) => encode_image(image, encoding, exr),
    }
}

/// Per half (by its bits): its 8-bit value sRGB-encoded, and as it is
/// (clamped), what [`to_rgba8`] makes of the half's float.
fn half_bytes() -> &'static [[u8; 2]] {
    static TABLE: std::sync::OnceLock<Vec<[u8; 2]>> = std::sync::OnceLock::new();
    TABLE.get_or_init(|| {
        (0..=u16::MAX)
            .map(|bits| {
                let v = half::f16::from_bits(bits).to_f32();
                [byte(linear_to_srgb(v)), byte(v.clamp(0.0, 1.0))]
            })
            .collect()
    })
}

/// A value in 0..1 as a byte, rounded (NaN as 0), as [`to_rgba8`] rounds.
fn byte(v: f32) -> u8 {
    (v * 255.0 + 0.5) as u8
}

/// [`to_rgba8`] of halves, through [`half_bytes`]: colour encoded as asked, alpha as it is.
pub fn halves_to_rgba8(image: &ImageF16, encoding: Encoding) -> Vec<u8> {
    let table = half_bytes();
    let colour = match encoding {
        Encoding::Srgb => 0,
        Encoding::Linear => 1,
    };
    image
        .values
        .chunks_exact(4)
        .flat_map(|p| {
            let at = |i: usize| table[usize::from(p[i].to_bits())];
            [at(0)[colour], at(1)[colour], at(2)[colour], at(3)[1]]
        })
        .collect()
}

/// `image` as 8-bit RGBA, row by row: colour encoded as asked, alpha as it is (clamped).
pub fn to_rgba8(image: &ImageF32, encoding: Encoding) -> Vec<u8> {
    image
        .pixels
        .iter()
        .flat_map(|p| {
            let c = |v: f32| match encoding {
                Encoding::Srgb => linear_to_srgb(v),
                Encoding::Linear => v.clamp(0.0, 1.0),
            };
            [c(p[0]), c(p[1]), c(p[2]), p[3].clamp(0.0, 1.0)].map(byte)
        })
        .collect()
}
