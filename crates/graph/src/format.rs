//! Reading and writing patches as `.ron`.
//!
//! Loading never panics and never guesses: a file that is not a patch is an
//! error naming the file, line and column; a file from a newer format is
//! refused before anything in it is interpreted. Saving is atomic: the text is
//! written to a temporary file beside the target, flushed, then renamed over it.

use std::fs;
use std::io::Write;
use std::path::{Path, PathBuf};

use serde::Deserialize;
use thiserror::Error;

use crate::document::{FORMAT_VERSION, Patch};

#[derive(Debug, Error)]
pub enum FormatError {
    #[error("{path}: cannot read the patch: {source}")]
    Read {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error(
        "{path}: the file is empty; a patch starts with `(version: {FORMAT_VERSION}, nodes: [...], links: [...])`"
    )]
    Empty { path: PathBuf },
    #[error("{path}:{line}:{col}: {message}")]
    Syntax {
        path: PathBuf,
        line: usize,
        col: usize,
        message: String,
    },
    #[error(
        "{path}: written by a newer Spreadlight (patch format version {found}); this build reads versions up to {FORMAT_VERSION}: update Spreadlight to open it"
    )]
    NewerVersion { path: PathBuf, found: u32 },
    #[error("{path}: cannot write the patch: {source}")]
    Write {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("cannot encode the patch as RON: {0}")]
    Encode(String),
}

/// Parse patch text. `path` only names the source in errors.
pub fn from_str(text: &str, path: &Path) -> Result<Patch, FormatError> {
    if text.trim().is_empty() {
        return Err(FormatError::Empty {
            path: path.to_owned(),
        });
    }
    // Read the version alone first: a newer file may use syntax this build
    // cannot parse, and "update Spreadlight" is then the only useful error.
    #[derive(Deserialize)]
    struct VersionOnly {
        version: u32,
    }
    if let Ok(VersionOnly { version }) = ron::from_str::<VersionOnly>(text)
        && version > FORMAT_VERSION
    {
        return Err(FormatError::NewerVersion {
            path: path.to_owned(),
            found: version,
        });
    }
    ron::from_str::<Patch>(text).map_err(|e| FormatError::Syntax {
        path: path.to_owned(),
        line: e.span.start.line,
        col: e.span.start.col,
        message: e.code.to_string(),
    })
}

/// Read and parse a patch file.
pub fn load(path: &Path) -> Result<Patch, FormatError> {
    let text = fs::read_to_string(path).map_err(|source| FormatError::Read {
        path: path.to_owned(),
        source,
    })?;
    from_str(&text, path)
}

/// The canonical text of a patch: what [`save`] writes. Stable, so saved
/// patches diff well and load-save-load is the identity.
pub fn to_string(patch: &Patch) -> Result<String, FormatError> {
    let upgraded;
    let patch = if patch.version < patch.required_version() {
        upgraded = versioned(patch.clone());
        &upgraded
    } else {
        patch
    };
    let config = ron::ser::PrettyConfig::new()
        .depth_limit(4)
        .indentor("    ")
        .separate_tuple_members(false);
    let mut text = ron::ser::to_string_pretty(patch, config)
        .map_err(|e| FormatError::Encode(e.to_string()))?;
    text.push('\n');
    Ok(text)
}

/// The patch, and every inline subpatch in it, at least at the version its contents need.
fn versioned(mut patch: Patch) -> Patch {
    patch.version = patch.version.max(patch.required_version());
    patch.subpatches = std::mem::take(&mut patch.subpatches)
        .into_iter()
        .map(|(name, sub)| (name, versioned(sub)))
        .collect();
    patch
}

/// Write a patch atomically: a crash during save leaves the old file or the
/// new one, never half of either.
pub fn save(patch: &Patch, path: &Path) -> Result<(), FormatError> {
    let text = to_string(patch)?;
    write_atomic(path, text.as_bytes()).map_err(|source| FormatError::Write {
        path: path.to_owned(),
        source,
    })
}

