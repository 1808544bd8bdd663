//! The editor's model of a patch: the document plus an undo history of typed
//! commands. No egui here, so every edit an artist can make is testable
//! without a window; the canvas is a projection of this model.

use std::collections::{BTreeMap, HashMap, HashSet, VecDeque};

use spreadlight_graph::{LinkDoc, NodeDoc, NodeId, Patch, PinRef, PinType, Registry, Spread};
use thiserror::Error;

/// Why a link was refused. Shown where the wire was dropped.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum LinkError {
    #[error("node {0} does not exist")]
    MissingNode(NodeId),
    #[error("node {node} is of type `{type_name}`, which this build does not know")]
    UnknownType { node: NodeId, type_name: String },
    #[error("{0} is not an output pin")]
    MissingOutput(PinRef),
    #[error("{0} is not an input pin")]
    MissingInput(PinRef),
    #[error("cannot link {from_type} to {to_type}")]
    Incompatible { from_type: String, to_type: String },
    #[error("this link would make a cycle ({from} already depends on {to})", from = .from.node(), to = .to.node())]
    Cycle { from: PinRef, to: PinRef },
}

/// A node's move: its id, where it was, where it went (canvas units).
pub type NodeMove = (NodeId, (f32, f32), (f32, f32));

/// One reversible change of the document. Every command has an exact inverse,
/// so undo and redo are the same machinery.
#[derive(Debug, Clone, PartialEq)]
pub enum Command {
    /// Insert nodes and links at the given indices (ascending), so an undone
    /// delete puts everything back where it was and a saved file is unchanged.
    Insert {
        nodes: Vec<(usize, NodeDoc)>,
        links: Vec<(usize, LinkDoc)>,
    },
    /// Remove the nodes and links at the given indices (they hold what is removed).
    Remove {
        nodes: Vec<(usize, NodeDoc)>,
        links: Vec<(usize, LinkDoc)>,
    },
    Move {
        moves: Vec<NodeMove>,
    },
    /// `None` is the pin's default (no value saved).
    SetValue {
        node: NodeId,
        pin: String,
        old: Option<Spread>,
        new: Option<Spread>,
    },
    /// Define, replace or remove an inline subpatch (`None`: not defined).
    Define {
        name: String,
        old: Option<Box<Patch>>,
        new: Option<Box<Patch>>,
    },
    Batch(Vec<Command>),
}

impl Command {
    pub fn inverse(&self) -> Command {
        match self {
            Command::Insert { nodes, links } => Command::Remove {
                nodes: nodes.clone(),
                links: links.clone(),
            },
            Command::Remove { nodes, links } => Command::Insert {
                nodes: nodes.clone(),
                links: links.clone(),
            },
            Command::Move { moves } => Command::Move {
                moves: moves.iter().map(|&(id, a, b)| (id, b, a)).collect(),
            },
            Command::SetValue {
                node,
                pin,
                old,
                new,
            } => Command::SetValue {
                node: *node,
                pin: pin.clone(),
                old: new.clone(),
                new: old.clone(),
            },
            Command::Define { name, old, new } => Command::Define {
                name: name.clone(),
                old: new.clone(),
                new: old.clone(),
            },
            Command::Batch(cmds) => {
                Command::Batch(cmds.iter().rev().map(Command::inverse).collect())
            }
        }
    }

    pub(crate) fn apply(&self, patch: &mut Patch) {
        match self {
            Command::Insert { nodes, links } => {
                for (i, n) in nodes {
                    let at = (*i).min(patch.nodes.len());
                    patch.nodes.insert(at, n.clone());
                }
                for (i, l) in links {
                    let at = (*i).min(patch.links.len());
                    patch.links.insert(at, l.clone());
                }
            }
            Command::Remove { nodes, links } => {
                // Links first and from the back: the indices were taken before anything moved.
                for (i, l) in links.iter().rev() {
                    if patch.links.get(*i) == Some(l) {
                        patch.links.remove(*i);
                    }
                }
                for (i, n) in nodes.iter().rev() {
                    if patch.nodes.get(*i).map(|x| x.id) == Some(n.id) {
                        patch.nodes.remove(*i);
                    }
                }
            }
            Command::Move { moves } => {
                for (id, _, to) in moves {
                    if let Some(n) = patch.node_mut(*id) {
                        n.pos = *to;
                    }
                }
            }
            Command::SetValue { node, pin, new, .. } => {
                if let Some(n) = patch.node_mut(*node) {
                    match new {
                        Some(v) => {
                            n.values.insert(pin.clone(), v.clone());
                        }
                        None => {
                            n.values.remove(pin);
                        }
                    }
                }
            }
            Command::Define { name, new, .. } => match new {
                Some(def) => {
                    patch.subpatches.insert(name.clone(), (**def).clone());
                }
                None => {
                    patch.subpatches.remove(name);
                }
            },
            Command::Batch(cmds) => {
                for c in cmds {
                    c.apply(patch);
                }
            }
        }
    }
}

