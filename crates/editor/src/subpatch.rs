//! Subpatches in the editor: making one from selected nodes (the links that
//! cross the selection become its pins), opening an inline one to edit it in
//! place, and unmaking one back into its nodes. Every change is one undoable
//! command on the [`EditorDoc`]; opening is navigation, not an edit.

use std::collections::{BTreeMap, HashSet};

use spreadlight_graph::subpatch::{INLET, OUTLET, ioboxes, is_iobox, pin_name};
use spreadlight_graph::{LinkDoc, NodeDoc, NodeId, Patch, PinRef, Registry, Spread};

use crate::model::{Command, EditorDoc};

/// How far from the top an IOBox sits from the nodes it serves, in canvas units.
const IOBOX_GAP: f32 = 40.0;

impl EditorDoc {
    /// The chain of inline subpatch names from the top to the open document.
    pub fn scope(&self) -> &[String] {
        &self.scope
    }

    /// The scope where the inline definition of `type_name` is, seen from the open document.
    fn definition_scope(&self, type_name: &str) -> Option<Vec<String>> {
        (0..=self.scope.len()).rev().find_map(|depth| {
            let doc = self.doc_at(&self.scope[..depth]);
            doc.subpatches.get(type_name).map(|_| {
                let mut scope = self.scope[..depth].to_vec();
                scope.push(type_name.to_owned());
                scope
            })
        })
    }

    /// Whether node `id` of the open document is an instance of an inline subpatch.
    pub fn is_inline_subpatch(&self, id: NodeId) -> bool {
        self.node(id)
            .is_some_and(|n| self.definition_scope(&n.type_name).is_some())
    }

    /// Open the inline subpatch node `id` is an instance of, to edit it in place.
    pub fn enter(&mut self, id: NodeId) -> bool {
        let Some(scope) = self
            .node(id)
            .and_then(|n| self.definition_scope(&n.type_name))
        else {
            return false;
        };
        self.scope = scope;
        self.reindex();
        true
    }

    /// Go back up to the document at `depth` of the breadcrumb (0: the top patch).
    pub fn leave_to(&mut self, depth: usize) {
        if depth < self.scope.len() {
            self.scope.truncate(depth);
            self.reindex();
        }
    }

    /// A subpatch name not yet taken by a node type or an inline definition.
    fn free_name(&self, registry: &Registry) -> String {
        let taken = |name: &str| {
            registry.get(name).is_some()
                || (0..=self.scope.len())
                    .any(|d| self.doc_at(&self.scope[..d]).subpatches.contains_key(name))
        };
        (1..)
            .map(|k| match k {
                1 => "Subpatch".to_owned(),
                k => format!("Subpatch {k}"),
            })
            .find(|name| !taken(name))
            .expect("some name is free")
    }

