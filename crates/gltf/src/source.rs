//! Where a glTF file's bytes come from: the GLB container (JSON and BIN
//! chunks), buffer and image URIs (base64 `data:` URIs and paths relative
//! to the file, percent-decoded), and image decoding to RGBA8.

use std::path::{Path, PathBuf};

use gltf::Document;

use super::GltfError;
use super::accessor::Buffers;
use spreadlight_render::material::maps::MapImage;

const GLB_MAGIC: &[u8; 4] = b"glTF";
const CHUNK_JSON: u32 = 0x4E4F_534A;
const CHUNK_BIN: u32 = 0x004E_4942;

fn u32_at(bytes: &[u8], at: usize) -> Option<u32> {
    let b = bytes.get(at..at.checked_add(4)?)?;
    Some(u32::from_le_bytes(b.try_into().ok()?))
}

/// The JSON of a glTF file and, for a GLB, its BIN chunk. Anything not
/// starting with the GLB magic is taken as JSON (a UTF-8 byte-order mark,
/// which the spec lets readers ignore, is dropped).
pub(super) fn split_glb(bytes: &[u8]) -> Result<(&[u8], Option<&[u8]>), String> {
    if !bytes.starts_with(GLB_MAGIC) {
        return Ok((bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes), None));
    }
    let header = |at| u32_at(bytes, at).ok_or("the file ends inside the 12-byte header");
    let version = header(4)?;
    if version != 2 {
        return Err(format!("version {version}; only glTF 2 is supported"));
    }
    let length = header(8)? as usize;
    let body = bytes.get(12..length).ok_or_else(|| {
        format!(
            "the header gives a length of {length} bytes, and the file has {}: it is truncated or damaged",
            bytes.len()
        )
    })?;

    let mut chunks = Vec::new();
    let mut at = 0;
    while at < body.len() {
        let (Some(len), Some(kind)) = (u32_at(body, at), u32_at(body, at + 4)) else {
            return Err(format!(
                "the file ends inside chunk {}'s header",
                chunks.len()
            ));
        };
        let data = (at + 8)
            .checked_add(len as usize)
            .and_then(|end| body.get(at + 8..end))
            .ok_or_else(|| {
                format!(
                    "chunk {} says it holds {len} bytes, past the end of the file",
                    chunks.len()
                )
            })?;
        chunks.push((kind, data));
        at += 8 + data.len();
    }
    let Some(&(CHUNK_JSON, json)) = chunks.first() else {
        return Err("the first chunk is not JSON".into());
    };
    // Unknown chunk types are skipped, as the spec asks.
    let bin = chunks
        .get(1)
        .and_then(|&(kind, d)| (kind == CHUNK_BIN).then_some(d));
    // Padding should be spaces; some writers use NULs, which JSON parsers refuse.
    let end = json.iter().rposition(|&b| b != 0).map_or(0, |p| p + 1);
    let json = json.get(..end).unwrap_or(json);
    Ok((json, bin))
}

/// Why the bytes behind a URI could not be had.
enum UriError {
    Missing(PathBuf, std::io::Error),
    Bad(String),
}

/// The bytes a URI points to: a base64 `data:` URI, or a file relative to
/// `base_dir` (the URI percent-decoded first).
fn read_uri(uri: &str, base_dir: Option<&Path>) -> Result<Vec<u8>, UriError> {
    if let Some(rest) = uri.strip_prefix("data:") {
        let Some((header, payload)) = rest.split_once(',') else {
            return Err(UriError::Bad(
                "the data URI has no `,` before its data".into(),
            ));
        };
        if !header.ends_with(";base64") {
            return Err(UriError::Bad(
                "only base64 data URIs are supported (`data:...;base64,...`)".into(),
            ));
        }
        return base64_decode(payload)
            .ok_or_else(|| UriError::Bad("the data URI is not valid base64".into()));
    }
    if let Some((scheme, _)) = uri.split_once(':')
        && scheme.len() > 1
        && scheme
            .bytes()
            .all(|b| b.is_ascii_alphanumeric() || b"+-.".contains(&b))
    {
        return Err(UriError::Bad(format!(
            "the URI scheme `{scheme}:` is not supported; use a relative path or a data URI"
        )));
    }
    let relative = percent_decode(uri)
        .ok_or_else(|| UriError::Bad(format!("`{uri}` is not a valid percent-encoded path")))?;
    let Some(base_dir) = base_dir else {
        return Err(UriError::Bad(format!(
            "`{relative}` is an external file, and the glTF was loaded from memory without a directory"
        )));
    };
    let file = base_dir.join(&relative);
    std::fs::read(&file).map_err(|e| UriError::Missing(file, e))
}

