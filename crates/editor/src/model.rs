//! The editor's model of a patch: the document plus an undo history of typed
//! commands. No egui here, so every edit an artist can make is testable
//! without a window; the canvas is a projection of this model.
//!
//! Split by concern: the commands and their inverses (`command.rs`), the
//! edits of nodes and the clipboard (`edits.rs`), links and their checks
//! (`links.rs`); here the document, its history and what the canvas looks up.

use std::collections::{HashMap, VecDeque};

use spreadlight_graph::{LinkDoc, NodeDoc, NodeId, Patch, PinRef, Registry, Spread};

mod command;
pub mod edits;
pub mod links;
pub mod organise;

pub use command::{Annotations, Command, NodeMove};

struct Entry {
    label: String,
    command: Command,
    /// Which document the command changed (undo opens it again).
    scope: Vec<String>,
    /// Distinguishes history states, so "saved" survives undo back to it.
    serial: u64,
}

/// How many edits undo remembers.
const HISTORY: usize = 1000;

/// The patch being edited, its history, and whether it differs from the saved file.
pub struct EditorDoc {
    top: Patch,
    /// The inline subpatch being edited, by the chain of definition names from the top (empty: the top).
    pub(crate) scope: Vec<String>,
    /// Subpatch files opened in place (`module_file.rs`): their edits are part of this document.
    pub(crate) files: crate::module_scope::Modules,
    undo: VecDeque<Entry>,
    redo: Vec<Entry>,
    next_serial: u64,
    saved_serial: Option<u64>,
    /// Bumped on every change: the runtime reloads when it moves.
    generation: u64,
    /// Lookups the canvas makes for every pin of every node each frame: by
    /// index, so a 500-node patch costs no quadratic searches.
    node_index: HashMap<NodeId, usize>,
    link_index: HashMap<PinRef, usize>,
}

impl Default for EditorDoc {
    fn default() -> Self {
        Self::new(Patch::default())
    }
}

impl EditorDoc {
    /// A document as loaded from disk: clean, with no history.
    pub fn new(patch: Patch) -> Self {
        let mut doc = EditorDoc {
            top: patch,
            scope: Vec::new(),
            files: Default::default(),
            undo: VecDeque::new(),
            redo: Vec::new(),
            next_serial: 1,
            saved_serial: Some(0),
            generation: 0,
            node_index: HashMap::new(),
            link_index: HashMap::new(),
        };
        doc.reindex();
        doc
    }

    pub(crate) fn reindex(&mut self) {
        self.generation += 1;
        // An undo can take away the subpatch being shown: show the deepest one left.
        self.scope.truncate(crate::module_scope::existing_depth(
            &self.top,
            &self.files,
            &self.scope,
        ));
        self.node_index.clear();
        let patch = crate::module_scope::doc_at(&self.top, &self.files, &self.scope);
        for (i, n) in patch.nodes.iter().enumerate() {
            // The first of duplicate ids wins, as in the network compiler.
            self.node_index.entry(n.id).or_insert(i);
        }
        self.link_index.clear();
        for (i, l) in patch.links.iter().enumerate() {
            self.link_index.entry(l.to.clone()).or_insert(i);
        }
    }

    /// The node with this id.
    pub fn node(&self, id: NodeId) -> Option<&NodeDoc> {
        self.patch().nodes.get(*self.node_index.get(&id)?)
    }

    /// A document restored from an autosave: it differs from the file on disk.
    pub fn recovered(patch: Patch) -> Self {
        let mut doc = Self::new(patch);
        doc.saved_serial = None;
        doc
    }

    /// The document the canvas shows: the top patch, or the inline subpatch
    /// opened in it ([`EditorDoc::scope`]).
    pub fn patch(&self) -> &Patch {
        crate::module_scope::doc_at(&self.top, &self.files, &self.scope)
    }

    pub(crate) fn viewed_mut(&mut self) -> &mut Patch {
        crate::module_scope::doc_at_mut(&mut self.top, &mut self.files, &self.scope)
    }

