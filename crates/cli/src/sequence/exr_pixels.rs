//! `--exr half`: EXR frames as half floats, ZIP-compressed (lossless over
//! the halves), written with the `exr` crate. A 1080p RGBA frame is about a
//! quarter of the default's 33 MB of uncompressed 32-bit floats, which a
//! sequence writing at GPU speed needs: at 60 frames a second the default
//! writes 2 GB a second. Half floats keep 11 significant bits, what
//! compositing beauty passes usually takes; data passes (depth, positions)
//! keep the default.

use exr::prelude::{
    Encoding, Image, Layer, LayerAttributes, SpecificChannels, Vec2, WritableImage, f16,
};
use spreadlight_render::readback::ImageF32;

/// The pixels of EXR files (`--exr`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum)]
pub enum ExrPixels {
    /// 32-bit floats, uncompressed (what `spreadlight` always wrote).
    #[default]
    Float,
    /// 16-bit floats, ZIP-compressed in blocks of 16 lines.
    Half,
}

/// `image` as the bytes of a half-float EXR file.
pub fn encode_half(image: &ImageF32) -> Result<Vec<u8>, String> {
    let (width, height) = (image.width as usize, image.height as usize);
    if image.pixels.len() != width * height {
        return Err("pixel count does not match the size".to_owned());
    }
    let channels = SpecificChannels::rgba(|Vec2(x, y): Vec2<usize>| {
        let p = image.pixels[y * width + x];
        let half = f16::from_f32;
        (half(p[0]), half(p[1]), half(p[2]), half(p[3]))
    });
    let layer = Layer::new(
        (width, height),
        LayerAttributes::default(),
        Encoding::SMALL_LOSSLESS,
        channels,
    );
    let mut bytes = std::io::Cursor::new(Vec::new());
    Image::from_layer(layer)
        .write()
        .to_buffered(&mut bytes)
        .map_err(|e| e.to_string())?;
    Ok(bytes.into_inner())
}

#[cfg(test)]
mod tests {
    use super::*;

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
        let bytes = encode_half(&image).expect("encodes");
        let decoded = image::load_from_memory_with_format(&bytes, image::ImageFormat::OpenExr)
            .expect("decodes")
            .to_rgba32f();
        assert_eq!(decoded.dimensions(), (2, 1));
        let expected: Vec<f32> = values.iter().map(|&v| f16::from_f32(v).to_f32()).collect();
        assert_eq!(decoded.into_raw(), expected);
        let wrong = ImageF32 { width: 3, ..image };
        assert!(encode_half(&wrong).is_err());
    }
}
