//! Flattening: a patch with subpatch nodes becomes one flat patch of plain
//! nodes, each subpatch instance replaced by a copy of its inside.
//!
//! Each inner node of each instance gets its own id in the flat patch (a hash
//! of its path, stable across edits), so state is per instance, caching and
//! demand work node by node across subpatch borders, and statistics count
//! every inner node. The subpatch's IOBoxes stay as pass-through nodes: a
//! parent link into pin `P` becomes a link into the `Inlet` named `P`, a
//! parent value on `P` becomes that `Inlet`'s value.

use std::collections::{HashMap, HashSet};

use crate::diagnostics::{Problem, ProblemKind, Severity, link_text};
use crate::document::{LinkDoc, NodeDoc, NodeId, Patch, PinRef};
use crate::registry::Registry;

use super::library::Library;
use super::pins::{INLET, OUTLET, ioboxes, is_iobox, pin_name};

/// The flat patch, and how to find each of its nodes in the documents.
#[derive(Default)]
pub(crate) struct Flat {
    pub patch: Patch,
    /// Each flat link's text as the user wrote it (for messages).
    pub link_labels: Vec<String>,
    /// For each flat node: the path of ids from the top document (enclosing subpatch nodes, then its own).
    pub paths: HashMap<NodeId, Vec<NodeId>>,
    /// For each instance's output pin (by the instance's path): the flat `Outlet` that carries it.
    pub instance_outputs: HashMap<(Vec<NodeId>, String), NodeId>,
    /// For each flat `Inlet` the parent feeds (by link or value): which node and pin feeds it.
    pub fed_inlets: HashMap<NodeId, Fed>,
    /// Problems found while flattening.
    pub problems: Vec<Problem>,
    /// Flat placeholders whose "unknown type" warning a flattening error replaces.
    pub explained: HashSet<NodeId>,
    /// Bypassed instances, to be short-circuited once their IOBoxes are typed.
    pub bypassed: Vec<BypassedInstance>,
}

/// A bypassed subpatch instance: its first `Inlet` and its `Outlet`s, in pin order.
pub(crate) struct BypassedInstance {
    pub first_inlet: Option<NodeId>,
    pub outlets: Vec<NodeId>,
}

/// A subpatch's pins of one direction, in order: name and the flat IOBox behind it.
type Pins = Vec<(String, NodeId)>;

/// The parent's subpatch node and pin behind a flat `Inlet`.
pub(crate) struct Fed {
    pub path: Vec<NodeId>,
    pub node_type: String,
    pub pin: String,
}

/// What a node of one document is in the flat patch.
enum Local {
    Plain(NodeId),
    Instance { inputs: Pins, outputs: Pins },
}

/// Inline definitions visible from a document: its own, then its parents'.
struct Scope<'s> {
    doc: &'s Patch,
    parent: Option<&'s Scope<'s>>,
}

/// A subpatch definition found by name, and the scope its inside sees.
enum Found<'s> {
    Inline(&'s Patch, Option<&'s Scope<'s>>),
    File(std::sync::Arc<Patch>),
    Unreadable(String),
}

pub(crate) fn flatten(patch: &Patch, registry: &Registry, library: &Library) -> Flat {
    let mut f = Flattener {
        registry,
        library,
        flat: Flat::default(),
        used: patch.nodes.iter().map(|n| n.id.0).collect(),
        index: HashMap::new(),
    };
    f.flat.patch.version = patch.version;
    f.expand(patch, None, &[], &[]);
    f.flat
}

struct Flattener<'a> {
    registry: &'a Registry,
    library: &'a Library,
    flat: Flat,
    /// Flat ids taken (the top document's own ids are reserved first).
    used: HashSet<u32>,
    /// Flat id to position in `flat.patch.nodes`.
    index: HashMap<NodeId, usize>,
}