    /// The whole patch, as saved and run.
    pub fn top(&self) -> &Patch {
        &self.top
    }

    pub fn generation(&self) -> u64 {
        self.generation
    }

    fn top_serial(&self) -> u64 {
        self.undo.back().map_or(0, |e| e.serial)
    }

    pub fn is_dirty(&self) -> bool {
        self.saved_serial != Some(self.top_serial())
    }

    pub fn mark_saved(&mut self) {
        self.saved_serial = Some(self.top_serial());
    }

    pub fn can_undo(&self) -> bool {
        !self.undo.is_empty()
    }

    pub fn can_redo(&self) -> bool {
        !self.redo.is_empty()
    }

    pub fn undo_label(&self) -> Option<&str> {
        self.undo.back().map(|e| e.label.as_str())
    }

    pub fn redo_label(&self) -> Option<&str> {
        self.redo.last().map(|e| e.label.as_str())
    }

    /// Apply a command and record it for undo.
    pub fn execute(&mut self, label: impl Into<String>, command: Command) {
        command.apply(self.viewed_mut());
        self.reindex();
        self.redo.clear();
        let serial = self.next_serial;
        self.next_serial += 1;
        self.undo.push_back(Entry {
            label: label.into(),
            command,
            scope: self.scope.clone(),
            serial,
        });
        if self.undo.len() > HISTORY {
            self.undo.pop_front();
        }
    }

    pub fn undo(&mut self) -> bool {
        let Some(entry) = self.undo.pop_back() else {
            return false;
        };
        self.scope = entry.scope.clone();
        entry.command.inverse().apply(self.viewed_mut());
        self.reindex();
        self.redo.push(entry);
        true
    }

    pub fn redo(&mut self) -> bool {
        let Some(entry) = self.redo.pop() else {
            return false;
        };
        // Like undo, redo changes the document the command was made in.
        self.scope = entry.scope.clone();
        entry.command.apply(self.viewed_mut());
        self.reindex();
        self.undo.push_back(entry);
        true
    }

    /// Set an input's value; `None` goes back to the pin's default. With
    /// `merge`, a change of the same pin as the last edit extends that edit, so
    /// one drag of a slider is one undo step.
    pub fn set_value(&mut self, node: NodeId, pin: &str, value: Option<Spread>, merge: bool) {
        let Some(n) = self.node(node) else {
            return;
        };
        let old = n.values.get(pin).cloned();
        if old == value {
            return;
        }
        if merge
            && self.redo.is_empty()
            && self.saved_serial != Some(self.top_serial())
            && let Some(Entry {
                command:
                    Command::SetValue {
                        node: last_node,
                        pin: last_pin,
                        new,
                        ..
                    },
                scope,
                ..
            }) = self.undo.back_mut()
            && *scope == self.scope
            && *last_node == node
            && last_pin == pin
        {
            *new = value.clone();
            let apply = Command::SetValue {
                node,
                pin: pin.to_owned(),
                old,
                new: value,
            };
            apply.apply(self.viewed_mut());
            self.reindex();
            return;
        }
        self.execute(
            format!("set {node}.{pin}"),
            Command::SetValue {
                node,
                pin: pin.to_owned(),
                old,
                new: value,
            },
        );
    }

    /// The link into input `to`, if any.
    pub fn link_into(&self, to: &PinRef) -> Option<&LinkDoc> {
        self.patch().links.get(*self.link_index.get(to)?)
    }

    /// Where a link into an input stands in the document's list (by its input, indexed).
    pub fn link_position(&self, link: &LinkDoc) -> Option<usize> {
        self.link_index.get(&link.to).copied()
    }

    /// The value an input holds in the document, or its default.
    pub fn input_value(&self, registry: &Registry, node: NodeId, pin: &str) -> Option<Spread> {
        let n = self.node(node)?;
        if let Some(v) = n.values.get(pin) {
            return Some(v.clone());
        }
        let def = registry.get(&n.type_name)?;
        def.inputs
            .iter()
            .find(|p| p.name == pin)
            .map(|p| p.default.clone())
    }
}

#[cfg(test)]
mod tests;
