//! Edits of nodes: create, delete, move, and the clipboard (copy, paste,
//! duplicate), each one undo step.

use std::collections::{HashMap, HashSet};

use spreadlight_graph::{LinkDoc, NodeDoc, NodeId, PinRef};

use super::{Command, EditorDoc};

/// What the copy command keeps: nodes and the links between them.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Clip {
    pub nodes: Vec<NodeDoc>,
    pub links: Vec<LinkDoc>,
}

impl EditorDoc {
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
}
