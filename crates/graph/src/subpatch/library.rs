//! Where subpatch files are found: `modules/` beside the patch, then the
//! user's library folder. A file `modules/DeferredScene.ron` defines the node
//! type `DeferredScene`. Files are parsed once and parsed again only when they
//! change on disk, so a host may refresh before every compile.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::SystemTime;

use crate::document::Patch;
use crate::format;

/// The folder beside a patch whose `.ron` files are subpatch types.
pub const MODULES_DIR: &str = "modules";

/// The environment variable naming the user's library folder; without it,
/// `$XDG_DATA_HOME/spreadlight/library` (or `~/.local/share/spreadlight/library`).
pub use spreadlight_dirs::LIBRARY_ENV;

/// A subpatch file as last read: its definition, or why it could not be read.
#[derive(Clone, Debug)]
pub struct LibraryEntry {
    pub path: PathBuf,
    pub definition: Result<Arc<Patch>, String>,
    stamp: Option<(SystemTime, u64)>,
}

/// Subpatch types defined by files, by type name. The first folder that
/// defines a name wins: a module beside the patch shadows the user library's.
#[derive(Clone, Debug, Default)]
pub struct Library {
    dirs: Vec<PathBuf>,
    entries: BTreeMap<String, LibraryEntry>,
}

impl Library {
    /// A library over these folders, in order (folders that do not exist hold nothing).
    pub fn new(dirs: Vec<PathBuf>) -> Self {
        let mut library = Library {
            dirs,
            entries: BTreeMap::new(),
        };
        library.refresh();
        library
    }

    /// The library a patch in `patch_dir` sees: its `modules/` folder, then the user library.
    pub fn beside(patch_dir: &Path) -> Self {
        let mut dirs = vec![patch_dir.join(MODULES_DIR)];
        dirs.push(user_library_dir());
        Library::new(dirs)
    }

    pub fn dirs(&self) -> &[PathBuf] {
        &self.dirs
    }

    /// Read the folders again: new files appear, deleted ones go, changed ones are parsed again.
    pub fn refresh(&mut self) {
        let mut entries = BTreeMap::new();
        for dir in &self.dirs {
            let Ok(listing) = std::fs::read_dir(dir) else {
                continue;
            };
            let mut files: Vec<PathBuf> = listing
                .filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| p.is_file() && p.extension().is_some_and(|e| e == "ron"))
                .collect();
            files.sort();
            for path in files {
                let Some(name) = path.file_stem().and_then(|s| s.to_str()) else {
                    continue;
                };
                if entries.contains_key(name) {
                    continue;
                }
                let stamp = std::fs::metadata(&path)
                    .ok()
                    .and_then(|m| Some((m.modified().ok()?, m.len())));
                let entry = match self.entries.remove(name) {
                    Some(old) if old.path == path && old.stamp.is_some() && old.stamp == stamp => {
                        old
                    }
                    _ => LibraryEntry {
                        definition: format::load(&path).map(Arc::new).map_err(|e| e.to_string()),
                        path: path.clone(),
                        stamp,
                    },
                };
                entries.insert(name.to_owned(), entry);
            }
        }
        self.entries = entries;
    }

    pub fn get(&self, name: &str) -> Option<&LibraryEntry> {
        self.entries.get(name)
    }

    /// Every subpatch type the folders define, sorted by name.
    pub fn entries(&self) -> impl Iterator<Item = (&str, &LibraryEntry)> {
        self.entries.iter().map(|(k, v)| (k.as_str(), v))
    }
}

/// The user's library folder (`spreadlight_dirs::library_dir`: the same
/// rules as the cache and the settings).
pub fn user_library_dir() -> PathBuf {
    spreadlight_dirs::library_dir()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn write(dir: &Path, name: &str, text: &str) {
        std::fs::create_dir_all(dir).expect("mkdir");
        std::fs::write(dir.join(name), text).expect("write");
    }

    #[test]
    fn the_folder_beside_the_patch_shadows_the_user_library() {
        let root = tempfile::tempdir().expect("tempdir");
        let (beside, user) = (root.path().join("modules"), root.path().join("library"));
        write(
            &beside,
            "Shared.ron",
            "(version: 1, nodes: [(id: 1, type: \"A\")])",
        );
        write(
            &user,
            "Shared.ron",
            "(version: 1, nodes: [(id: 2, type: \"B\")])",
        );
        write(&user, "Mine.ron", "(version: 1)");
        write(&user, "notes.txt", "not a patch");
        let library = Library::new(vec![beside.clone(), user.clone()]);
        let names: Vec<&str> = library.entries().map(|(n, _)| n).collect();
        assert_eq!(names, ["Mine", "Shared"]);
        let shared = library.get("Shared").expect("listed");
        assert_eq!(shared.path, beside.join("Shared.ron"));
        assert_eq!(
            shared.definition.as_ref().expect("parsed").nodes[0].type_name,
            "A"
        );
        assert_eq!(
            library.get("Mine").expect("listed").path,
            user.join("Mine.ron")
        );
    }
}
