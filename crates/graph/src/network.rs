//! The network: a patch compiled against the registry into what runs.
//!
//! Compiling checks every value and link once, so evaluation never has to:
//! each input of each node is either a link to an earlier node's output (the
//! nodes are kept in topological order) or a constant spread. Everything that
//! cannot run as written becomes a [`Problem`] on its node and is left out;
//! the document keeps it.

use std::collections::hash_map::Entry;
use std::collections::{HashMap, HashSet};
use std::sync::Arc;

use crate::diagnostics::{Problem, ProblemKind, Severity, link_text};
use crate::document::{NodeId, Patch};
use crate::registry::{Memory, NodeDef, Registry};
use crate::spread::Spread;
use crate::value::PinType;

/// Where an input's spread comes from.
#[derive(Clone, Debug, PartialEq)]
pub enum InputSource {
    /// Output `output` of the node at index `node` of the network (always an earlier one).
    /// `convert` is the input's type when the link needs a conversion (e.g. Int to Float).
    Link {
        node: usize,
        output: usize,
        convert: Option<PinType>,
    },
    /// A value from the patch, or the pin's default.
    Constant(Arc<Spread>),
}

/// One node of the network.
#[derive(Clone, Debug)]
pub struct NetworkNode {
    pub id: NodeId,
    pub type_name: String,
    /// `None` for a node type this build does not know: a placeholder that never evaluates.
    pub def: Option<Arc<NodeDef>>,
    pub inputs: Vec<InputSource>,
    /// Bypassed in the document: the runtime passes its first input through
    /// instead of running it (`Runtime::evaluate`).
    pub bypass: bool,
}

/// A compiled patch.
#[derive(Clone, Debug, Default)]
pub struct Network {
    nodes: Vec<NetworkNode>,
    index: HashMap<NodeId, usize>,
    needed: Vec<bool>,
    problems: Vec<Problem>,
    /// Where each node (by index) sits in the documents: the ids of the
    /// subpatch nodes around it, outermost first, then its own id there.
    paths: Vec<Vec<NodeId>>,
    by_path: HashMap<Vec<NodeId>, usize>,
    /// The flat `Outlet` (by index) behind each output pin of each subpatch instance.
    instance_outputs: HashMap<(Vec<NodeId>, String), usize>,
    /// The placeholder (by index) linked into (node index, input): that
    /// input gets an empty spread, and an error about it says why.
    fed_by_unknown: HashMap<(usize, usize), usize>,
}

/// What flattening adds to a compile: typed IOBoxes and the links' own texts.
pub(crate) struct CompileExtras<'a> {
    pub defs: HashMap<NodeId, Arc<NodeDef>>,
    pub link_labels: &'a [String],
    /// Definitions that compiling expands (subpatches): one still in the
    /// flat patch could not be expanded and never runs.
    pub expanded: fn(&NodeDef) -> bool,
}

struct Edge {
    from: usize,
    output: usize,
    to: usize,
    input: usize,
    convert: Option<PinType>,
    link: usize,
}

// `Network::compile` and `compile_with` (a patch with subpatches) are in
// subpatch/mod.rs: they flatten first, then come here.
impl Network {
    /// Compile an already flat patch (no subpatch nodes left).
    pub(crate) fn compile_flat(
        patch: &Patch,
        registry: &Registry,
        extras: &CompileExtras<'_>,
    ) -> Network {
        Compiler {
            patch,
            registry,
            extras,
            problems: Vec::new(),
            placeholder_links: Vec::new(),
        }
        .run()
    }

    /// Set where each node sits in the documents, from flat id to path.
    pub(crate) fn set_paths(
        &mut self,
        mut paths: HashMap<NodeId, Vec<NodeId>>,
        instance_outputs: HashMap<(Vec<NodeId>, String), NodeId>,
    ) {
        self.paths = self
            .nodes
            .iter()
            .map(|n| paths.remove(&n.id).unwrap_or_else(|| vec![n.id]))
            .collect();
        self.by_path = self
            .paths
            .iter()
            .enumerate()
            .map(|(i, p)| (p.clone(), i))
            .collect();
        self.instance_outputs = instance_outputs
            .into_iter()
            .filter_map(|(key, id)| Some((key, self.index_of(id)?)))
            .collect();
    }

