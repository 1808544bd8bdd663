//! Where the editor keeps things on disk: the recent-files list and the
//! autosave recovery files (the patch's, and beside it its subpatch files'
//! unsaved edits). Patches themselves go through the graph crate's atomic save.

use std::fs;
use std::path::{Path, PathBuf};
use std::time::SystemTime;

use serde::{Deserialize, Serialize};
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
    #[error("{path}: not a subpatch-files autosave: {message}")]
    Modules { path: PathBuf, message: String },
}

/// How many recent files the File menu lists.
pub const RECENT_MAX: usize = 10;

/// The editor's own directory: `SPREADLIGHT_CONFIG_DIR` if set (tests point it
/// at a temporary directory), else `$XDG_CONFIG_HOME/spreadlight`, else
/// `~/.config/spreadlight`; `spreadlight_dirs` knows them all.
pub use spreadlight_dirs::config_dir;

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

/// Remove a recovery file and its subpatch files' autosave.
pub fn remove_recovery(path: &Path) {
    // Missing is the normal case: nothing was autosaved since the last save.
    let _ = fs::remove_file(path);
    let _ = fs::remove_file(module_recovery_path(path));
}

/// Where the unsaved edits of the subpatch files opened in place go: beside
/// the patch's recovery file (`.NAME.ron.modules.autosave`), not beside the
/// module files, because it is restarting the editor on this patch that
/// offers them back, and a module shared by two patches may be edited from
/// either.
pub fn module_recovery_path(recovery: &Path) -> PathBuf {
    recovery.with_extension("modules.autosave")
}

/// One subpatch file's unsaved edits, as autosaved.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ModuleEdit {
    /// The node type the file defines (its stem).
    pub name: String,
    /// The module file the edits belong in.
    pub path: PathBuf,
    /// The file's document as edited.
    pub patch: Patch,
}

/// The subpatch files' autosave on disk: a versioned list of edits.
#[derive(Serialize, Deserialize)]
struct ModuleAutosave {
    version: u32,
    files: Vec<ModuleEdit>,
}

const MODULE_AUTOSAVE_VERSION: u32 = 1;

/// Autosave the subpatch files' edits beside `recovery` (none: remove it).
/// Written atomically, as patches are: a kill mid-write leaves the last one.
pub fn write_module_recovery(edits: &[ModuleEdit], recovery: &Path) -> Result<(), FileError> {
    let path = module_recovery_path(recovery);
    if edits.is_empty() {
        let _ = fs::remove_file(&path);
        return Ok(());
    }
    let io = |source| FileError::Io {
        path: path.clone(),
        source,
    };
    let autosave = ModuleAutosave {
        version: MODULE_AUTOSAVE_VERSION,
        files: edits.to_vec(),
    };
    let text =
        ron::ser::to_string_pretty(&autosave, ron::ser::PrettyConfig::new()).map_err(|e| {
            FileError::Modules {
                path: path.clone(),
                message: e.to_string(),
            }
        })?;
    let dir = path.parent().unwrap_or(Path::new("."));
    fs::create_dir_all(dir).map_err(io)?;
    let mut tmp = tempfile::NamedTempFile::new_in(dir).map_err(io)?;
    std::io::Write::write_all(&mut tmp, text.as_bytes()).map_err(io)?;
    tmp.as_file().sync_all().map_err(io)?;
    tmp.persist(&path).map_err(|e| io(e.error))?;
    Ok(())
}

/// The subpatch files' edits autosaved beside `recovery`: those to restore,
/// and the module files saved since the autosave (their edits are stale, as
/// a recovery file older than its patch is, and are not offered).
#[derive(Debug, Default, PartialEq)]
pub struct ModuleRecovery {
    pub edits: Vec<ModuleEdit>,
    pub stale: Vec<PathBuf>,
}

pub fn load_module_recovery(recovery: &Path) -> Result<ModuleRecovery, FileError> {
    let path = module_recovery_path(recovery);
    let text = match fs::read_to_string(&path) {
        Ok(text) => text,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(ModuleRecovery::default()),
        Err(source) => return Err(FileError::Io { path, source }),
    };
    let autosave: ModuleAutosave = ron::from_str(&text).map_err(|e| FileError::Modules {
        path: path.clone(),
        message: e.to_string(),
    })?;
    if autosave.version > MODULE_AUTOSAVE_VERSION {
        return Err(FileError::Modules {
            path,
            message: format!(
                "written by a newer Spreadlight (version {}, this build reads {MODULE_AUTOSAVE_VERSION})",
                autosave.version
            ),
        });
    }
    let written = modified(&path);
    let mut recovery = ModuleRecovery::default();
    for edit in autosave.files {
        match (modified(&edit.path), written) {
            (Some(saved), Some(written)) if saved > written => recovery.stale.push(edit.path),
            _ => recovery.edits.push(edit),
        }
    }
    Ok(recovery)
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

    fn set_modified(path: &Path, when: SystemTime) {
        fs::File::options()
            .write(true)
            .open(path)
            .and_then(|f| f.set_modified(when))
            .expect("touch");
    }

    #[test]
    fn subpatch_file_edits_autosave_beside_the_recovery_and_stale_ones_are_left_out() {
        let dir = tempfile::tempdir().expect("tempdir");
        let rec = recovery_path(Some(&dir.path().join("p.ron")), dir.path());
        assert_eq!(
            module_recovery_path(&rec),
            dir.path().join(".p.ron.modules.autosave")
        );
        let (a, b) = (dir.path().join("A.ron"), dir.path().join("B.ron"));
        let mut edited = Patch::default();
        edited.add(spreadlight_graph::NodeDoc::new(1, "LFO"));
        for file in [&a, &b] {
            format::save(&Patch::default(), file).expect("module");
            set_modified(file, SystemTime::now() - std::time::Duration::from_secs(60));
        }
        let edits: Vec<ModuleEdit> = [("A", &a), ("B", &b)]
            .into_iter()
            .map(|(name, path)| ModuleEdit {
                name: name.to_owned(),
                path: path.clone(),
                patch: edited.clone(),
            })
            .collect();
        write_module_recovery(&edits, &rec).expect("autosave");
        let loaded = load_module_recovery(&rec).expect("reads");
        assert_eq!(loaded.edits, edits, "lossless");
        assert!(loaded.stale.is_empty());

        // B saved after the autosave: its edits are stale, A's still offered.
        set_modified(&b, SystemTime::now() + std::time::Duration::from_secs(60));
        let loaded = load_module_recovery(&rec).expect("reads");
        assert_eq!(loaded.edits, edits[..1]);
        assert_eq!(loaded.stale, [b]);

        // No edits left: the file goes; so does it with the patch's recovery.
        write_module_recovery(&[], &rec).expect("removes");
        assert!(!module_recovery_path(&rec).exists());
        assert_eq!(
            load_module_recovery(&rec).expect("none"),
            ModuleRecovery::default()
        );
        write_module_recovery(&edits, &rec).expect("autosave");
        write_recovery(&Patch::default(), &rec).expect("autosave");
        remove_recovery(&rec);
        assert!(!rec.exists() && !module_recovery_path(&rec).exists());
    }

    #[test]
    fn a_damaged_subpatch_files_autosave_is_an_error_naming_it() {
        let dir = tempfile::tempdir().expect("tempdir");
        let rec = dir.path().join(".p.ron.autosave");
        fs::write(module_recovery_path(&rec), "(version: 1, files: [(name:").expect("write");
        let err = load_module_recovery(&rec).expect_err("damaged");
        assert!(err.to_string().contains(".p.ron.modules.autosave"), "{err}");
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
