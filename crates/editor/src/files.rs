//! Where the editor keeps things on disk: the recent-files list and the
//! autosave recovery files. Patches themselves go through the graph crate's
//! atomic save.

use std::fs;
use std::path::{Path, PathBuf};
use std::time::SystemTime;

use spreadlight_graph::{FormatError, Patch, format};
use thiserror::Error;

#[derive(Debug, Error)]
pub enum FileError {
    #[error(transparent)]
    Format(#[from] FormatError),
    #[error("{path}: {source}")]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
}

/// How many recent files the File menu lists.
pub const RECENT_MAX: usize = 10;

/// The editor's own directory: `SPREADLIGHT_CONFIG_DIR` if set (tests point it
/// at a temporary directory), else `$XDG_CONFIG_HOME/spreadlight`, else
/// `~/.config/spreadlight`.
pub fn config_dir() -> PathBuf {
    if let Some(dir) = std::env::var_os("SPREADLIGHT_CONFIG_DIR") {
        return PathBuf::from(dir);
    }
    if let Some(dir) = std::env::var_os("XDG_CONFIG_HOME") {
        return PathBuf::from(dir).join("spreadlight");
    }
    match std::env::var_os("HOME") {
        Some(home) => PathBuf::from(home).join(".config").join("spreadlight"),
        None => std::env::temp_dir().join("spreadlight"),
    }
}

/// The recovery file of a patch: hidden beside it (`.NAME.ron.autosave`), so
/// it follows the patch and is found again however the editor is started.
/// An untitled patch autosaves into the config directory.
pub fn recovery_path(patch: Option<&Path>, config: &Path) -> PathBuf {
    match patch.and_then(|p| Some((p.parent()?, p.file_name()?))) {
        Some((dir, name)) => {
            let mut hidden = std::ffi::OsString::from(".");
            hidden.push(name);
            hidden.push(".autosave");
            dir.join(hidden)
        }
        None => config.join("untitled.ron.autosave"),
    }
}

fn modified(path: &Path) -> Option<SystemTime> {
    fs::metadata(path).and_then(|m| m.modified()).ok()
}

/// The recovery file to offer on start: it exists and is newer than the patch
/// (or the patch is gone). A recovery file older than its patch is stale: the
/// patch was saved after it.
pub fn pending_recovery(patch: Option<&Path>, config: &Path) -> Option<PathBuf> {
    let recovery = recovery_path(patch, config);
    let written = modified(&recovery)?;
    match patch.and_then(modified) {
        Some(saved) if saved > written => None,
        _ => Some(recovery),
    }
}

pub fn write_recovery(patch: &Patch, path: &Path) -> Result<(), FileError> {
    if let Some(dir) = path.parent() {
        fs::create_dir_all(dir).map_err(|source| FileError::Io {
            path: dir.to_owned(),
            source,
        })?;
    }
    format::save(patch, path)?;
    Ok(())
}

pub fn remove_recovery(path: &Path) {
    // Missing is the normal case: nothing was autosaved since the last save.
    let _ = fs::remove_file(path);
}

/// The recent-files list, most recent first.
pub fn load_recent(config: &Path) -> Vec<PathBuf> {
    let Ok(text) = fs::read_to_string(config.join("recent.ron")) else {
        return Vec::new();
    };
    ron::from_str(&text).unwrap_or_default()
}

/// Put `path` first in the list and store it.
pub fn remember_recent(config: &Path, recent: &mut Vec<PathBuf>, path: &Path) {
    let path = fs::canonicalize(path).unwrap_or_else(|_| path.to_owned());
    recent.retain(|p| p != &path);
    recent.insert(0, path);
    recent.truncate(RECENT_MAX);
    if fs::create_dir_all(config).is_ok()
        && let Ok(text) = ron::to_string(recent)
    {
        // The list is a convenience: failing to store it must not disturb editing.
        let _ = fs::write(config.join("recent.ron"), text);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn recovery_sits_beside_the_patch_hidden() {
        let p = recovery_path(Some(Path::new("/a/b/scene.ron")), Path::new("/cfg"));
        assert_eq!(p, Path::new("/a/b/.scene.ron.autosave"));
        let u = recovery_path(None, Path::new("/cfg"));
        assert_eq!(u, Path::new("/cfg/untitled.ron.autosave"));
    }

    #[test]
    fn only_a_recovery_newer_than_the_patch_is_offered() {
        let dir = tempfile::tempdir().expect("tempdir");
        let patch = dir.path().join("p.ron");
        format::save(&Patch::default(), &patch).expect("save");
        assert_eq!(pending_recovery(Some(&patch), dir.path()), None);
        let rec = recovery_path(Some(&patch), dir.path());
        write_recovery(&Patch::default(), &rec).expect("autosave");
        // File times have coarse resolution on some file systems: set them explicitly.
        let old = SystemTime::now() - std::time::Duration::from_secs(60);
        fs::File::options()
            .write(true)
            .open(&patch)
            .and_then(|f| f.set_modified(old))
            .expect("touch");
        assert_eq!(
            pending_recovery(Some(&patch), dir.path()),
            Some(rec.clone())
        );
        format::save(&Patch::default(), &patch).expect("save again");
        fs::File::options()
            .write(true)
            .open(&rec)
            .and_then(|f| f.set_modified(old))
            .expect("touch");
        assert_eq!(pending_recovery(Some(&patch), dir.path()), None);
    }

    #[test]
    fn recent_files_are_most_recent_first_without_duplicates() {
        let dir = tempfile::tempdir().expect("tempdir");
        let mut recent = Vec::new();
        for name in ["a.ron", "b.ron", "a.ron"] {
            remember_recent(dir.path(), &mut recent, &dir.path().join(name));
        }
        let names: Vec<_> = load_recent(dir.path())
            .iter()
            .map(|p| p.file_name().expect("name").to_owned())
            .collect();
        assert_eq!(names, ["a.ron", "b.ron"]);
    }
}