    /// Make an inline subpatch of the nodes `ids` of the open document and put
    /// one node of it in their place: each outside output that feeds the
    /// selection becomes an input pin (an `Inlet` inside), each selected output
    /// read outside becomes an output pin (an `Outlet`). One undo step.
    pub fn make_subpatch(&mut self, registry: &Registry, ids: &[NodeId]) -> Option<NodeId> {
        let inside: HashSet<NodeId> = ids.iter().copied().collect();
        let patch = self.patch();
        let chosen: Vec<(usize, NodeDoc)> = patch
            .nodes
            .iter()
            .enumerate()
            .filter(|(_, n)| inside.contains(&n.id))
            .map(|(i, n)| (i, n.clone()))
            .collect();
        if chosen.is_empty() {
            return None;
        }
        let touching: Vec<(usize, LinkDoc)> = patch
            .links
            .iter()
            .enumerate()
            .filter(|(_, l)| inside.contains(&l.from.node()) || inside.contains(&l.to.node()))
            .map(|(i, l)| (i, l.clone()))
            .collect();
        let name = self.free_name(registry);
        let min_x = chosen.iter().map(|(_, n)| n.pos.0).fold(f32::MAX, f32::min);
        let min_y = chosen.iter().map(|(_, n)| n.pos.1).fold(f32::MAX, f32::min);
        let max_y = chosen.iter().map(|(_, n)| n.pos.1).fold(f32::MIN, f32::max);
        let mut def = Patch::default();
        for (_, n) in &chosen {
            let mut copy = n.clone();
            copy.pos = (n.pos.0 - min_x, n.pos.1 - min_y + IOBOX_GAP);
            def.add(copy);
        }
        let mut pins = PinNames::default();
        let new_id = NodeId(patch.next_id().0);
        let mut outer_links = Vec::new();
        // Inputs: one Inlet per outside output feeding the selection.
        let mut inlets: BTreeMap<PinRef, NodeId> = BTreeMap::new();
        for (_, link) in &touching {
            let crosses_in =
                !inside.contains(&link.from.node()) && inside.contains(&link.to.node());
            if crosses_in {
                let inlet = *inlets.entry(link.from.clone()).or_insert_with(|| {
                    let id = def.next_id();
                    let pin = pins.unique(link.to.pin());
                    let x = def.node(link.to.node()).map_or(0.0, |n| n.pos.0);
                    def.add(
                        NodeDoc::new(id.0, INLET)
                            .at(x, 0.0)
                            .with("Name", vec![pin.clone()]),
                    );
                    outer_links.push(LinkDoc {
                        from: link.from.clone(),
                        to: PinRef(new_id, pin),
                    });
                    id
                });
                def.links.push(LinkDoc {
                    from: PinRef(inlet, "Output".to_owned()),
                    to: link.to.clone(),
                });
            } else if inside.contains(&link.from.node()) && inside.contains(&link.to.node()) {
                def.links.push(link.clone());
            }
        }
        // Outputs: one Outlet per selected output read outside.
        let mut outlets: BTreeMap<PinRef, String> = BTreeMap::new();
        for (_, link) in &touching {
            if !inside.contains(&link.from.node()) || inside.contains(&link.to.node()) {
                continue;
            }
            let pin = outlets.entry(link.from.clone()).or_insert_with(|| {
                let id = def.next_id();
                let pin = pins.unique(link.from.pin());
                let x = def.node(link.from.node()).map_or(0.0, |n| n.pos.0);
                let y = max_y - min_y + 2.0 * IOBOX_GAP;
                def.add(
                    NodeDoc::new(id.0, OUTLET)
                        .at(x, y)
                        .with("Name", vec![pin.clone()]),
                );
                def.links.push(LinkDoc {
                    from: link.from.clone(),
                    to: PinRef(id, "Input".to_owned()),
                });
                pin
            });
            outer_links.push(LinkDoc {
                from: PinRef(new_id, pin.clone()),
                to: link.to.clone(),
            });
        }
        let node = NodeDoc::new(new_id.0, &name).at(min_x, min_y);
        let (kept_nodes, kept_links) = (
            patch.nodes.len() - chosen.len(),
            patch.links.len() - touching.len(),
        );
        let command = Command::Batch(vec![
            Command::Remove {
                nodes: chosen,
                links: touching,
            },
            Command::Define {
                name: name.clone(),
                old: None,
                new: Some(Box::new(def)),
            },
            Command::Insert {
                nodes: vec![(kept_nodes, node)],
                links: outer_links
                    .into_iter()
                    .enumerate()
                    .map(|(k, l)| (kept_links + k, l))
                    .collect(),
            },
        ]);
        self.execute(format!("make subpatch {name}"), command);
        Some(new_id)
    }