    pub(crate) fn problems_mut(&mut self) -> &mut Vec<Problem> {
        &mut self.problems
    }

    /// Where node `index` sits: the subpatch nodes around it, outermost first, then its own id.
    pub fn path(&self, index: usize) -> &[NodeId] {
        &self.paths[index]
    }

    /// The node at a path of ids (a top-level node's path is its id alone).
    pub fn index_at(&self, path: &[NodeId]) -> Option<usize> {
        self.by_path.get(path).copied()
    }

    /// The node that carries output pin `pin` of the subpatch instance at `path`.
    pub fn instance_output(&self, path: &[NodeId], pin: &str) -> Option<usize> {
        self.instance_outputs
            .get(&(path.to_vec(), pin.to_owned()))
            .copied()
    }

    /// Nodes in evaluation (topological) order.
    pub fn nodes(&self) -> &[NetworkNode] {
        &self.nodes
    }

    pub fn index_of(&self, id: NodeId) -> Option<usize> {
        self.index.get(&id).copied()
    }

    /// Whether node `index` feeds a sink (or is one): only those are evaluated.
    pub fn is_needed(&self, index: usize) -> bool {
        self.needed[index]
    }

    /// Demand with `also` (node indices) demanded besides the sinks: what a
    /// host that looks at a node (the editor's previews) must evaluate. The
    /// network's own demand, the one `render` and `play` run, is unchanged.
    pub fn needed_with(&self, also: &[usize]) -> Vec<bool> {
        let mut needed = self.needed.clone();
        let mut grew = false;
        for &i in also {
            if let Some(n) = needed.get_mut(i) {
                grew |= !*n;
                *n = true;
            }
        }
        if grew {
            spread_demand(&self.nodes, &mut needed);
        }
        needed
    }

    pub fn problems(&self) -> &[Problem] {
        &self.problems
    }

    /// The unknown-type node (by index) linked into input `input` of node
    /// `index`, if one is: why that input is empty.
    pub fn fed_by_unknown(&self, index: usize, input: usize) -> Option<usize> {
        self.fed_by_unknown.get(&(index, input)).copied()
    }

    pub fn has_errors(&self) -> bool {
        self.problems.iter().any(|p| p.severity == Severity::Error)
    }

    /// How many earlier frames the outputs of the nodes that run depend on,
    /// and the types of the nodes that make it so (sorted, once each): what
    /// a render starting past frame 0 must evaluate first, and why. Memories
    /// add up along a chain (a frame delay of a frame delay remembers two
    /// frames); one unbounded node makes the whole network unbounded.
    pub fn memory(&self) -> (Memory, Vec<String>) {
        let add = |a: Memory, b: Memory| match (a, b) {
            (Memory::Unbounded, _) | (_, Memory::Unbounded) => Memory::Unbounded,
            (Memory::None, m) | (m, Memory::None) => m,
            (Memory::Frames(x), Memory::Frames(y)) => Memory::Frames(x.saturating_add(y)),
        };
        // Nodes are in topological order: every link comes from an earlier node.
        let mut upstream = vec![Memory::None; self.nodes.len()];
        for (i, node) in self.nodes.iter().enumerate() {
            let inputs = node
                .inputs
                .iter()
                .filter_map(|input| match input {
                    InputSource::Link { node, .. } => upstream.get(*node).copied(),
                    InputSource::Constant(_) => None,
                })
                .max()
                .unwrap_or(Memory::None);
            let own = node.def.as_ref().map_or(Memory::None, |d| d.memory);
            upstream[i] = add(own, inputs);
        }
        let running = |i: &usize| self.is_needed(*i);
        let most = (0..self.nodes.len())
            .filter(running)
            .map(|i| upstream[i])
            .max()
            .unwrap_or(Memory::None);
        let types: std::collections::BTreeSet<String> = (0..self.nodes.len())
            .filter(running)
            .filter_map(|i| self.nodes[i].def.as_ref())
            .filter(|d| match most {
                Memory::None => false,
                Memory::Frames(_) => d.memory != Memory::None,
                Memory::Unbounded => d.memory == Memory::Unbounded,
            })
            .map(|d| d.name.to_string())
            .collect();
        (most, types.into_iter().collect())
    }
}

