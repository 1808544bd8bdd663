//! Autosave: the recovery file written a moment after each edit, removed
//! once the document is saved, and the offer to restore one left by an
//! editor that did not close.

use std::path::{Path, PathBuf};

use crate::files;
use crate::model::EditorDoc;

#[derive(Default)]
pub(super) struct Autosave {
    /// The document generation last written to the recovery file.
    pub(super) generation: Option<u64>,
    /// When it was written (egui's input time, seconds).
    pub(super) last: f64,
    /// Whether a recovery file of this document exists.
    pub(super) recovery_written: bool,
    /// A recovery file found at start, offered for restoring.
    pub(super) offer: Option<PathBuf>,
    /// The subpatch files whose autosaved edits the offer restores too.
    pub(super) offer_modules: Vec<PathBuf>,
}

/// What a look at the autosave did.
#[derive(Debug, PartialEq)]
pub(super) enum Autosaved {
    /// Nothing to write (saved, or written already).
    Nothing,
    /// An edit to write in this many seconds.
    In(f64),
    Written,
    Failed(String),
}

impl Autosave {
    /// A new document: nothing of it written yet.
    pub(super) fn forget(&mut self) {
        self.generation = None;
        self.recovery_written = false;
    }

    /// Offer the recovery file of `path` (the patch, `None` for a new one), if one was left.
    pub(super) fn find_offer(&mut self, path: Option<&Path>, config_dir: &Path) {
        self.offer = files::pending_recovery(path, config_dir);
        if let Some(recovery) = &self.offer {
            // What cannot be read is said when restoring; the offer lists what can.
            self.offer_modules = files::load_module_recovery(recovery)
                .map(|m| m.edits.into_iter().map(|e| e.path).collect())
                .unwrap_or_default();
        }
    }

    /// Write `doc` to `recovery` when it changed and the last write is
    /// `period` seconds old at `now`; remove the file once `doc` is saved.
    pub(super) fn tick(
        &mut self,
        doc: &EditorDoc,
        recovery: &Path,
        period: f64,
        now: f64,
    ) -> Autosaved {
        if !doc.is_dirty() {
            if self.recovery_written {
                files::remove_recovery(recovery);
                self.recovery_written = false;
            }
            return Autosaved::Nothing;
        }
        if self.generation == Some(doc.generation()) {
            return Autosaved::Nothing;
        }
        let wait = period - (now - self.last);
        if wait > 0.0 {
            return Autosaved::In(wait);
        }
        self.last = now;
        // The subpatch files' edits first: a restart looks for the patch's
        // recovery file, so once that is written both hold this edit.
        let written = files::write_module_recovery(&doc.unsaved_module_files(), recovery)
            .and_then(|()| files::write_recovery(doc.top(), recovery));
        match written {
            Ok(()) => {
                self.generation = Some(doc.generation());
                self.recovery_written = true;
                Autosaved::Written
            }
            Err(e) => Autosaved::Failed(format!("autosave failed: {e}")),
        }
    }
}