    /// Put the nodes of the inline subpatch node `id` back in its place, its
    /// IOBoxes replaced by the links and values they passed on; the definition
    /// goes too when no other node uses it. One undo step. Returns the new ids.
    pub fn unmake_subpatch(&mut self, id: NodeId) -> Vec<NodeId> {
        let Some(node) = self.node(id).cloned() else {
            return Vec::new();
        };
        let Some(scope) = self.definition_scope(&node.type_name) else {
            return Vec::new();
        };
        let def = self.doc_at(&scope).clone();
        let patch = self.patch();
        let first = patch.next_id().0;
        let plain: Vec<&NodeDoc> = def
            .nodes
            .iter()
            .filter(|n| !is_iobox(&n.type_name))
            .collect();
        let new_id = |old: NodeId| {
            plain
                .iter()
                .position(|n| n.id == old)
                .map(|k| NodeId(first + k as u32))
        };
        let min_x = plain.iter().map(|n| n.pos.0).fold(f32::MAX, f32::min);
        let min_y = plain.iter().map(|n| n.pos.1).fold(f32::MAX, f32::min);
        let mut nodes: Vec<NodeDoc> = plain
            .iter()
            .map(|n| {
                let mut copy = (*n).clone();
                copy.id = new_id(n.id).expect("listed");
                copy.pos = (node.pos.0 + n.pos.0 - min_x, node.pos.1 + n.pos.1 - min_y);
                copy
            })
            .collect();
        let touching: Vec<(usize, LinkDoc)> = patch
            .links
            .iter()
            .enumerate()
            .filter(|(_, l)| l.from.node() == id || l.to.node() == id)
            .map(|(i, l)| (i, l.clone()))
            .collect();
        // What feeds each input pin outside: a link, or a value.
        let feed = |pin: &str| -> Feed {
            if let Some((_, l)) = touching
                .iter()
                .find(|(_, l)| l.to == PinRef(id, pin.to_owned()))
            {
                return Feed::Link(l.from.clone());
            }
            match node.values.get(pin) {
                Some(v) => Feed::Value(v.clone()),
                None => Feed::Nothing,
            }
        };
        let mut links = Vec::new();
        for link in &def.links {
            let from = def.node(link.from.node());
            let to = def.node(link.to.node());
            let (Some(from), Some(to)) = (from, to) else {
                continue;
            };
            // Sources, with an Inlet replaced by what feeds its pin outside.
            let source = if from.type_name == INLET {
                feed(&pin_name(from))
            } else {
                match new_id(from.id) {
                    Some(n) => Feed::Link(PinRef(n, link.from.pin().to_owned())),
                    None => continue,
                }
            };
            // Targets, with an Outlet replaced by the outside inputs its pin feeds.
            let targets: Vec<PinRef> = if to.type_name == OUTLET {
                let pin = pin_name(to);
                touching
                    .iter()
                    .filter(|(_, l)| l.from == PinRef(id, pin.clone()))
                    .map(|(_, l)| l.to.clone())
                    .collect()
            } else {
                new_id(to.id)
                    .map(|n| PinRef(n, link.to.pin().to_owned()))
                    .into_iter()
                    .collect()
            };
            for target in targets {
                match &source {
                    Feed::Link(from) => links.push(LinkDoc {
                        from: from.clone(),
                        to: target,
                    }),
                    Feed::Value(v) => {
                        if let Some(n) = nodes.iter_mut().find(|n| n.id == target.node()) {
                            n.values.insert(target.pin().to_owned(), v.clone());
                        }
                    }
                    Feed::Nothing => {}
                }
            }
        }
        let node_index = patch.nodes.iter().position(|n| n.id == id).expect("exists");
        let (kept_nodes, kept_links) = (patch.nodes.len() - 1, patch.links.len() - touching.len());
        let still_used = patch
            .nodes
            .iter()
            .any(|n| n.id != id && n.type_name == node.type_name);
        let new_ids: Vec<NodeId> = nodes.iter().map(|n| n.id).collect();
        let mut commands = vec![
            Command::Remove {
                nodes: vec![(node_index, node.clone())],
                links: touching,
            },
            Command::Insert {
                nodes: nodes
                    .into_iter()
                    .enumerate()
                    .map(|(k, n)| (kept_nodes + k, n))
                    .collect(),
                links: links
                    .into_iter()
                    .enumerate()
                    .map(|(k, l)| (kept_links + k, l))
                    .collect(),
            },
        ];
        // A definition in the open document that nothing else uses goes with its last node.
        if !still_used && scope.len() == self.scope.len() + 1 {
            commands.push(Command::Define {
                name: node.type_name.clone(),
                old: Some(Box::new(def)),
                new: None,
            });
        }
        self.execute(
            format!("unmake subpatch {}", node.type_name),
            Command::Batch(commands),
        );
        new_ids
    }
}

