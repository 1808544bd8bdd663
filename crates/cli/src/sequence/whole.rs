//! Whether a frame file is whole, cheaply: a resume (and every farm round's
//! `--dry-run`) checks thousands of frames, so this reads headers and
//! trailers, not pixels. PNG: the size in its header and the IEND chunk at
//! its end. OpenEXR (single-part, scanlines or tiles; the image crate
//! writes 64x64 tiles): the data window, and the offset table's last chunk
//! ending at the end of the file. Anything else is decoded in full.

use std::fs::File;
use std::io::{Read, Seek, SeekFrom};
use std::path::Path;

const PNG_END: [u8; 12] = [0, 0, 0, 0, b'I', b'E', b'N', b'D', 0xAE, 0x42, 0x60, 0x82];
const EXR_MAGIC: [u8; 4] = [0x76, 0x2f, 0x31, 0x01];

/// Whether `path` holds a whole image of `size`.
pub fn is_whole(path: &Path, size: (u32, u32)) -> bool {
    let Ok(mut file) = File::open(path) else {
        return false;
    };
    let mut magic = [0u8; 4];
    if file.read_exact(&mut magic).is_err() {
        return false;
    }
    let quick = if magic == EXR_MAGIC {
        exr(&mut file)
    } else if magic == [0x89, b'P', b'N', b'G'] {
        png(path, &mut file)
    } else {
        None
    };
    match quick {
        Some(found) => found == size,
        None => image::open(path).is_ok_and(|i| (i.width(), i.height()) == size),
    }
}

/// A PNG's size when it ends with its IEND chunk; `Some((0, 0))` when it
/// does not (cut short), `None` when its header cannot be read.
fn png(path: &Path, file: &mut File) -> Option<(u32, u32)> {
    let dimensions = image::ImageReader::open(path)
        .ok()?
        .into_dimensions()
        .ok()?;
    let mut end = [0u8; 12];
    file.seek(SeekFrom::End(-12)).ok()?;
    file.read_exact(&mut end).ok()?;
    Some(if end == PNG_END { dimensions } else { (0, 0) })
}

/// An EXR's size when its last chunk ends at the end of the file, `Some((0, 0))`
/// when it is cut short, `None` for a layout this does not read (decoded instead).
fn exr(file: &mut File) -> Option<(u32, u32)> {
    let length = file.metadata().ok()?.len();
    let mut head = Vec::new();
    file.seek(SeekFrom::Start(0)).ok()?;
    file.by_ref().take(1 << 20).read_to_end(&mut head).ok()?;
    let flags = u32::from_le_bytes(head.get(4..8)?.try_into().ok()?);
    // Deep or multi-part files: decode instead.
    if flags & 0x1c00 != 0 {
        return None;
    }
    let tiled = flags & 0x200 != 0;
    let (mut at, mut window, mut lines, mut count) = (8usize, None, None, None);
    loop {
        let name_end = at + head.get(at..)?.iter().position(|&b| b == 0)?;
        if name_end == at {
            at += 1; // the header's terminating null
            break;
        }
        let name = &head[at..name_end];
        let type_end = name_end + 1 + head.get(name_end + 1..)?.iter().position(|&b| b == 0)?;
        let size_at = type_end + 1;
        let size = u32::from_le_bytes(head.get(size_at..size_at + 4)?.try_into().ok()?) as usize;
        let value = head.get(size_at + 4..size_at + 4 + size)?;
        match name {
            b"dataWindow" if size == 16 => {
                let int = |i: usize| {
                    i32::from_le_bytes(value[i * 4..i * 4 + 4].try_into().unwrap_or_default())
                };
                window = Some((int(0), int(1), int(2), int(3)));
            }
            // Scanlines per chunk, by compression (OpenEXR's table).
            b"compression" if size == 1 => {
                lines = Some(match value[0] {
                    0..=2 => 1,
                    3 | 5 => 16,
                    4 | 6 | 7 | 8 => 32,
                    9 => 256,
                    _ => return None,
                });
            }
            b"chunkCount" if size == 4 => {
                count = Some(u32::from_le_bytes(value.try_into().ok()?) as usize);
            }
            _ => {}
        }
        at = size_at + 4 + size;
    }
    let (x0, y0, x1, y1) = window?;
    let (width, height) = (
        u32::try_from(x1 - x0 + 1).ok()?,
        u32::try_from(y1 - y0 + 1).ok()?,
    );
    let chunks = match (count, tiled) {
        (Some(count), _) => count,
        (None, false) => (height as usize).div_ceil(lines?),
        (None, true) => return None,
    };
    let mut table = vec![0u8; chunks * 8];
    file.seek(SeekFrom::Start(at as u64)).ok()?;
    if file.read_exact(&mut table).is_err() {
        return Some((0, 0));
    }
    let last = table
        .chunks_exact(8)
        .map(|o| u64::from_le_bytes(o.try_into().unwrap_or_default()))
        .max()?;
    // A chunk: where it is (a scanline chunk: its first line; a tile: x, y
    // and level x, y, as i32s), its byte count (i32), the bytes.
    let header = if tiled { 20 } else { 8 };
    let mut chunk = [0u8; 20];
    file.seek(SeekFrom::Start(last)).ok()?;
    if last >= length || file.read_exact(&mut chunk[..header]).is_err() {
        return Some((0, 0));
    }
    let bytes = u64::from(u32::from_le_bytes(
        chunk[header - 4..header].try_into().ok()?,
    ));
    Some(if last + header as u64 + bytes == length {
        (width, height)
    } else {
        (0, 0)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cut(path: &Path, keep: usize) -> std::path::PathBuf {
        let bytes = std::fs::read(path).expect("read");
        let out = path.with_extension(format!(
            "cut.{}",
            path.extension().expect("ext").to_string_lossy()
        ));
        std::fs::write(&out, &bytes[..keep.min(bytes.len())]).expect("write");
        out
    }

    #[test]
    fn whole_files_pass_and_cut_ones_do_not() {
        let dir = tempfile::tempdir().expect("tempdir");
        for (name, height) in [("a.png", 37), ("a.exr", 37), ("b.exr", 3)] {
            let path = dir.path().join(name);
            let image = image::Rgba32FImage::from_fn(20, height, |x, y| {
                image::Rgba([x as f32 / 20.0, y as f32, 0.5, 1.0])
            });
            if name.ends_with("png") {
                image::DynamicImage::ImageRgba32F(image)
                    .to_rgba8()
                    .save(&path)
                    .expect("png");
            } else {
                image.save(&path).expect("exr");
            }
            assert!(is_whole(&path, (20, height)), "{name}");
            // Read from headers and trailers, not decoded.
            let mut file = File::open(&path).expect("open");
            let quick = if name.ends_with("png") {
                png(&path, &mut file)
            } else {
                exr(&mut file)
            };
            assert_eq!(quick, Some((20, height)), "{name}");
            assert!(!is_whole(&path, (21, height)), "{name}: another size");
            let length = std::fs::metadata(&path).expect("stat").len() as usize;
            for keep in [length - 1, length - 20, length / 2, 10, 0] {
                assert!(
                    !is_whole(&cut(&path, keep), (20, height)),
                    "{name} cut to {keep} of {length} bytes"
                );
            }
        }
        assert!(!is_whole(&dir.path().join("none.png"), (1, 1)));
    }
}