struct Compiler<'a> {
    patch: &'a Patch,
    registry: &'a Registry,
    extras: &'a CompileExtras<'a>,
    problems: Vec<Problem>,
    /// (node, input, placeholder) by document index: inputs linked from an
    /// unknown type, which get an empty spread instead.
    placeholder_links: Vec<(usize, usize, usize)>,
}

impl Compiler<'_> {
    /// How messages quote link `index`: as the user wrote it, before flattening.
    fn link_label(&self, index: usize) -> String {
        match self.extras.link_labels.get(index) {
            Some(label) => label.clone(),
            None => link_text(&self.patch.links[index]),
        }
    }

    fn problem(
        &mut self,
        severity: Severity,
        doc_index: Option<usize>,
        id: NodeId,
        pin: Option<&str>,
        kind: ProblemKind,
    ) {
        let node_type = match doc_index {
            Some(i) => self.patch.nodes[i].type_name.clone(),
            None => "(missing)".to_owned(),
        };
        self.problems.push(Problem {
            severity,
            node: id,
            within: Vec::new(),
            node_type,
            pin: pin.map(str::to_owned),
            kind,
        });
    }

    fn run(mut self) -> Network {
        let patch = self.patch;
        // Ids first: a duplicate is left out, so every id names exactly one node.
        let mut by_id: HashMap<NodeId, usize> = HashMap::new();
        let mut included = Vec::new();
        for (i, node) in patch.nodes.iter().enumerate() {
            match by_id.entry(node.id) {
                Entry::Occupied(_) => self.problem(
                    Severity::Error,
                    Some(i),
                    node.id,
                    None,
                    ProblemKind::DuplicateNodeId,
                ),
                Entry::Vacant(slot) => {
                    slot.insert(i);
                    included.push(i);
                }
            }
        }

        let mut defs: Vec<Option<Arc<NodeDef>>> = vec![None; patch.nodes.len()];
        // (document index, index of its problem) of each unknown-type node.
        let mut placeholders = Vec::new();
        let mut inputs: Vec<Vec<InputSource>> = vec![Vec::new(); patch.nodes.len()];
        for &i in &included {
            let node = &patch.nodes[i];
            let def = match self.extras.defs.get(&node.id) {
                Some(def) => Some(def),
                // A subpatch's entry never runs: one still here could not be expanded.
                None => self
                    .registry
                    .get(&node.type_name)
                    .filter(|d| !(self.extras.expanded)(d)),
            };
            match def {
                Some(def) => {
                    inputs[i] = self.constant_inputs(i, def);
                    defs[i] = Some(def.clone());
                }
                None => {
                    placeholders.push((i, self.problems.len()));
                    let suggestion = self.registry.nearest(&node.type_name).map(str::to_owned);
                    self.problem(
                        Severity::Warning,
                        Some(i),
                        node.id,
                        None,
                        ProblemKind::UnknownNodeType {
                            suggestion,
                            feeds: None,
                        },
                    );
                }
            }
        }
        // Which sink each placeholder's work was meant for (known once every type is).
        for (i, problem) in placeholders {
            let sink = fed_sink(patch, &by_id, &defs, i);
            if let ProblemKind::UnknownNodeType { feeds, .. } = &mut self.problems[problem].kind {
                *feeds = sink;
            }
        }

        let edges = self.check_links(&by_id, &defs, &mut inputs);
        let (order, edges) = self.order_and_break_cycles(&included, edges);

        let mut net_index = vec![usize::MAX; patch.nodes.len()];
        for (k, &i) in order.iter().enumerate() {
            net_index[i] = k;
        }
        for e in &edges {
            inputs[e.to][e.input] = InputSource::Link {
                node: net_index[e.from],
                output: e.output,
                convert: e.convert,
            };
        }
        let nodes: Vec<NetworkNode> = order
            .iter()
            .map(|&i| NetworkNode {
                id: patch.nodes[i].id,
                type_name: patch.nodes[i].type_name.clone(),
                def: defs[i].clone(),
                inputs: std::mem::take(&mut inputs[i]),
                bypass: patch.nodes[i].bypass,
            })
            .collect();
        let index = nodes.iter().enumerate().map(|(k, n)| (n.id, k)).collect();
        let fed_by_unknown = self
            .placeholder_links
            .iter()
            .map(|&(to, k, from)| ((net_index[to], k), net_index[from]))
            .filter(|&((to, _), from)| to != usize::MAX && from != usize::MAX)
            .collect();
        let needed = needed_nodes(&nodes);
        let paths = nodes.iter().map(|n| vec![n.id]).collect();
        let by_path = nodes
            .iter()
            .enumerate()
            .map(|(k, n)| (vec![n.id], k))
            .collect();
        Network {
            nodes,
            index,
            needed,
            problems: self.problems,
            paths,
            by_path,
            instance_outputs: HashMap::new(),
            fed_by_unknown,
        }
    }

    /// The inputs from the patch's values, or the pins' defaults where a value is missing or bad.
    fn constant_inputs(&mut self, i: usize, def: &NodeDef) -> Vec<InputSource> {
        let node = &self.patch.nodes[i];
        let mut inputs: Vec<InputSource> = def
            .inputs
            .iter()
            .map(|p| InputSource::Constant(Arc::new(p.default.clone())))
            .collect();
        for (pin, value) in &node.values {
            let Some(k) = def.input_index(pin) else {
                if def.pins_unknown {
                    continue;
                }
                let available = def.inputs.iter().map(|p| p.name.to_string()).collect();
                self.problem(
                    Severity::Error,
                    Some(i),
                    node.id,
                    Some(pin),
                    ProblemKind::ValueForMissingPin { available },
                );
                continue;
            };
            let ty = def.inputs[k].ty;
            if !value.fits(ty) {
                let kind = ProblemKind::ValueWrongType {
                    expected: ty.name(),
                    found: value.type_name().to_owned(),
                };
                self.problem(Severity::Error, Some(i), node.id, Some(pin), kind);
                continue;
            }
            if let (PinType::Enum(enum_def), Spread::Enum(options)) = (ty, value)
                && let Some(bad) = options.iter().find(|o| enum_def.index_of(o).is_none())
            {
                let kind = ProblemKind::UnknownEnumOption {
                    value: bad.clone(),
                    options: enum_def.options.iter().map(|o| (*o).to_owned()).collect(),
                };
                self.problem(Severity::Error, Some(i), node.id, Some(pin), kind);
                continue;
            }
            if let Some(slice) = value.first_non_finite() {
                self.problem(
                    Severity::Error,
                    Some(i),
                    node.id,
                    Some(pin),
                    ProblemKind::NonFiniteValue { slice },
                );
                continue;
            }
            inputs[k] = InputSource::Constant(Arc::new(value.clone()));
        }
        inputs
    }

    fn check_links(
        &mut self,
        by_id: &HashMap<NodeId, usize>,
        defs: &[Option<Arc<NodeDef>>],
        inputs: &mut [Vec<InputSource>],
    ) -> Vec<Edge> {
        let mut edges = Vec::new();
        let mut linked: HashSet<(usize, usize)> = HashSet::new();
        for (li, link) in self.patch.links.iter().enumerate() {
            let text = self.link_label(li);
            let (from, to) = (
                by_id.get(&link.from.node()).copied(),
                by_id.get(&link.to.node()).copied(),
            );
            let Some(from) = from else {
                let kind = ProblemKind::LinkFromMissingNode { link: text };
                self.problem(
                    Severity::Error,
                    to,
                    link.to.node(),
                    Some(link.to.pin()),
                    kind,
                );
                continue;
            };
            let Some(to) = to else {
                let kind = ProblemKind::LinkToMissingNode { link: text };
                self.problem(
                    Severity::Error,
                    Some(from),
                    link.from.node(),
                    Some(link.from.pin()),
                    kind,
                );
                continue;
            };
            // A placeholder's pins are whatever the file says; check the known end only.
            let to_def = defs[to].clone();
            let input = match &to_def {
                Some(def) => match def.input_index(link.to.pin()) {
                    Some(k) => Some(k),
                    None if def.pins_unknown => continue,
                    None => {
                        let available = def.inputs.iter().map(|p| p.name.to_string()).collect();
                        let kind = ProblemKind::MissingInputPin { available };
                        self.problem(
                            Severity::Error,
                            Some(to),
                            link.to.node(),
                            Some(link.to.pin()),
                            kind,
                        );
                        continue;
                    }
                },
                None => None,
            };
            let Some(from_def) = defs[from].clone() else {
                // A placeholder outputs nothing: the input it feeds gets an empty spread.
                if let (Some(def), Some(k)) = (&to_def, input) {
                    inputs[to][k] =
                        InputSource::Constant(Arc::new(Spread::empty(def.inputs[k].ty)));
                    self.placeholder_links.push((to, k, from));
                }
                continue;
            };
            let Some(output) = from_def.output_index(link.from.pin()) else {
                if from_def.pins_unknown {
                    // As from a placeholder: the input it feeds gets an empty spread.
                    if let (Some(def), Some(k)) = (&to_def, input) {
                        inputs[to][k] =
                            InputSource::Constant(Arc::new(Spread::empty(def.inputs[k].ty)));
                    }
                    continue;
                }
                let available = from_def
                    .outputs
                    .iter()
                    .map(|p| p.name.to_string())
                    .collect();
                let kind = ProblemKind::MissingOutputPin { available };
                self.problem(
                    Severity::Error,
                    Some(from),
                    link.from.node(),
                    Some(link.from.pin()),
                    kind,
                );
                continue;
            };
            let (Some(to_def), Some(input)) = (to_def, input) else {
                continue;
            };
            let (from_ty, to_ty) = (from_def.outputs[output].ty, to_def.inputs[input].ty);
            if !from_ty.links_to(to_ty) {
                let kind = ProblemKind::IncompatibleLink {
                    link: text,
                    from_type: from_ty.name(),
                    to_type: to_ty.name(),
                };
                self.problem(
                    Severity::Error,
                    Some(to),
                    link.to.node(),
                    Some(link.to.pin()),
                    kind,
                );
                continue;
            }
            if !linked.insert((to, input)) {
                let kind = ProblemKind::InputLinkedTwice { link: text };
                self.problem(
                    Severity::Error,
                    Some(to),
                    link.to.node(),
                    Some(link.to.pin()),
                    kind,
                );
                continue;
            }
            let convert = (from_ty != to_ty).then_some(to_ty);
            edges.push(Edge {
                from,
                output,
                to,
                input,
                convert,
                link: li,
            });
        }
        edges
    }

    /// A topological order of the included nodes, by depth-first search in
    /// patch order. A link that closes a cycle is reported and left out.
    fn order_and_break_cycles(
        &mut self,
        included: &[usize],
        edges: Vec<Edge>,
    ) -> (Vec<usize>, Vec<Edge>) {
        let n = self.patch.nodes.len();
        let mut out_edges: Vec<Vec<usize>> = vec![Vec::new(); n];
        for (k, e) in edges.iter().enumerate() {
            out_edges[e.from].push(k);
        }
        #[derive(Clone, Copy, PartialEq)]
        enum Mark {
            New,
            Open,
            Done,
        }
        let mut mark = vec![Mark::New; n];
        let mut broken = vec![false; edges.len()];
        let mut postorder = Vec::with_capacity(included.len());
        // Iterative, so a chain of 100,000 nodes cannot overflow the stack.
        let mut stack: Vec<(usize, usize)> = Vec::new();
        for &root in included {
            if mark[root] != Mark::New {
                continue;
            }
            mark[root] = Mark::Open;
            stack.push((root, 0));
            while let Some(&mut (node, ref mut next)) = stack.last_mut() {
                if let Some(&k) = out_edges[node].get(*next) {
                    *next += 1;
                    let target = edges[k].to;
                    match mark[target] {
                        Mark::New => {
                            mark[target] = Mark::Open;
                            stack.push((target, 0));
                        }
                        Mark::Open => {
                            broken[k] = true;
                            let start = stack.iter().position(|&(s, _)| s == target).unwrap_or(0);
                            let mut path: Vec<NodeId> = stack[start..]
                                .iter()
                                .map(|&(s, _)| self.patch.nodes[s].id)
                                .collect();
                            path.push(self.patch.nodes[target].id);
                            let link = &self.patch.links[edges[k].link];
                            let kind = ProblemKind::Cycle {
                                link: self.link_label(edges[k].link),
                                path,
                            };
                            self.problem(
                                Severity::Error,
                                Some(target),
                                link.to.node(),
                                Some(link.to.pin()),
                                kind,
                            );
                        }
                        Mark::Done => {}
                    }
                } else {
                    mark[node] = Mark::Done;
                    postorder.push(node);
                    stack.pop();
                }
            }
        }
        postorder.reverse();
        let edges = edges
            .into_iter()
            .zip(broken)
            .filter(|(_, b)| !b)
            .map(|(e, _)| e)
            .collect();
        (postorder, edges)
    }
}