/// What reached a subpatch's input pin from outside.
enum Feed {
    Link(PinRef),
    Value(Spread),
    Nothing,
}

/// Pin names made unique within one subpatch: a second `Input` becomes `Input 2`.
#[derive(Default)]
struct PinNames(HashSet<String>);

impl PinNames {
    fn unique(&mut self, wanted: &str) -> String {
        let name = (1..)
            .map(|k| match k {
                1 => wanted.to_owned(),
                k => format!("{wanted} {k}"),
            })
            .find(|n| !self.0.contains(n))
            .expect("some name is free");
        self.0.insert(name.clone());
        name
    }
}

/// The IOBoxes of the open document, for the pins it shows its parent (used by tests and the inspector).
pub fn pin_names(doc: &Patch) -> (Vec<String>, Vec<String>) {
    let names = |kind| ioboxes(doc, kind).into_iter().map(pin_name).collect();
    (names(INLET), names(OUTLET))
}

#[cfg(test)]
mod tests {
    use spreadlight_graph::{FrameClock, Runtime};

    use super::*;

    /// LFO -> Multiply (x3) -> Probe, and LFO -> Probe "raw".
    fn chain() -> EditorDoc {
        let mut p = Patch::default();
        p.add(NodeDoc::new(1, "LFO"));
        p.add(
            NodeDoc::new(2, "Multiply (Value)")
                .at(0.0, 40.0)
                .with("Input 2", vec![3.0f32]),
        );
        p.add(
            NodeDoc::new(3, "Probe")
                .at(0.0, 80.0)
                .with("Name", vec!["out".to_owned()]),
        );
        p.link(1, "Output", 2, "Input 1");
        p.link(2, "Output", 3, "Input");
        EditorDoc::new(p)
    }

    /// What the probe shows over a few frames.
    fn run(doc: &EditorDoc) -> Vec<String> {
        let mut rt = Runtime::new(spreadlight_nodes::registry());
        let problems = rt.load(doc.top()).to_vec();
        assert!(problems.is_empty(), "{problems:?}");
        (0..4)
            .map(|f| {
                rt.evaluate(FrameClock::fixed(f * 7, 60.0));
                format!("{:?}", rt.probes().get("out").expect("the probe ran"))
            })
            .collect()
    }

    #[test]
    fn making_a_subpatch_keeps_what_the_patch_computes_and_undoes_in_one_step() {
        let registry = spreadlight_nodes::registry();
        let mut doc = chain();
        let before = doc.top().clone();
        let expected = run(&doc);
        let id = doc.make_subpatch(&registry, &[NodeId(2)]).expect("made");
        let node = doc.node(id).expect("the subpatch node");
        assert_eq!(node.type_name, "Subpatch");
        let def = &doc.top().subpatches["Subpatch"];
        assert_eq!(
            pin_names(def),
            (vec!["Input 1".to_owned()], vec!["Output".to_owned()])
        );
        assert_eq!(doc.patch().nodes.len(), 3, "LFO, Probe and the subpatch");
        assert_eq!(run(&doc), expected, "the crossing links became its pins");
        assert_eq!(doc.undo_label(), Some("make subpatch Subpatch"));
        assert!(doc.undo());
        assert_eq!(doc.top(), &before);
        assert!(doc.redo());
        assert_eq!(run(&doc), expected);
    }

    #[test]
    fn a_subpatch_opens_in_place_and_edits_inside_are_undone_there() {
        let registry = spreadlight_nodes::registry();
        let mut doc = chain();
        let id = doc.make_subpatch(&registry, &[NodeId(2)]).expect("made");
        assert!(doc.enter(id));
        assert_eq!(doc.scope(), ["Subpatch".to_owned()]);
        assert!(doc.patch().nodes.iter().any(|n| n.type_name == INLET));
        doc.set_value(NodeId(2), "Input 2", Some(vec![5.0f32].into()), false);
        assert_eq!(
            doc.top().subpatches["Subpatch"]
                .node(NodeId(2))
                .expect("inside")
                .values["Input 2"],
            vec![5.0f32].into(),
            "the edit lands in the definition"
        );
        doc.leave_to(0);
        assert!(doc.scope().is_empty());
        assert!(doc.undo(), "undo the edit made inside");
        assert_eq!(
            doc.scope(),
            ["Subpatch".to_owned()],
            "undo opens where the edit was"
        );
        assert_eq!(
            doc.patch().node(NodeId(2)).expect("inside").values["Input 2"],
            vec![3.0f32].into()
        );
    }

