//! `-o out.mp4` / `-o out.mov`: frames streamed to ffmpeg over a pipe as raw
//! 8-bit RGBA (nothing written to disk first). The video is written to a
//! partial file and renamed when ffmpeg has finished it, like every frame.

use std::ffi::OsString;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdin, Command, Stdio};

use anyhow::{Context, bail};
use spreadlight_render::image_io::{Encoding, to_rgba8};
use spreadlight_render::readback::ImageF32;

use super::files::partial_path;
use super::names::VideoKind;

/// The ffmpeg to run: `SPREADLIGHT_FFMPEG` or `ffmpeg` on the PATH.
fn ffmpeg() -> OsString {
    std::env::var_os("SPREADLIGHT_FFMPEG").unwrap_or_else(|| "ffmpeg".into())
}

/// A video being written.
pub struct Video {
    child: Child,
    stdin: Option<ChildStdin>,
    partial: PathBuf,
    path: PathBuf,
    size: (u32, u32),
}

impl Video {
    /// Start ffmpeg writing `path` from frames of `size` at `fps`.
    /// Fails with what to install when ffmpeg is missing.
    pub fn open(path: &Path, kind: VideoKind, size: (u32, u32), fps: f64) -> anyhow::Result<Video> {
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir)
                .with_context(|| format!("cannot create {}", dir.display()))?;
        }
        let partial = partial_path(path);
        let mut command = Command::new(ffmpeg());
        command
            .args(["-hide_banner", "-loglevel", "error", "-y"])
            .args(["-f", "rawvideo", "-pix_fmt", "rgba"])
            .args(["-s", &format!("{}x{}", size.0, size.1)])
            .args(["-framerate", &fps.to_string(), "-i", "-"]);
        match kind {
            // yuv420p wants even sizes: pad by a pixel where needed.
            VideoKind::Mp4 => command.args([
                "-c:v",
                "libx264",
                "-pix_fmt",
                "yuv420p",
                "-crf",
                "16",
                "-vf",
                "pad=ceil(iw/2)*2:ceil(ih/2)*2",
                "-movflags",
                "+faststart",
                "-f",
                "mp4",
            ]),
            VideoKind::ProRes => command.args([
                "-c:v",
                "prores_ks",
                "-profile:v",
                "3",
                "-pix_fmt",
                "yuv422p10le",
                "-f",
                "mov",
            ]),
        };
        command
            .arg(&partial)
            .stdin(Stdio::piped())
            .stdout(Stdio::null())
            .stderr(Stdio::inherit());
        let mut child = match command.spawn() {
            Ok(child) => child,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => bail!(
                "cannot write {}: ffmpeg is not installed (`{}` not found). Install Debian's `ffmpeg` \
                 package (`apt-get install ffmpeg`), or write frames instead (`-o out/shot_####.png`)",
                path.display(),
                ffmpeg().to_string_lossy()
            ),
            Err(e) => return Err(e).context("cannot start ffmpeg"),
        };
        let stdin = child.stdin.take();
        Ok(Video {
            child,
            stdin,
            partial,
            path: path.to_owned(),
            size,
        })
    }

    /// The next frame.
    pub fn push(&mut self, image: &ImageF32, encoding: Encoding) -> anyhow::Result<()> {
        if (image.width, image.height) != self.size {
            bail!(
                "a frame of {}x{} in a video of {}x{}",
                image.width,
                image.height,
                self.size.0,
                self.size.1
            );
        }
        let stdin = self.stdin.as_mut().context("ffmpeg's input is closed")?;
        stdin
            .write_all(&to_rgba8(image, encoding))
            .with_context(|| format!("ffmpeg stopped taking frames for {}", self.path.display()))
    }

    /// Close the stream, wait for ffmpeg and move the video into place.
    pub fn finish(mut self) -> anyhow::Result<PathBuf> {
        drop(self.stdin.take());
        let status = self.child.wait().context("ffmpeg")?;
        if !status.success() {
            let _ = std::fs::remove_file(&self.partial);
            bail!("ffmpeg failed ({status}) writing {}", self.path.display());
        }
        std::fs::rename(&self.partial, &self.path)
            .with_context(|| format!("cannot move the video to {}", self.path.display()))?;
        Ok(self.path.clone())
    }

    /// Stop ffmpeg and remove the partial video.
    pub fn abort(mut self) {
        drop(self.stdin.take());
        let _ = self.child.kill();
        let _ = self.child.wait();
        let _ = std::fs::remove_file(&self.partial);
    }
}
