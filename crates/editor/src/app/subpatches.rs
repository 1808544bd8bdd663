//! The editor's side of subpatches: their types in the registry the canvas
//! draws with, making and unmaking them from the selection, opening one in
//! place (double-click) and the breadcrumb back.

use egui::Ui;
use spreadlight_graph::NodeId;
use spreadlight_graph::subpatch::{self, Library};

use super::{EditorApp, FIT_FROM_SCRATCH};

impl EditorApp {
    /// Keep the registry's subpatch types in step with the document: every
    /// inline definition seen from the open document, every subpatch file
    /// opened in place (as edited) and every library file, with pins from
    /// their IOBoxes.
    pub(super) fn refresh_subpatch_types(&mut self) {
        let library = self.frame.runtime.library().cloned().unwrap_or_default();
        let scope = self.doc.scope().to_vec();
        let mut found: Vec<(String, spreadlight_graph::Patch, String)> = Vec::new();
        // Inner definitions shadow outer ones, inline ones shadow files.
        for depth in (0..=scope.len()).rev() {
            for (name, def) in &self.doc.doc_at(&scope[..depth]).subpatches {
                if !found.iter().any(|(n, ..)| n == name) {
                    found.push((name.clone(), def.clone(), "inline".to_owned()));
                }
            }
        }
        for (name, file) in self.doc.module_files() {
            if !found.iter().any(|(n, ..)| n == name) {
                let source = file.path.display().to_string();
                found.push((name.clone(), file.patch.clone(), source));
            }
        }
        for (name, entry) in library.entries() {
            if let Ok(def) = &entry.definition
                && !found.iter().any(|(n, ..)| n == name)
            {
                found.push((
                    name.to_owned(),
                    (**def).clone(),
                    entry.path.display().to_string(),
                ));
            }
        }
        for old in std::mem::take(&mut self.subpatch_types) {
            if !found.iter().any(|(n, ..)| *n == old) {
                self.registry.remove(&old);
            }
        }
        for (name, def, source) in found {
            let builtin = self
                .registry
                .get(&name)
                .is_some_and(|d| !subpatch::is_subpatch_def(d));
            if builtin {
                continue;
            }
            let node_def = subpatch::node_def(&name, &def, &self.registry, &library, &source);
            self.registry.replace(node_def);
            self.subpatch_types.push(name);
        }
        self.sync_instance();
    }

    /// The instance the open document is shown for follows the scope (an undo
    /// may open another document): keep the remembered one while it fits.
    fn sync_instance(&mut self) {
        let scope = self.doc.scope();
        let fits = self.instance.len() == scope.len()
            && self
                .instance
                .iter()
                .zip(scope)
                .enumerate()
                .all(|(k, (id, name))| {
                    let doc = self.doc.doc_at(&scope[..k]);
                    doc.node(*id).is_some_and(|n| &n.type_name == name)
                });
        if fits {
            return;
        }
        // Otherwise the first instance of each definition on the way down.
        let mut path = Vec::new();
        for (k, name) in scope.iter().enumerate() {
            match self
                .doc
                .doc_at(&scope[..k])
                .nodes
                .iter()
                .find(|n| &n.type_name == name)
            {
                Some(n) => path.push(n.id),
                None => break,
            }
        }
        self.instance = path;
    }

    /// The subpatch instance the open document shows (node ids from the top; empty at the top).
    pub fn instance(&self) -> &[NodeId] {
        &self.instance
    }

    /// Open the subpatch node `id` is an instance of, in place: an inline
    /// one, or a subpatch file (read into the document; saving writes it).
    pub fn open_subpatch(&mut self, id: NodeId) -> bool {
        let mut instance = self.instance.clone();
        if !self.doc.enter(id) && !self.enter_module_file(id) {
            return false;
        }
        instance.push(id);
        self.instance = instance;
        self.after_navigation();
        true
    }

    fn enter_module_file(&mut self, id: NodeId) -> bool {
        let Some(file) = self.doc.node(id).and_then(|n| {
            let library: &Library = self.frame.runtime.library()?;
            Some(library.get(&n.type_name)?.path.clone())
        }) else {
            return false;
        };
        match self.doc.enter_file(id, &file) {
            Ok(()) => true,
            Err(e) => {
                self.status = format!("cannot open {}: {e}", file.display());
                false
            }
        }
    }

    /// Go back to the document at `depth` of the breadcrumb (0: the top patch).
    pub fn leave_subpatch(&mut self, depth: usize) {
        self.doc.leave_to(depth);
        self.instance.truncate(depth);
        self.after_navigation();
    }

    fn after_navigation(&mut self) {
        self.canvas.selected.clear();
        self.canvas.fit = FIT_FROM_SCRATCH;
        self.status = match self.doc.scope().last() {
            Some(name) => format!("editing subpatch {name}"),
            None => "editing the patch".to_owned(),
        };
    }

    /// Make a subpatch of the selected nodes (Ctrl+G); selects its node.
    pub fn make_subpatch_of_selection(&mut self) -> Option<NodeId> {
        let ids = self.selected();
        let id = self.doc.make_subpatch(&self.registry, &ids)?;
        self.canvas.selected = [id].into_iter().collect();
        Some(id)
    }

    /// Put the selected subpatch nodes' insides back in their place (Ctrl+Shift+G).
    pub fn unmake_selected_subpatches(&mut self) {
        let mut made = Vec::new();
        for id in self.selected() {
            made.extend(self.doc.unmake_subpatch(id));
        }
        if !made.is_empty() {
            self.canvas.selected = made.into_iter().collect();
        }
    }

    /// "Patch › Subpatch › …": where the open document is; a click goes back up.
    pub(super) fn breadcrumb(&mut self, ui: &mut Ui) {
        let scope = self.doc.scope().to_vec();
        if scope.is_empty() {
            return;
        }
        ui.horizontal(|ui| {
            let top = self
                .path
                .as_ref()
                .and_then(|p| p.file_stem())
                .map_or_else(|| "Patch".to_owned(), |s| s.to_string_lossy().into_owned());
            if ui.button(format!("⏶ {top}")).clicked() {
                self.leave_subpatch(0);
            }
            for (depth, name) in scope.iter().enumerate() {
                ui.label("›");
                let last = depth + 1 == scope.len();
                let mut button = ui.add_enabled(!last, egui::Button::new(name));
                // A subpatch file says which file its edits are saved to.
                let file = self.doc.module_files().get(name).filter(|_| {
                    !self
                        .doc
                        .doc_at(&scope[..depth])
                        .subpatches
                        .contains_key(name)
                });
                if let Some(file) = file {
                    button = button.on_hover_text(format!("saved to {}", file.path.display()));
                }
                if button.clicked() {
                    self.leave_subpatch(depth + 1);
                }
            }
        });
    }
}