    #[test]
    fn inside_a_subpatch_iobox_pins_link_to_any_type_and_make_new_pins() {
        let registry = spreadlight_nodes::registry();
        let mut doc = chain();
        let id = doc.make_subpatch(&registry, &[NodeId(2)]).expect("made");
        assert!(doc.enter(id));
        let inlet = doc.add_node(INLET, (200.0, 0.0));
        let outlet = doc.add_node(OUTLET, (200.0, 120.0));
        let sine = doc.add_node("Sin (Value)", (200.0, 60.0));
        doc.set_value(inlet, "Name", Some(vec!["Angle".to_owned()].into()), false);
        doc.set_value(outlet, "Name", Some(vec!["Sine".to_owned()].into()), false);
        for (from, to) in [
            ((inlet, "Output"), (sine, "Input")),
            ((sine, "Output"), (outlet, "Input")),
        ] {
            doc.link(
                &registry,
                PinRef(from.0, from.1.to_owned()),
                PinRef(to.0, to.1.to_owned()),
            )
            .expect("links");
        }
        let (inputs, outputs) = pin_names(doc.patch());
        assert_eq!(inputs, ["Input 1", "Angle"]);
        assert_eq!(outputs, ["Output", "Sine"]);
        doc.leave_to(0);
        let (ins, outs) = spreadlight_graph::subpatch::pins_of(
            &doc.top().subpatches["Subpatch"],
            &registry,
            &Default::default(),
        );
        assert_eq!(
            outs[1].ty,
            spreadlight_graph::PinType::Float,
            "typed from inside"
        );
        assert_eq!(ins[1].ty, spreadlight_graph::PinType::Float);
    }

    #[test]
    fn undoing_the_making_of_the_open_subpatch_shows_the_patch_again() {
        let registry = spreadlight_nodes::registry();
        let mut doc = chain();
        let id = doc.make_subpatch(&registry, &[NodeId(2)]).expect("made");
        assert!(doc.enter(id));
        assert!(doc.undo());
        assert!(
            doc.scope().is_empty(),
            "the definition is gone, so is its breadcrumb"
        );
        assert_eq!(doc.patch().nodes.len(), 3);
    }

    #[test]
    fn unmaking_puts_the_nodes_back_with_their_links_and_values() {
        let registry = spreadlight_nodes::registry();
        let mut doc = chain();
        let expected = run(&doc);
        let id = doc.make_subpatch(&registry, &[NodeId(2)]).expect("made");
        let made = doc.top().clone();
        let back = doc.unmake_subpatch(id);
        assert_eq!(back.len(), 1);
        assert!(
            doc.top().subpatches.is_empty(),
            "its only node is gone, so is the definition"
        );
        assert_eq!(doc.patch().links.len(), 2);
        assert_eq!(run(&doc), expected);
        assert!(doc.undo());
        assert_eq!(doc.top(), &made);
    }

    #[test]
    fn a_value_on_a_pin_survives_unmaking() {
        let registry = spreadlight_nodes::registry();
        let mut doc = chain();
        let id = doc.make_subpatch(&registry, &[NodeId(2)]).expect("made");
        doc.unlink_input(&PinRef(id, "Input 1".to_owned()));
        doc.set_value(id, "Input 1", Some(vec![2.0f32].into()), false);
        let expected = run(&doc);
        let back = doc.unmake_subpatch(id);
        let node = doc.patch().node(back[0]).expect("back");
        assert_eq!(node.values["Input 1"], vec![2.0f32].into());
        assert_eq!(run(&doc), expected);
    }
}