impl UriError {
    fn into_gltf(self, path: &Path, what: String) -> GltfError {
        match self {
            UriError::Missing(file, source) => GltfError::MissingFile {
                path: path.to_owned(),
                what,
                file,
                source,
            },
            UriError::Bad(reason) => GltfError::Uri {
                path: path.to_owned(),
                what,
                reason,
            },
        }
    }
}

/// The bytes of every buffer, by index; each is checked to hold at least
/// its declared `byteLength`.
pub(super) fn load_buffers(
    document: &Document,
    bin: Option<&[u8]>,
    base_dir: Option<&Path>,
    path: &Path,
) -> Result<Vec<Vec<u8>>, GltfError> {
    document
        .buffers()
        .map(|buffer| {
            let index = buffer.index();
            let data = match buffer.source() {
                gltf::buffer::Source::Bin => {
                    bin.map(<[u8]>::to_vec).ok_or_else(|| GltfError::Buffer {
                        path: path.to_owned(),
                        index,
                        reason: "it is the GLB's binary chunk, and the file has none".into(),
                    })?
                }
                gltf::buffer::Source::Uri(uri) => read_uri(uri, base_dir)
                    .map_err(|e| e.into_gltf(path, format!("buffer {index}")))?,
            };
            if data.len() < buffer.length() {
                return Err(GltfError::Buffer {
                    path: path.to_owned(),
                    index,
                    reason: format!(
                        "it declares {} bytes, and its data has {}",
                        buffer.length(),
                        data.len()
                    ),
                });
            }
            Ok(data)
        })
        .collect()
}

/// One image, decoded (PNG or JPEG, told by content) to RGBA8.
pub(super) fn decode_image(
    document: &Document,
    index: usize,
    buffers: &Buffers,
    base_dir: Option<&Path>,
    path: &Path,
) -> Result<MapImage, GltfError> {
    let image_error = |reason: String| GltfError::Image {
        path: path.to_owned(),
        index,
        reason,
    };
    // From the JSON: `gltf::Image::source` unwraps fields that validation
    // does not require (an image with neither a buffer view nor a URI).
    let json = document
        .as_json()
        .images
        .get(index)
        .ok_or_else(|| image_error("it does not exist".into()))?;
    let bytes = match (&json.buffer_view, &json.uri) {
        (Some(view), _) => {
            let view = document.views().nth(view.value()).ok_or_else(|| {
                image_error(format!("buffer view {} does not exist", view.value()))
            })?;
            buffers.view_bytes(&view).map_err(image_error)?.to_vec()
        }
        (None, Some(uri)) => {
            read_uri(uri, base_dir).map_err(|e| e.into_gltf(path, format!("image {index}")))?
        }
        (None, None) => return Err(image_error("it has neither a buffer view nor a URI".into())),
    };
    let decoded = image::load_from_memory(&bytes)
        .map_err(|e| image_error(format!("cannot decode: {e}")))?
        .to_rgba8();
    Ok(MapImage {
        width: decoded.width(),
        height: decoded.height(),
        rgba8: decoded.into_raw(),
    })
}

