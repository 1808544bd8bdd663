//! Subpatch files opened in place. A node whose type is a subpatch file (a
//! module beside the patch or in the user library) opens inside the parent's
//! canvas like an inline one: the file is read into the document, the scope
//! (the breadcrumb) names it like an inline definition, edits go through the
//! same undo history, and saving the patch writes the file back.
//!
//! A scope is a chain of definition names; each name is looked up first among
//! the inline definitions of the document before it (inline ones shadow files,
//! as in the runtime), then among the opened files.

use std::path::{Path, PathBuf};

use spreadlight_graph::{NodeId, Patch, format};

use crate::files::ModuleEdit;
use crate::model::EditorDoc;
use crate::module_scope::doc_at;
pub use crate::module_scope::{ModuleFile, Modules};

/// Why a subpatch file could not be opened in place.
#[derive(Debug, thiserror::Error)]
pub enum OpenError {
    #[error("node {0} is not in the open document")]
    NoNode(NodeId),
    #[error(transparent)]
    Load(#[from] format::FormatError),
}

impl EditorDoc {
    /// The document at `scope` (inline definitions and opened files).
    pub fn doc_at(&self, scope: &[String]) -> &Patch {
        doc_at(self.top(), &self.files, scope)
    }

    /// The subpatch files opened in place so far, by type name.
    pub fn module_files(&self) -> &Modules {
        &self.files
    }

    /// Open the subpatch file `path`, which node `id`'s type names, in place
    /// (read once; later openings show it as edited).
    pub fn enter_file(&mut self, id: NodeId, path: &Path) -> Result<(), OpenError> {
        let name = self
            .node(id)
            .ok_or(OpenError::NoNode(id))?
            .type_name
            .clone();
        if !self.files.contains_key(&name) {
            let patch = format::load(path)?;
            self.files.insert(
                name.clone(),
                ModuleFile {
                    path: path.to_owned(),
                    saved: patch.clone(),
                    patch,
                },
            );
        }
        self.scope.push(name);
        self.reindex();
        Ok(())
    }

    /// The patch the runtime runs: the top patch, with each edited file's
    /// definition carried inline (inline definitions shadow files) so its
    /// edits run before they are saved.
    pub fn runtime_patch(&self) -> Patch {
        let mut patch = self.top().clone();
        for (name, file) in &self.files {
            if file.patch != file.saved {
                patch
                    .subpatches
                    .entry(name.clone())
                    .or_insert_with(|| file.patch.clone());
            }
        }
        patch
    }

    /// Write every edited subpatch file; the first failure stops and is returned.
    pub fn save_module_files(&mut self) -> Result<Vec<PathBuf>, format::FormatError> {
        let mut written = Vec::new();
        for file in self.files.values_mut() {
            if file.patch != file.saved {
                format::save(&file.patch, &file.path)?;
                file.saved = file.patch.clone();
                written.push(file.path.clone());
            }
        }
        Ok(written)
    }

    /// The subpatch files edited and not saved: what autosave keeps.
    pub fn unsaved_module_files(&self) -> Vec<ModuleEdit> {
        self.files
            .iter()
            .filter(|(_, file)| file.patch != file.saved)
            .map(|(name, file)| ModuleEdit {
                name: name.clone(),
                path: file.path.clone(),
                patch: file.patch.clone(),
            })
            .collect()
    }

    /// Put autosaved edits of subpatch files back, unsaved: each file as on
    /// disk now is what saving compares against, so the file is written only
    /// when the user saves. A file that cannot be read any more is written
    /// again on save; its reason is returned, by path.
    pub fn restore_module_files(&mut self, edits: Vec<ModuleEdit>) -> Vec<(PathBuf, String)> {
        let mut unreadable = Vec::new();
        for edit in edits {
            let saved = format::load(&edit.path).unwrap_or_else(|e| {
                unreadable.push((edit.path.clone(), e.to_string()));
                Patch::default()
            });
            self.files.insert(
                edit.name,
                ModuleFile {
                    path: edit.path,
                    patch: edit.patch,
                    saved,
                },
            );
        }
        self.reindex();
        unreadable
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use spreadlight_graph::NodeDoc;

    fn module() -> Patch {
        let mut m = Patch::default();
        m.add(NodeDoc::new(1, "Inlet").with("Name", vec!["In".to_owned()]));
        m.add(NodeDoc::new(2, "Outlet").with("Name", vec!["Out".to_owned()]));
        m.link(1, "Output", 2, "Input");
        m
    }

    fn parent() -> Patch {
        let mut p = Patch::default();
        p.add(NodeDoc::new(1, "LFO"));
        p.add(NodeDoc::new(2, "Scale"));
        p.link(1, "Output", 2, "In");
        p
    }

    #[test]
    fn edits_inside_a_file_are_undoable_run_inline_and_saved_to_the_file() {
        let dir = tempfile::tempdir().expect("tempdir");
        let file = dir.path().join("Scale.ron");
        format::save(&module(), &file).expect("save");
        let mut doc = EditorDoc::new(parent());
        doc.enter_file(NodeId(2), &file).expect("opens");
        assert_eq!(doc.scope(), ["Scale".to_owned()]);
        assert_eq!(doc.patch(), &module());
        assert_eq!(
            doc.runtime_patch(),
            parent(),
            "nothing edited: the file runs as it is"
        );

        doc.add_node("Probe", (0.0, 80.0));
        assert_eq!(doc.top(), &parent(), "the patch itself is unchanged");
        assert!(doc.is_dirty());
        let edited = doc.module_files()["Scale"].patch.clone();
        assert_eq!(edited.nodes.len(), 3);
        assert_eq!(doc.runtime_patch().subpatches["Scale"], edited);

        // Undo from the top opens the file again; redo too.
        doc.leave_to(0);
        assert!(doc.undo());
        assert_eq!(doc.scope(), ["Scale".to_owned()]);
        assert_eq!(doc.patch(), &module());
        doc.leave_to(0);
        assert!(doc.redo());
        assert_eq!(doc.scope(), ["Scale".to_owned()]);
        assert_eq!(doc.patch(), &edited);

        assert_eq!(
            doc.save_module_files().expect("written"),
            vec![file.clone()]
        );
        assert_eq!(format::load(&file).expect("reads"), edited);
        assert!(
            doc.runtime_patch().subpatches.is_empty(),
            "the file has it now"
        );
        assert!(doc.save_module_files().expect("nothing").is_empty());
    }

    #[test]
    fn a_missing_file_is_an_error_naming_it_and_nothing_opens() {
        let dir = tempfile::tempdir().expect("tempdir");
        let file = dir.path().join("Gone.ron");
        let mut doc = EditorDoc::new(parent());
        let err = doc.enter_file(NodeId(2), &file).expect_err("no file");
        assert!(err.to_string().contains("Gone.ron"), "{err}");
        assert!(doc.scope().is_empty());
        assert!(doc.module_files().is_empty());
    }
}