/// The sink nearest downstream of the node at document index `start`,
/// following the document's links (a placeholder's links never reach the
/// network, which replaces them by empty inputs): where its work was going.
fn fed_sink(
    patch: &Patch,
    by_id: &HashMap<NodeId, usize>,
    defs: &[Option<Arc<NodeDef>>],
    start: usize,
) -> Option<crate::diagnostics::FedSink> {
    let mut seen = HashSet::from([start]);
    let mut queue = std::collections::VecDeque::from([start]);
    while let Some(from) = queue.pop_front() {
        let id = patch.nodes[from].id;
        for link in patch.links.iter().filter(|l| l.from.node() == id) {
            let Some(&to) = by_id.get(&link.to.node()) else {
                continue;
            };
            if !seen.insert(to) {
                continue;
            }
            if defs[to].as_ref().is_some_and(|d| d.sink) {
                return Some(crate::diagnostics::FedSink {
                    path: vec![patch.nodes[to].id],
                    node_type: patch.nodes[to].type_name.clone(),
                });
            }
            queue.push_back(to);
        }
    }
    None
}

/// Demand: sinks are needed, and so is everything that feeds a needed node.
/// One backward pass suffices because links only point forward in the order.
fn needed_nodes(nodes: &[NetworkNode]) -> Vec<bool> {
    let mut needed: Vec<bool> = nodes
        .iter()
        .map(|n| n.def.as_ref().is_some_and(|d| d.sink))
        .collect();
    spread_demand(nodes, &mut needed);
    needed
}

/// Everything that feeds a needed node is needed too.
fn spread_demand(nodes: &[NetworkNode], needed: &mut [bool]) {
    for i in (0..nodes.len()).rev() {
        if !needed[i] {
            continue;
        }
        for input in &nodes[i].inputs {
            if let InputSource::Link { node, .. } = input {
                needed[*node] = true;
            }
        }
    }
}
