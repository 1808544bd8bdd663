//! The document's reversible changes: each command and its exact inverse,
//! so undo and redo are the same machinery.

use spreadlight_graph::{CommentDoc, FrameDoc, LinkDoc, NodeDoc, NodeId, Patch, Spread};

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
    /// Bypass or run nodes again: (node, old, new).
    Bypass {
        nodes: Vec<(NodeId, bool, bool)>,
    },
    /// Replace the comments and frames (`organise.rs`).
    Annotate {
        old: Box<Annotations>,
        new: Box<Annotations>,
    },
    Batch(Vec<Command>),
}

/// A document's comments and frames, replaced as a whole by [`Command::Annotate`].
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Annotations {
    pub comments: Vec<CommentDoc>,
    pub frames: Vec<FrameDoc>,
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
            Command::Bypass { nodes } => Command::Bypass {
                nodes: nodes.iter().map(|&(id, a, b)| (id, b, a)).collect(),
            },
            Command::Annotate { old, new } => Command::Annotate {
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
            Command::Bypass { nodes } => {
                for &(id, _, bypass) in nodes {
                    if let Some(n) = patch.node_mut(id) {
                        n.bypass = bypass;
                    }
                }
            }
            Command::Annotate { new, .. } => {
                patch.comments = new.comments.clone();
                patch.frames = new.frames.clone();
            }
            Command::Batch(cmds) => {
                for c in cmds {
                    c.apply(patch);
                }
            }
        }
    }
}
