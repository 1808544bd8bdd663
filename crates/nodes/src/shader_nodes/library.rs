//! Where shader node files come from, and hot reload.
//!
//! Three places, later ones overriding earlier ones by type name: the
//! examples shipped in the repository's `shaders/nodes/` (embedded in the
//! binary), the user's library (the folders in `SPREADLIGHT_SHADERS`,
//! separated like `PATH`), and the `shaders/` folder beside the patch.
//! [`ShaderLibrary::poll`] looks at the folders' files (their modification
//! time and size: cheap enough to call a few times a second) and swaps every
//! changed type in the registry. A file that breaks keeps its last good
//! version registered (this library's, else the shipped example it
//! overrides), with the error shown on its nodes; one that never compiled is
//! a node without pins that keeps its values and links for the fixed file. A
//! version that compiles keeps the one it replaced, to run where it cannot
//! (a device limit).

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::SystemTime;

use spreadlight_graph::Registry;
use spreadlight_render::shader_nodes::ShaderNodeError;

use super::def::broken_def;
use super::shader_type::{ShaderType, type_name};

/// One file as last seen.
struct Seen {
    stamp: (Option<SystemTime>, u64),
    name: String,
}

/// The shader files of a set of folders, watched.
#[derive(Default)]
pub struct ShaderLibrary {
    folders: Vec<PathBuf>,
    seen: BTreeMap<PathBuf, Seen>,
    /// The last version of each type that compiled.
    good: BTreeMap<String, Arc<ShaderType>>,
    /// Each type's current error (its newest file does not compile).
    errors: BTreeMap<String, ShaderNodeError>,
}

/// What one poll changed.
#[derive(Debug, Default, PartialEq)]
pub struct Changes {
    /// Types registered or replaced (compiled, or kept with an error).
    pub updated: Vec<String>,
    /// Types whose file went away.
    pub removed: Vec<String>,
}

impl Changes {
    pub fn is_empty(&self) -> bool {
        self.updated.is_empty() && self.removed.is_empty()
    }
}

impl ShaderLibrary {
    /// Watch these folders (missing ones are fine: they may appear later).
    pub fn new(folders: Vec<PathBuf>) -> Self {
        ShaderLibrary {
            folders,
            ..Default::default()
        }
    }

    /// The user library (`SPREADLIGHT_SHADERS`) and the `shaders/` folder beside `patch`.
    pub fn for_patch(patch: Option<&Path>) -> Self {
        let mut folders: Vec<PathBuf> = std::env::var_os("SPREADLIGHT_SHADERS")
            .map(|v| std::env::split_paths(&v).collect())
            .unwrap_or_default();
        if let Some(dir) = patch.and_then(Path::parent) {
            folders.push(dir.join("shaders"));
        }
        Self::new(folders)
    }

    pub fn folders(&self) -> &[PathBuf] {
        &self.folders
    }

    /// For a shader node type that no file provides (`Nosie (Shader)`, or a
    /// file since moved): which file would make it and where it was looked
    /// for, so the message names the missing file instead of the next node
    /// saying that nothing is connected. `None` for names of other types.
    pub fn missing_file(&self, type_name: &str) -> Option<String> {
        let stem = super::shader_type::file_stem(type_name)?;
        let mut places: Vec<String> = self
            .folders
            .iter()
            .map(|f| {
                format!(
                    "`{}`",
                    std::path::absolute(f)
                        .unwrap_or_else(|_| f.clone())
                        .display()
                )
            })
            .collect();
        places.push(format!(
            "the {} examples built in (shaders/nodes/)",
            super::EXAMPLES.len()
        ));
        Some(format!(
            "no shader file makes it: `{stem}.wgsl` (or another name that reads as `{type_name}`) \
             is in none of {}",
            places.join(", ")
        ))
    }

    /// Errors of files that do not compile now, by type name.
    pub fn errors(&self) -> &BTreeMap<String, ShaderNodeError> {
        &self.errors
    }

    /// The current good version of a type.
    pub fn get(&self, name: &str) -> Option<&Arc<ShaderType>> {
        self.good.get(name)
    }

    fn files(&self) -> Vec<PathBuf> {
        let mut files = Vec::new();
        for folder in &self.folders {
            let Ok(entries) = std::fs::read_dir(folder) else {
                continue;
            };
            let mut here: Vec<PathBuf> = entries
                .flatten()
                .map(|e| e.path())
                .filter(|p| p.extension().is_some_and(|e| e == "wgsl"))
                .collect();
            here.sort();
            files.extend(here);
        }
        files
    }

    /// Look for new, changed and deleted files and update `registry`.
    pub fn poll(&mut self, registry: &mut Registry) -> Changes {
        let mut changes = Changes::default();
        let files = self.files();
        let gone: Vec<PathBuf> = self
            .seen
            .keys()
            .filter(|p| !files.contains(p))
            .cloned()
            .collect();
        for path in gone {
            if let Some(seen) = self.seen.remove(&path) {
                // Another folder may still provide the type.
                if !self.seen.values().any(|s| s.name == seen.name) {
                    registry.remove(&seen.name);
                    self.good.remove(&seen.name);
                    self.errors.remove(&seen.name);
                    changes.removed.push(seen.name);
                }
            }
        }
        for path in files {
            let meta = std::fs::metadata(&path).ok();
            let stamp = (
                meta.as_ref().and_then(|m| m.modified().ok()),
                meta.as_ref().map_or(0, |m| m.len()),
            );
            if self.seen.get(&path).is_some_and(|s| s.stamp == stamp) {
                continue;
            }
            let stem = path
                .file_stem()
                .and_then(|s| s.to_str())
                .unwrap_or("shader");
            let name = type_name(stem);
            let file = path.display().to_string();
            let loaded = std::fs::read_to_string(&path)
                .map_err(|e| {
                    ShaderNodeError::at(&file, Default::default(), format!("cannot read: {e}"))
                })
                .and_then(|text| ShaderType::load(&name, &file, &text));
            self.install(registry, &name, loaded);
            self.seen.insert(
                path,
                Seen {
                    stamp,
                    name: name.clone(),
                },
            );
            changes.updated.push(name);
        }
        changes
    }

    /// Register a freshly loaded version, or keep the last good one with the error.
    fn install(
        &mut self,
        registry: &mut Registry,
        name: &str,
        loaded: Result<Arc<ShaderType>, ShaderNodeError>,
    ) {
        // The last good version: this library's, else the shipped example
        // the file overrides.
        let good = self
            .good
            .get(name)
            .cloned()
            .or_else(|| super::shipped(name));
        match loaded {
            Ok(ty) => {
                if let Some(good) = &good {
                    ty.keep_previous(good);
                }
                registry.replace(ty.node_def(None));
                self.errors.remove(name);
                self.good.insert(name.to_owned(), ty);
            }
            Err(error) => {
                let def = match good {
                    Some(good) => good.node_def(Some(error.clone())),
                    // Never compiled: a pin-less node that shows the error
                    // once and keeps its values and links for the fixed file.
                    None => broken_def(name, &error),
                };
                registry.replace(def);
                self.errors.insert(name.to_owned(), error);
            }
        }
    }
}
