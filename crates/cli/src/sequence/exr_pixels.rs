//! `--exr half`: EXR frames as half floats, ZIP-compressed (lossless over
//! the halves; `exr_zip.rs` writes them). A 1080p RGBA frame is about a
//! quarter of the default's 33 MB of uncompressed 32-bit floats, which a
//! sequence writing at GPU speed needs: at 60 frames a second the default
//! writes 2 GB a second. Half floats keep 11 significant bits, what
//! compositing beauty passes usually takes; data passes (depth, positions)
//! keep the default.

use spreadlight_render::readback::Pixels;

use super::exr_zip::{self, Samples, Spent};

/// The pixels of EXR files (`--exr`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum)]
pub enum ExrPixels {
    /// 32-bit floats, uncompressed (what `spreadlight` always wrote).
    #[default]
    Float,
    /// 16-bit floats, ZIP-compressed in blocks of 16 lines (libdeflate at level 1).
    Half,
}

/// `pixels` as the bytes of a half-float EXR file, and where the time
/// went. A texture's halves are written as they are (the same bytes as
/// rounding their floats to halves gives: a half widens to a float exactly).
pub fn encode_half(pixels: &Pixels) -> Result<(Vec<u8>, Spent), String> {
    let (width, height) = pixels.size();
    let samples = match pixels {
        Pixels::Half(image) => Samples::Halves(&image.values),
        Pixels::Float(image) => Samples::Floats(&image.pixels),
    };
    exr_zip::encode(samples, (width as usize, height as usize), exr_zip::DEFLATE)
}

#[cfg(test)]
mod tests {
    use super::*;
    use exr::prelude::f16;
    use spreadlight_render::readback::{ImageF16, ImageF32};

    #[test]
    fn half_exr_decodes_to_the_halves_of_the_image() {
        let values = [0.0, 0.25, 1.5, 1000.0, -2.0, 0.1, 65504.0, 3.0];
        let image = ImageF32 {
            width: 2,
            height: 1,
            pixels: vec![
                [values[0], values[1], values[2], values[3]],
                [values[4], values[5], values[6], values[7]],
            ],
        };
        let halves = Pixels::Half(ImageF16 {
            width: 2,
            height: 1,
            values: values.iter().map(|&v| f16::from_f32(v)).collect(),
        });
        let (bytes, _) = encode_half(&Pixels::Float(image.clone())).expect("encodes");
        let decoded = image::load_from_memory_with_format(&bytes, image::ImageFormat::OpenExr)
            .expect("decodes")
            .to_rgba32f();
        assert_eq!(decoded.dimensions(), (2, 1));
        let expected: Vec<f32> = values.iter().map(|&v| f16::from_f32(v).to_f32()).collect();
        assert_eq!(decoded.into_raw(), expected);
        // The texture's halves themselves make the same file.
        assert_eq!(encode_half(&halves).expect("encodes").0, bytes);
        let wrong = ImageF32 { width: 3, ..image };
        assert!(encode_half(&Pixels::Float(wrong)).is_err());
    }
}