impl Flattener<'_> {
    /// A flat id for the node `id` of the document at `within`: the top
    /// document keeps its ids; inner nodes get a hash of their path above
    /// 2^31, probing past the rare collision.
    fn alloc(&mut self, within: &[NodeId], id: NodeId) -> NodeId {
        if within.is_empty() {
            return id;
        }
        let mut h: u32 = 0x811c_9dc5;
        for part in within.iter().chain([&id]) {
            for byte in part.0.to_le_bytes() {
                h = (h ^ u32::from(byte)).wrapping_mul(0x0100_0193);
            }
        }
        let mut candidate = 0x8000_0000 | h;
        while !self.used.insert(candidate) {
            candidate = 0x8000_0000 | candidate.wrapping_add(1);
        }
        NodeId(candidate)
    }

    fn push(&mut self, flat_id: NodeId, path: Vec<NodeId>, node: &NodeDoc) {
        self.index.insert(flat_id, self.flat.patch.nodes.len());
        self.flat.patch.nodes.push(NodeDoc {
            id: flat_id,
            ..node.clone()
        });
        self.flat.paths.insert(flat_id, path);
    }

    fn problem(&mut self, within: &[NodeId], node: &NodeDoc, pin: Option<&str>, kind: ProblemKind) {
        let severity = match kind {
            ProblemKind::DuplicatePinName { .. } => Severity::Warning,
            _ => Severity::Error,
        };
        self.flat.problems.push(Problem {
            severity,
            node: node.id,
            within: within.to_vec(),
            node_type: node.type_name.clone(),
            pin: pin.map(str::to_owned),
            kind,
        });
    }

    fn find<'s>(&self, name: &str, scope: Option<&'s Scope<'s>>) -> Option<Found<'s>> {
        let mut at = scope;
        while let Some(s) = at {
            if let Some(def) = s.doc.subpatches.get(name) {
                return Some(Found::Inline(def, Some(s)));
            }
            at = s.parent;
        }
        let entry = self.library.get(name)?;
        Some(match &entry.definition {
            Ok(def) => Found::File(def.clone()),
            Err(e) => Found::Unreadable(e.clone()),
        })
    }

    /// Put the nodes and links of `doc` (the inside of the subpatch node at
    /// `within`, or the top patch) into the flat patch. Returns its pins.
    fn expand<'s>(
        &mut self,
        doc: &'s Patch,
        parent: Option<&'s Scope<'s>>,
        within: &[NodeId],
        chain: &[String],
    ) -> (Pins, Pins) {
        let scope = Scope { doc, parent };
        let mut locals: HashMap<NodeId, Local> = HashMap::new();
        for node in &doc.nodes {
            let mut path = within.to_vec();
            path.push(node.id);
            match locals.get(&node.id) {
                Some(Local::Plain(first)) => {
                    // A duplicate id: the same flat id, so compiling reports it.
                    let first = *first;
                    self.push(first, path, node);
                    continue;
                }
                Some(Local::Instance { .. }) => {
                    self.problem(within, node, None, ProblemKind::DuplicateNodeId);
                    continue;
                }
                None => {}
            }
            let flat_id = self.alloc(within, node.id);
            let builtin = self
                .registry
                .get(&node.type_name)
                .is_some_and(|def| !super::is_subpatch_def(def));
            let local = if is_iobox(&node.type_name) || builtin {
                self.push(flat_id, path, node);
                Local::Plain(flat_id)
            } else {
                self.instance(node, flat_id, path, &scope, within, chain)
            };
            locals.insert(node.id, local);
        }
        for link in &doc.links {
            self.link(doc, within, link, &locals);
        }
        let mut pins = |kind: &str| {
            let mut seen = HashSet::new();
            let mut out = Vec::new();
            for node in ioboxes(doc, kind) {
                let name = pin_name(node);
                let Some(Local::Plain(flat_id)) = locals.get(&node.id) else {
                    continue;
                };
                if seen.insert(name.clone()) {
                    out.push((name, *flat_id));
                } else {
                    self.problem(
                        within,
                        node,
                        Some("Name"),
                        ProblemKind::DuplicatePinName { name },
                    );
                }
            }
            out
        };
        (pins(INLET), pins(OUTLET))
    }

    /// A node that is no built-in type: an instance of a subpatch, or a placeholder.
    fn instance<'s>(
        &mut self,
        node: &NodeDoc,
        flat_id: NodeId,
        path: Vec<NodeId>,
        scope: &'s Scope<'s>,
        within: &[NodeId],
        chain: &[String],
    ) -> Local {
        let placeholder = |f: &mut Self, path: Vec<NodeId>, kind: Option<ProblemKind>| {
            if let Some(kind) = kind {
                f.problem(within, node, None, kind);
                f.flat.explained.insert(flat_id);
            }
            f.push(flat_id, path, node);
            Local::Plain(flat_id)
        };
        let name = &node.type_name;
        if chain.contains(name) {
            let start = chain.iter().position(|c| c == name).unwrap_or(0);
            let mut cycle = chain[start..].to_vec();
            cycle.push(name.clone());
            return placeholder(
                self,
                path,
                Some(ProblemKind::RecursiveSubpatch { chain: cycle }),
            );
        }
        let mut inner_chain = chain.to_vec();
        inner_chain.push(name.clone());
        let first_inner = self.flat.patch.nodes.len();
        let (inputs, outputs) = match self.find(name, Some(scope)) {
            None => return placeholder(self, path, None),
            Some(Found::Unreadable(message)) => {
                return placeholder(
                    self,
                    path,
                    Some(ProblemKind::UnreadableSubpatch { message }),
                );
            }
            Some(Found::Inline(def, def_scope)) => self.expand(def, def_scope, &path, &inner_chain),
            Some(Found::File(def)) => self.expand(&def, None, &path, &inner_chain),
        };
        for (pin, value) in &node.values {
            match inputs.iter().find(|(name, _)| name == pin) {
                Some((_, inlet)) => {
                    let k = self.index[inlet];
                    self.flat.patch.nodes[k]
                        .values
                        .insert("Input".to_owned(), value.clone());
                    let fed = Fed {
                        path: path.clone(),
                        node_type: node.type_name.clone(),
                        pin: pin.clone(),
                    };
                    self.flat.fed_inlets.insert(*inlet, fed);
                }
                None => {
                    let available = inputs.iter().map(|(n, _)| n.clone()).collect();
                    self.problem(
                        within,
                        node,
                        Some(pin),
                        ProblemKind::ValueForMissingPin { available },
                    );
                }
            }
        }
        for (pin, outlet) in &outputs {
            self.flat
                .instance_outputs
                .insert((path.clone(), pin.clone()), *outlet);
        }
        if node.bypass {
            self.bypass(first_inner, &inputs, &outputs);
        }
        Local::Instance { inputs, outputs }
    }

    /// A bypassed instance does not run, as a bypassed node does not: every
    /// node of its inside (nested instances' too, all pushed from
    /// `first_inner` on) is bypassed, and `compile` later links its first
    /// `Inlet` straight to the matching `Outlet` (`short_circuit`).
    fn bypass(&mut self, first_inner: usize, inputs: &Pins, outputs: &Pins) {
        let own: HashSet<NodeId> = inputs.iter().chain(outputs).map(|(_, id)| *id).collect();
        for node in &mut self.flat.patch.nodes[first_inner..] {
            if !own.contains(&node.id) {
                node.bypass = true;
            }
        }
        self.flat.bypassed.push(BypassedInstance {
            first_inlet: inputs.first().map(|(_, id)| *id),
            outlets: outputs.iter().map(|(_, id)| *id).collect(),
        });
    }

    fn link(
        &mut self,
        doc: &Patch,
        within: &[NodeId],
        link: &LinkDoc,
        locals: &HashMap<NodeId, Local>,
    ) {
        let node_doc = |id: NodeId| doc.nodes.iter().find(|n| n.id == id);
        let text = link_text(link);
        let (from, to) = (locals.get(&link.from.node()), locals.get(&link.to.node()));
        let (Some(from), Some(to)) = (from, to) else {
            // One end is missing: say so on the end that exists.
            let (present, pin, kind) = match (from, to) {
                (None, _) => (
                    link.to.node(),
                    link.to.pin(),
                    ProblemKind::LinkFromMissingNode { link: text },
                ),
                _ => (
                    link.from.node(),
                    link.from.pin(),
                    ProblemKind::LinkToMissingNode { link: text },
                ),
            };
            match node_doc(present) {
                Some(node) => self.problem(within, node, Some(pin), kind),
                None => self.flat.problems.push(Problem {
                    severity: Severity::Error,
                    node: present,
                    within: within.to_vec(),
                    node_type: "(missing)".to_owned(),
                    pin: Some(pin.to_owned()),
                    kind,
                }),
            }
            return;
        };
        let from = match from {
            Local::Plain(id) => PinRef(*id, link.from.pin().to_owned()),
            Local::Instance { outputs, .. } => {
                match outputs.iter().find(|(n, _)| n == link.from.pin()) {
                    Some((_, outlet)) => PinRef(*outlet, "Output".to_owned()),
                    None => {
                        let available = outputs.iter().map(|(n, _)| n.clone()).collect();
                        if let Some(node) = node_doc(link.from.node()) {
                            self.problem(
                                within,
                                node,
                                Some(link.from.pin()),
                                ProblemKind::MissingOutputPin { available },
                            );
                        }
                        return;
                    }
                }
            }
        };
        let to = match to {
            Local::Plain(id) => PinRef(*id, link.to.pin().to_owned()),
            Local::Instance { inputs, .. } => match inputs.iter().find(|(n, _)| n == link.to.pin())
            {
                Some((_, inlet)) => {
                    let mut path = within.to_vec();
                    path.push(link.to.node());
                    let node_type =
                        node_doc(link.to.node()).map_or(String::new(), |n| n.type_name.clone());
                    let fed = Fed {
                        path,
                        node_type,
                        pin: link.to.pin().to_owned(),
                    };
                    self.flat.fed_inlets.insert(*inlet, fed);
                    PinRef(*inlet, "Input".to_owned())
                }
                None => {
                    let available = inputs.iter().map(|(n, _)| n.clone()).collect();
                    if let Some(node) = node_doc(link.to.node()) {
                        self.problem(
                            within,
                            node,
                            Some(link.to.pin()),
                            ProblemKind::MissingInputPin { available },
                        );
                    }
                    return;
                }
            },
        };
        self.flat.patch.links.push(LinkDoc { from, to });
        self.flat.link_labels.push(text);
    }
}

