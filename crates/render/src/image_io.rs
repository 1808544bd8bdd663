//! Writing rendered images: PNG (8-bit; sRGB-encoded unless asked not to)
//! or OpenEXR (32-bit float, linear), by file extension.

use std::path::Path;

use crate::error::RenderError;
use crate::readback::{ImageF32, linear_to_srgb};

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
    let mut bytes = std::io::Cursor::new(Vec::new());
    let result = if exr {
        let data: Vec<f32> = image.pixels.iter().flatten().copied().collect();
        image::Rgba32FImage::from_raw(image.width, image.height, data)
            .ok_or("pixel count does not match the size")?
            .write_to(&mut bytes, image::ImageFormat::OpenExr)
    } else {
        image::RgbaImage::from_raw(image.width, image.height, to_rgba8(image, encoding))
            .ok_or("pixel count does not match the size")?
            .write_to(&mut bytes, image::ImageFormat::Png)
    };
    result.map_err(|e| e.to_string())?;
    Ok(bytes.into_inner())
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
            [c(p[0]), c(p[1]), c(p[2]), p[3].clamp(0.0, 1.0)].map(|v| (v * 255.0 + 0.5) as u8)
        })
        .collect()
}