/// What the copy command keeps: nodes and the links between them.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Clip {
    pub nodes: Vec<NodeDoc>,
    pub links: Vec<LinkDoc>,
}

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

    /// Create a node of `type_name` at `pos`; returns its id.
    pub fn add_node(&mut self, type_name: &str, pos: (f32, f32)) -> NodeId {
        let id = self.patch().next_id();
        let node = NodeDoc::new(id.0, type_name).at(pos.0, pos.1);
        let at = self.patch().nodes.len();
        self.execute(
            format!("create {type_name}"),
            Command::Insert {
                nodes: vec![(at, node)],
                links: Vec::new(),
            },
        );
        id
    }

    /// Delete nodes and every link touching them.
    pub fn delete_nodes(&mut self, ids: &[NodeId]) {
        let set: HashSet<NodeId> = ids.iter().copied().collect();
        let nodes: Vec<(usize, NodeDoc)> = self
            .patch()
            .nodes
            .iter()
            .enumerate()
            .filter(|(_, n)| set.contains(&n.id))
            .map(|(i, n)| (i, n.clone()))
            .collect();
        if nodes.is_empty() {
            return;
        }
        let links: Vec<(usize, LinkDoc)> = self
            .patch()
            .links
            .iter()
            .enumerate()
            .filter(|(_, l)| set.contains(&l.from.node()) || set.contains(&l.to.node()))
            .map(|(i, l)| (i, l.clone()))
            .collect();
        let label = if nodes.len() == 1 {
            format!("delete {}", nodes[0].1.type_name)
        } else {
            format!("delete {} nodes", nodes.len())
        };
        self.execute(label, Command::Remove { nodes, links });
    }

    /// Record the end of a drag: nodes moved to new positions.
    pub fn move_nodes(&mut self, moves: &[(NodeId, (f32, f32))]) {
        let moves: Vec<_> = moves
            .iter()
            .filter_map(|&(id, to)| {
                let from = self.node(id)?.pos;
                (from != to).then_some((id, from, to))
            })
            .collect();
        if moves.is_empty() {
            return;
        }
        let label = if moves.len() == 1 {
            "move node".to_owned()
        } else {
            format!("move {} nodes", moves.len())
        };
        self.execute(label, Command::Move { moves });
    }

    /// Check a link against the registry's pin types and the patch's links.
    pub fn validate_link(
        &self,
        registry: &Registry,
        from: &PinRef,
        to: &PinRef,
    ) -> Result<(), LinkError> {
        let (from_ty, to_ty) = link_types(self.patch(), registry, from, to)?;
        // An `Inlet`'s output is `Any` until compiling types it from what it feeds.
        if !from_ty.links_to(to_ty) && from_ty != PinType::Any {
            return Err(LinkError::Incompatible {
                from_type: from_ty.name(),
                to_type: to_ty.name(),
            });
        }
        if from.node() == to.node() || reaches(self.patch(), to.node(), from.node()) {
            return Err(LinkError::Cycle {
                from: from.clone(),
                to: to.clone(),
            });
        }
        Ok(())
    }

    /// Link `from` to `to` after validating it. An input takes one link, so a
    /// link already into `to` is replaced (in one undo step).
    pub fn link(&mut self, registry: &Registry, from: PinRef, to: PinRef) -> Result<(), LinkError> {
        self.validate_link(registry, &from, &to)?;
        let link = LinkDoc { from, to };
        if self.patch().links.contains(&link) {
            return Ok(());
        }
        let replaced: Vec<(usize, LinkDoc)> = self
            .patch()
            .links
            .iter()
            .enumerate()
            .filter(|(_, l)| l.to == link.to)
            .map(|(i, l)| (i, l.clone()))
            .collect();
        let at = self.patch().links.len() - replaced.len();
        let label = format!("link {} to {}", link.from, link.to);
        let insert = Command::Insert {
            nodes: Vec::new(),
            links: vec![(at, link)],
        };
        let command = if replaced.is_empty() {
            insert
        } else {
            Command::Batch(vec![
                Command::Remove {
                    nodes: Vec::new(),
                    links: replaced,
                },
                insert,
            ])
        };
        self.execute(label, command);
        Ok(())
    }

    /// Remove the link from `from` to `to`, if there is one.
    pub fn unlink(&mut self, from: &PinRef, to: &PinRef) -> bool {
        let Some(i) = self
            .patch()
            .links
            .iter()
            .position(|l| &l.from == from && &l.to == to)
        else {
            return false;
        };
        let link = self.patch().links[i].clone();
        self.execute(
            format!("unlink {} from {}", link.from, link.to),
            Command::Remove {
                nodes: Vec::new(),
                links: vec![(i, link)],
            },
        );
        true
    }

    /// Remove every link into input `to` (right-click on an input pin).
    pub fn unlink_input(&mut self, to: &PinRef) -> bool {
        let links: Vec<(usize, LinkDoc)> = self
            .patch()
            .links
            .iter()
            .enumerate()
            .filter(|(_, l)| &l.to == to)
            .map(|(i, l)| (i, l.clone()))
            .collect();
        if links.is_empty() {
            return false;
        }
        self.execute(
            format!("unlink {to}"),
            Command::Remove {
                nodes: Vec::new(),
                links,
            },
        );
        true
    }

    /// Remove every link out of output `from`.
    pub fn unlink_output(&mut self, from: &PinRef) -> bool {
        let links: Vec<(usize, LinkDoc)> = self
            .patch()
            .links
            .iter()
            .enumerate()
            .filter(|(_, l)| &l.from == from)
            .map(|(i, l)| (i, l.clone()))
            .collect();
        if links.is_empty() {
            return false;
        }
        self.execute(
            format!("unlink {from}"),
            Command::Remove {
                nodes: Vec::new(),
                links,
            },
        );
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

    /// The selected nodes and the links between them.
    pub fn copy(&self, ids: &[NodeId]) -> Clip {
        let set: HashSet<NodeId> = ids.iter().copied().collect();
        Clip {
            nodes: self
                .patch()
                .nodes
                .iter()
                .filter(|n| set.contains(&n.id))
                .cloned()
                .collect(),
            links: self
                .patch()
                .links
                .iter()
                .filter(|l| set.contains(&l.from.node()) && set.contains(&l.to.node()))
                .cloned()
                .collect(),
        }
    }

    /// Insert a copy of `clip` with fresh ids, shifted by `offset`; returns the new ids.
    pub fn paste(&mut self, clip: &Clip, offset: (f32, f32)) -> Vec<NodeId> {
        if clip.nodes.is_empty() {
            return Vec::new();
        }
        let first = self.patch().next_id().0;
        let mut ids: HashMap<NodeId, NodeId> = HashMap::new();
        let mut nodes = Vec::new();
        let base = self.patch().nodes.len();
        for (k, n) in clip.nodes.iter().enumerate() {
            let mut copy = n.clone();
            copy.id = NodeId(first + k as u32);
            copy.pos = (n.pos.0 + offset.0, n.pos.1 + offset.1);
            ids.insert(n.id, copy.id);
            nodes.push((base + k, copy));
        }
        let base = self.patch().links.len();
        let links: Vec<(usize, LinkDoc)> = clip
            .links
            .iter()
            .filter_map(|l| {
                Some(LinkDoc {
                    from: PinRef(*ids.get(&l.from.node())?, l.from.pin().to_owned()),
                    to: PinRef(*ids.get(&l.to.node())?, l.to.pin().to_owned()),
                })
            })
            .enumerate()
            .map(|(k, l)| (base + k, l))
            .collect();
        let new_ids = nodes.iter().map(|(_, n)| n.id).collect();
        let label = format!("paste {} nodes", nodes.len());
        self.execute(label, Command::Insert { nodes, links });
        new_ids
    }

    /// Copy and paste in one step.
    pub fn duplicate(&mut self, ids: &[NodeId], offset: (f32, f32)) -> Vec<NodeId> {
        let clip = self.copy(ids);
        self.paste(&clip, offset)
    }

    /// The link into input `to`, if any.
    pub fn link_into(&self, to: &PinRef) -> Option<&LinkDoc> {
        self.patch().links.get(*self.link_index.get(to)?)
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

fn link_types(
    patch: &Patch,
    registry: &Registry,
    from: &PinRef,
    to: &PinRef,
) -> Result<(PinType, PinType), LinkError> {
    let def_of = |id: NodeId| {
        let node = patch.node(id).ok_or(LinkError::MissingNode(id))?;
        registry
            .get(&node.type_name)
            .ok_or_else(|| LinkError::UnknownType {
                node: id,
                type_name: node.type_name.clone(),
            })
    };
    let from_def = def_of(from.node())?;
    let to_def = def_of(to.node())?;
    let from_ty = from_def
        .outputs
        .iter()
        .find(|p| p.name == from.pin())
        .ok_or_else(|| LinkError::MissingOutput(from.clone()))?
        .ty;
    let to_ty = to_def
        .inputs
        .iter()
        .find(|p| p.name == to.pin())
        .ok_or_else(|| LinkError::MissingInput(to.clone()))?
        .ty;
    Ok((from_ty, to_ty))
}

/// Whether `target` can be reached from `start` by following links downstream.
fn reaches(patch: &Patch, start: NodeId, target: NodeId) -> bool {
    let mut downstream: BTreeMap<NodeId, Vec<NodeId>> = BTreeMap::new();
    for l in &patch.links {
        downstream
            .entry(l.from.node())
            .or_default()
            .push(l.to.node());
    }
    let mut seen = HashSet::new();
    let mut stack = vec![start];
    while let Some(n) = stack.pop() {
        if n == target {
            return true;
        }
        if seen.insert(n)
            && let Some(next) = downstream.get(&n)
        {
            stack.extend(next.iter().copied());
        }
    }
    false
}

#[cfg(test)]
mod tests;