/// Short-circuit each bypassed instance once its IOBoxes are typed: the
/// links into its `Outlet`s (from its inside) go, and its first `Inlet` feeds
/// its first `Outlet` of the same type, else the first one its type links to
/// (Int to Float, Color and Vec4), as `Runtime`'s bypass of a plain node
/// does. The other `Outlet`s, unlinked, pass on their empty default.
pub(crate) fn short_circuit(
    flat: &mut Flat,
    typed: &HashMap<NodeId, (crate::PinType, crate::Spread)>,
) {
    let ty = |id: &NodeId| typed.get(id).map(|(ty, _)| *ty);
    for instance in std::mem::take(&mut flat.bypassed) {
        let outlets: HashSet<NodeId> = instance.outlets.iter().copied().collect();
        let mut k = 0;
        while k < flat.patch.links.len() {
            if outlets.contains(&flat.patch.links[k].to.node()) {
                flat.patch.links.remove(k);
                if k < flat.link_labels.len() {
                    flat.link_labels.remove(k);
                }
            } else {
                k += 1;
            }
        }
        let Some(inlet) = instance.first_inlet else {
            continue;
        };
        let Some(from) = ty(&inlet) else {
            continue;
        };
        let target = instance
            .outlets
            .iter()
            .find(|o| ty(o) == Some(from))
            .or_else(|| {
                instance
                    .outlets
                    .iter()
                    .find(|o| ty(o).is_some_and(|to| from.links_to(to)))
            });
        if let Some(&outlet) = target {
            let link = LinkDoc::new(inlet.0, "Output", outlet.0, "Input");
            flat.link_labels.push(link_text(&link));
            flat.patch.links.push(link);
        }
    }
}