/// `%XX` escapes to bytes; the result must be UTF-8.
fn percent_decode(s: &str) -> Option<String> {
    let mut out = Vec::with_capacity(s.len());
    let mut bytes = s.bytes();
    while let Some(b) = bytes.next() {
        if b == b'%' {
            let hex = [bytes.next()?, bytes.next()?];
            let hex = std::str::from_utf8(&hex).ok()?;
            out.push(u8::from_str_radix(hex, 16).ok()?);
        } else {
            out.push(b);
        }
    }
    String::from_utf8(out).ok()
}

/// Standard base64 (RFC 4648, `+` and `/`), padding optional; `None` on any
/// other character.
fn base64_decode(s: &str) -> Option<Vec<u8>> {
    let s = s.trim_end_matches('=');
    let mut out = Vec::with_capacity(s.len() / 4 * 3 + 3);
    let mut acc = 0u32;
    let mut bits = 0;
    for c in s.bytes() {
        let v = match c {
            b'A'..=b'Z' => c - b'A',
            b'a'..=b'z' => c - b'a' + 26,
            b'0'..=b'9' => c - b'0' + 52,
            b'+' => 62,
            b'/' => 63,
            _ => return None,
        };
        acc = (acc << 6) | u32::from(v);
        bits += 6;
        if bits >= 8 {
            bits -= 8;
            out.push((acc >> bits) as u8);
            acc &= (1 << bits) - 1;
        }
    }
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base64_round_trips_known_values() {
        assert_eq!(base64_decode("").unwrap(), b"");
        assert_eq!(base64_decode("Zg==").unwrap(), b"f");
        assert_eq!(base64_decode("Zm8=").unwrap(), b"fo");
        assert_eq!(base64_decode("Zm9v").unwrap(), b"foo");
        assert_eq!(base64_decode("Zm9vYmFy").unwrap(), b"foobar");
        assert_eq!(base64_decode("AP8/+w").unwrap(), [0x00, 0xff, 0x3f, 0xfb]);
        assert_eq!(base64_decode("Zm9v!"), None);
    }

    #[test]
    fn percent_decoding() {
        assert_eq!(percent_decode("a%20b.bin").as_deref(), Some("a b.bin"));
        assert_eq!(percent_decode("%C3%A9.png").as_deref(), Some("é.png"));
        assert_eq!(percent_decode("bad%2"), None);
        assert_eq!(percent_decode("bad%zz"), None);
        assert_eq!(percent_decode("%FF"), None);
    }

    #[test]
    fn uris() {
        assert!(
            matches!(read_uri("data:application/octet-stream;base64,AAEC", None), Ok(b) if b == [0, 1, 2])
        );
        assert!(
            matches!(read_uri("data:text/plain,hello", None), Err(UriError::Bad(m)) if m.contains("base64"))
        );
        assert!(
            matches!(read_uri("https://example.com/a.bin", None), Err(UriError::Bad(m)) if m.contains("https"))
        );
        assert!(
            matches!(read_uri("a.bin", None), Err(UriError::Bad(m)) if m.contains("from memory"))
        );
        let dir = tempfile::tempdir().unwrap();
        assert!(
            matches!(read_uri("nope.bin", Some(dir.path())), Err(UriError::Missing(f, _)) if f.ends_with("nope.bin"))
        );
    }

    #[test]
    fn glb_container_errors() {
        assert!(split_glb(b"glTF").unwrap_err().contains("header"));
        let mut glb = b"glTF".to_vec();
        glb.extend(1u32.to_le_bytes());
        glb.extend(12u32.to_le_bytes());
        assert!(split_glb(&glb).unwrap_err().contains("version 1"));
        glb[4] = 2;
        glb[8] = 200;
        assert!(split_glb(&glb).unwrap_err().contains("truncated"));
        glb[8] = 12;
        assert!(split_glb(&glb).unwrap_err().contains("not JSON"));
        // A header claiming less than itself must not underflow.
        glb[8] = 3;
        assert!(split_glb(&glb).is_err());
        let (json, bin) = split_glb(b"\xEF\xBB\xBF{}").unwrap();
        assert_eq!((json, bin), (&b"{}"[..], None));
    }
}
