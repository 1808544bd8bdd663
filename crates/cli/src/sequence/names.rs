//! Where frames go: `-o` names a frame sequence (`shot_####.exr`, the `#`s
//! padding the frame number, or `shot_{frame}.png`), one image (no frame
//! token: only for one frame), or a video (`.mp4`, `.mov`). `{name}` stands
//! for the Output node's Name; with several outputs and no `{name}`, each
//! sequence goes in a folder named for its output beside the path.

use std::path::{Path, PathBuf};

/// What `-o` asks for.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Target {
    /// One file per frame.
    Frames(Template),
    /// One image: the range's only frame.
    Image(Template),
    /// Frames streamed to ffmpeg.
    Video(Template, VideoKind),
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VideoKind {
    /// H.264 in MP4.
    Mp4,
    /// ProRes 422 HQ in QuickTime.
    ProRes,
}

/// The `-o` text, checked: it has a known extension.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Template(String);

impl Target {
    pub fn parse(path: &Path) -> Result<Target, String> {
        let text = path.to_string_lossy().into_owned();
        let extension = path
            .extension()
            .map(|e| e.to_string_lossy().to_ascii_lowercase())
            .unwrap_or_default();
        let framed = text.contains('#') || text.contains("{frame}");
        let template = Template(text.clone());
        match extension.as_str() {
            "png" | "exr" if framed => Ok(Target::Frames(template)),
            "png" | "exr" => Ok(Target::Image(template)),
            "mp4" | "mov" if framed => Err(format!(
                "`{text}`: a video is one file; leave the frame number out of its name"
            )),
            "mp4" => Ok(Target::Video(template, VideoKind::Mp4)),
            "mov" => Ok(Target::Video(template, VideoKind::ProRes)),
            _ => Err(format!(
                "`{text}`: write images (.png, .exr: add `####` or `{{frame}}` for a sequence) or a video (.mp4, .mov)"
            )),
        }
    }

    pub fn template(&self) -> &Template {
        match self {
            Target::Frames(t) | Target::Image(t) | Target::Video(t, _) => t,
        }
    }
}

impl Template {
    /// The path of `frame` of the output `name`; `several` when the patch
    /// writes more than one sequence (they must not share files).
    pub fn path(&self, name: &str, several: bool, frame: u64) -> PathBuf {
        let mut text = self.0.replace("{name}", name);
        if several && !self.0.contains("{name}") {
            let path = PathBuf::from(&text);
            let file = path.file_name().map(|f| f.to_owned()).unwrap_or_default();
            text = path
                .with_file_name(name)
                .join(file)
                .to_string_lossy()
                .into_owned();
        }
        PathBuf::from(pad_hashes(
            &text.replace("{frame}", &format!("{frame:05}")),
            frame,
        ))
    }
}

/// Each run of `#` replaced by `frame`, zero-padded to the run's length.
fn pad_hashes(text: &str, frame: u64) -> String {
    let mut out = String::with_capacity(text.len() + 8);
    let mut run = 0;
    for c in text.chars().chain(std::iter::once('\0')) {
        if c == '#' {
            run += 1;
            continue;
        }
        if run > 0 {
            out.push_str(&format!("{frame:0run$}"));
            run = 0;
        }
        if c != '\0' {
            out.push(c);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn target(s: &str) -> Result<Target, String> {
        Target::parse(Path::new(s))
    }

    #[test]
    fn hashes_pad_and_frame_tokens_fill_in() {
        let t = target("out/shot_####.exr").expect("ok");
        assert!(matches!(t, Target::Frames(_)));
        let p = |t: &Target, name, several, frame| {
            t.template()
                .path(name, several, frame)
                .to_string_lossy()
                .into_owned()
        };
        assert_eq!(p(&t, "beauty", false, 7), "out/shot_0007.exr");
        assert_eq!(p(&t, "beauty", false, 123_456), "out/shot_123456.exr");
        assert_eq!(p(&t, "beauty", true, 7), "out/beauty/shot_0007.exr");
        let t = target("out/{name}.{frame}.png").expect("ok");
        assert_eq!(p(&t, "depth", true, 3), "out/depth.00003.png");
        assert_eq!(p(&target("a.png").expect("ok"), "x", false, 9), "a.png");
    }

    #[test]
    fn kinds_come_from_the_extension() {
        assert!(matches!(target("x.png"), Ok(Target::Image(_))));
        assert!(matches!(
            target("x.MP4"),
            Ok(Target::Video(_, VideoKind::Mp4))
        ));
        assert!(matches!(
            target("x.mov"),
            Ok(Target::Video(_, VideoKind::ProRes))
        ));
        assert!(
            target("x_####.mp4")
                .expect_err("no frames in a video")
                .contains("one file")
        );
        assert!(target("x.jpg").expect_err("unknown").contains(".png, .exr"));
    }
}