fn write_atomic(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let dir = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    let file_name = path
        .file_name()
        .ok_or_else(|| std::io::Error::other("the path names no file"))?;
    // The temporary file sits in the same directory, so the rename stays on one file system and is atomic.
    let mut tmp_name = file_name.to_owned();
    tmp_name.push(format!(".tmp{}", std::process::id()));
    let tmp = dir.join(tmp_name);
    let result = (|| {
        let mut file = fs::File::create(&tmp)?;
        file.write_all(bytes)?;
        file.sync_all()?;
        fs::rename(&tmp, path)
    })();
    if result.is_err() {
        let _ = fs::remove_file(&tmp);
    }
    result
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::document::{LinkDoc, NodeDoc};

    fn sample() -> Patch {
        let mut p = Patch::default();
        p.add(
            NodeDoc::new(1, "LFO")
                .at(10.0, 20.0)
                .with("Period", vec![2.0f32]),
        );
        p.add(NodeDoc::new(2, "Probe").with("Name", vec!["phase".to_owned()]));
        p.links.push(LinkDoc::new(1, "Output", 2, "Input"));
        p
    }

    #[test]
    fn round_trip_is_identity() {
        let p = sample();
        let text = to_string(&p).expect("encode");
        let back = from_str(&text, Path::new("mem.ron")).expect("decode");
        assert_eq!(back, p);
        assert_eq!(to_string(&back).expect("encode"), text);
    }

    #[test]
    fn comments_frames_and_bypass_round_trip_and_need_version_3() {
        use crate::organise::{CommentDoc, FrameDoc};
        let mut p = sample();
        p.version = 1;
        assert_eq!(
            to_string(&p).expect("encode").lines().nth(1),
            Some("    version: 1,")
        );
        p.comments
            .push(CommentDoc::new(0.0, -40.0, "# Phase\n- **LFO** drives it"));
        let mut frame = FrameDoc::new("Source", (-10.0, -10.0), (80.0, 60.0));
        frame.color = (120, 60, 40);
        p.frames.push(frame);
        p.nodes[1].bypass = true;
        let text = to_string(&p).expect("encode");
        let back = from_str(&text, Path::new("mem.ron")).expect("decode");
        assert_eq!(back.version, 3, "{text}");
        assert_eq!(back.comments, p.comments);
        assert_eq!(back.frames, p.frames);
        assert!(back.nodes[1].bypass && !back.nodes[0].bypass);
        assert_eq!(to_string(&back).expect("encode"), text);
        // A file without them (an older one) loads with none.
        let old = from_str(
            "(version: 2, nodes: [(id: 1, type: \"LFO\")])",
            Path::new("old.ron"),
        )
        .expect("decode");
        assert!(old.comments.is_empty() && old.frames.is_empty() && !old.nodes[0].bypass);
    }

    #[test]
    fn syntax_errors_carry_line_and_column() {
        let err = from_str(
            "(version: 1,\n nodes: [\n (id: 1, type: LFO) ],\n)",
            Path::new("bad.ron"),
        )
        .unwrap_err();
        match err {
            FormatError::Syntax {
                line,
                col,
                ref path,
                ..
            } => {
                assert_eq!(line, 3);
                assert!(col > 1);
                assert_eq!(path, Path::new("bad.ron"));
            }
            other => panic!("wrong error {other:?}"),
        }
    }

    #[test]
    fn newer_versions_are_refused_by_name() {
        let err = from_str(
            "(version: 99, nodes: [], links: [], future: 3)",
            Path::new("new.ron"),
        )
        .unwrap_err();
        assert!(
            matches!(err, FormatError::NewerVersion { found: 99, .. }),
            "{err}"
        );
        assert!(err.to_string().contains("update Spreadlight"));
    }

    #[test]
    fn atomic_save_replaces_and_leaves_no_temporary() {
        let dir = tempfile::tempdir().expect("tempdir");
        let path = dir.path().join("p.ron");
        fs::write(&path, "old").expect("write");
        save(&sample(), &path).expect("save");
        assert_eq!(load(&path).expect("load"), sample());
        let names: Vec<_> = fs::read_dir(dir.path())
            .expect("ls")
            .map(|e| e.expect("entry").file_name())
            .collect();
        assert_eq!(names, vec![std::ffi::OsString::from("p.ron")]);
    }

    #[test]
    fn failed_save_keeps_the_old_file() {
        let dir = tempfile::tempdir().expect("tempdir");
        // A directory where the file should be: rename must fail, the directory stays.
        let path = dir.path().join("taken");
        fs::create_dir(&path).expect("mkdir");
        assert!(save(&sample(), &path).is_err());
        assert!(path.is_dir());
        assert_eq!(fs::read_dir(dir.path()).expect("ls").count(), 1);
    }
}
