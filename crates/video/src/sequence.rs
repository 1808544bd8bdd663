//! Image sequences by pattern: `frames/f_####.png` is every file of
//! `frames/` named `f_`, a number, `.png`, in the order of their numbers
//! (the run of `#`s says where the number stands; numbers may be longer
//! than the run, gaps are skipped). Decoded with the `image` crate: PNG, EXR
//! (tone-clamped to 8 bits), JPEG, ...

use std::path::{Path, PathBuf};
use std::sync::Arc;

use crate::error::MediaError;
use crate::frame::{Frame, VideoInfo};

pub struct ImageSequence {
    pattern: PathBuf,
    files: Vec<PathBuf>,
    info: VideoInfo,
}

impl ImageSequence {
    /// Whether a file name is a pattern rather than a file.
    pub fn is_pattern(path: &Path) -> bool {
        path.file_name()
            .is_some_and(|n| n.to_string_lossy().contains('#'))
    }

    /// The files matching `pattern`, played at `fps`; the first file sets the size.
    pub fn open(pattern: &Path, fps: f64) -> Result<Self, MediaError> {
        let name = pattern
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        let (Some(first), Some(last)) = (name.find('#'), name.rfind('#')) else {
            return Err(MediaError::EmptySequence(pattern.to_path_buf()));
        };
        let (prefix, suffix) = (&name[..first], &name[last + 1..]);
        let digits = last + 1 - first;
        let dir = pattern
            .parent()
            .filter(|d| !d.as_os_str().is_empty())
            .unwrap_or(Path::new("."));
        let entries = std::fs::read_dir(dir).map_err(|e| MediaError::Image {
            path: pattern.to_path_buf(),
            message: format!("cannot list {}: {e}", dir.display()),
        })?;
        let mut numbered: Vec<(u64, PathBuf)> = entries
            .filter_map(|e| e.ok())
            .filter_map(|e| {
                let file = e.file_name().to_string_lossy().into_owned();
                let number = file.strip_prefix(prefix)?.strip_suffix(suffix)?;
                (number.len() >= digits && number.bytes().all(|b| b.is_ascii_digit()))
                    .then(|| number.parse().ok())
                    .flatten()
                    .map(|n| (n, e.path()))
            })
            .collect();
        numbered.sort();
        let files: Vec<PathBuf> = numbered.into_iter().map(|(_, p)| p).collect();
        let first = files
            .first()
            .ok_or_else(|| MediaError::EmptySequence(pattern.to_path_buf()))?;
        let (width, height) = image::image_dimensions(first).map_err(|e| MediaError::Image {
            path: first.clone(),
            message: e.to_string(),
        })?;
        if !(fps.is_finite() && fps > 0.0) {
            return Err(MediaError::Image {
                path: pattern.to_path_buf(),
                message: format!("a sequence plays at a positive frame rate, not {fps}"),
            });
        }
        Ok(ImageSequence {
            pattern: pattern.to_path_buf(),
            info: VideoInfo {
                width,
                height,
                fps,
                frames: files.len() as u64,
            },
            files,
        })
    }

    pub fn info(&self) -> VideoInfo {
        self.info
    }

    /// The pattern it was opened with.
    pub fn pattern(&self) -> &Path {
        &self.pattern
    }

    pub fn frame(&mut self, index: u64) -> Result<Arc<Frame>, MediaError> {
        let index = index.min(self.info.frames.saturating_sub(1));
        let path = &self.files[index as usize];
        let image = image::open(path)
            .map_err(|e| MediaError::Image {
                path: path.clone(),
                message: e.to_string(),
            })?
            .to_rgba8();
        Ok(Arc::new(Frame {
            index,
            width: image.width(),
            height: image.height(),
            rgba: image.into_raw(),
        }))
    }
}
