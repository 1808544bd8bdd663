//! Links: checking one against the registry's pin types and the patch (no
//! cycles), making, replacing and removing them, each one undo step.

use std::collections::{BTreeMap, HashSet};

use spreadlight_graph::{LinkDoc, NodeId, Patch, PinRef, PinType, Registry};
use thiserror::Error;

use super::{Command, EditorDoc};

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

impl EditorDoc {
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
