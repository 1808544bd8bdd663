//! The dataflow runtime: evaluates a compiled [`Network`] frame by frame.
//!
//! Demand-driven: only nodes that feed a sink run. Cached: a node runs again
//! only when an input changed (tracked by output versions, not by comparing
//! spreads) or when it depends on time. A failing node outputs nothing that
//! frame and everything else keeps going.

use std::sync::Arc;
use std::time::Instant;

use crate::clock::FrameClock;
use crate::diagnostics::Problem;
use crate::document::{NodeId, Patch};
use crate::network::{InputSource, Network, NetworkNode};
use crate::node::{AfterEvaluate, EvalContext, Node, NodeError, PatchDir, ProbeLog, Services};
use crate::registry::{NodeDef, Registry};
use crate::snapshot::RuntimeSnapshot;
use crate::spread::Spread;
use crate::stats::{FrameStats, NodeRun, NodeStat};
use crate::subpatch::Library;

/// The running state of one node.
struct NodeState {
    instance: Option<Box<dyn Node>>,
    inputs: Vec<Arc<Spread>>,
    /// For each linked input, the version of the upstream output last read.
    seen: Vec<u64>,
    outputs: Vec<Arc<Spread>>,
    /// An empty spread of each output's type, made once: the outputs start
    /// each evaluation from these (an `Arc` an output a frame otherwise, for
    /// every node that runs again: issue 33).
    empties: Vec<Arc<Spread>>,
    /// Bumped (from one counter for the whole runtime) whenever the outputs are recomputed; 0 = never.
    version: u64,
    /// Must run next frame whatever its inputs say (new node, or its values or links changed).
    dirty: bool,
    error: Option<NodeError>,
}

const UNSEEN: u64 = u64::MAX;

/// Evaluates a patch. Load a patch with [`Runtime::load`], then call
/// [`Runtime::evaluate`] once per frame.
pub struct Runtime {
    registry: Registry,
    /// Shared with the [`RuntimeSnapshot`]s taken since the last load.
    network: Arc<Network>,
    states: Vec<NodeState>,
    probes: ProbeLog,
    stats: FrameStats,
    versions: u64,
    services: Services,
    /// Subpatch files; `None` until the host sets one or a load finds the patch's folder.
    library: Option<Library>,
    /// Whether the host chose the library (otherwise it follows the [`PatchDir`] service).
    library_set: bool,
    /// Output pins the host looks at besides the sinks ([`Runtime::demand_also`]), by path.
    also: Vec<(Vec<NodeId>, String)>,
    /// What runs: the network's demand with `also`'s nodes and what feeds them.
    demand: Vec<bool>,
}

impl Runtime {
    pub fn new(registry: Registry) -> Self {
        Runtime {
            registry,
            network: Arc::default(),
            states: Vec::new(),
            probes: ProbeLog::new(),
            stats: FrameStats::default(),
            versions: 0,
            services: Services::default(),
            library: None,
            library_set: false,
            also: Vec::new(),
            demand: Vec::new(),
        }
    }

    /// Evaluate these output pins (a node's path and pin name) too, and what
    /// feeds them, though no sink needs them: the editor previews a branch
    /// this way. Without it (as `render` and `play` run) only what feeds a
    /// sink is evaluated. Kept across loads; an empty list drops it.
    pub fn demand_also(&mut self, pins: Vec<(Vec<NodeId>, String)>) {
        if pins != self.also {
            self.also = pins;
            self.demand = self.demand_of(&self.network);
        }
    }

    fn demand_of(&self, network: &Network) -> Vec<bool> {
        let also: Vec<usize> = self
            .also
            .iter()
            .filter_map(|(path, pin)| {
                network
                    .index_at(path)
                    .or_else(|| network.instance_output(path, pin))
            })
            .collect();
        network.needed_with(&also)
    }

    /// Whether node `index` of the network runs: it feeds a sink or a pin
    /// demanded with [`Runtime::demand_also`].
    pub fn is_demanded(&self, index: usize) -> bool {
        self.demand.get(index).copied().unwrap_or(false)
    }

    /// Where subpatch files come from. Without this, a runtime uses
    /// [`Library::beside`] the folder its [`PatchDir`] service names (if any).
    pub fn set_library(&mut self, library: Library) {
        self.library = Some(library);
        self.library_set = true;
    }

    /// The subpatch library of the last load (refreshed at every load).
    pub fn library(&self) -> Option<&Library> {
        self.library.as_ref()
    }

    /// The library for the next compile, read again from disk.
    fn refreshed_library(&mut self) -> Library {
        if !self.library_set {
            let beside = self
                .services
                .get::<PatchDir>()
                .map(|dir| Library::beside(&dir.0));
            let stale = match (&self.library, &beside) {
                (Some(old), Some(new)) => old.dirs() != new.dirs(),
                (None, Some(_)) => true,
                _ => false,
            };
            if stale {
                self.library = beside;
            }
        }
        match &mut self.library {
            Some(library) => {
                library.refresh();
                library.clone()
            }
            None => Library::default(),
        }
    }

    /// Make a service (e.g. the renderer) available to every node.
    pub fn provide<T: std::any::Any + Send + Sync>(&mut self, service: Arc<T>) {
        self.services.provide(service);
    }

    /// Re-evaluate the sinks next frame even if nothing changed: a benchmark
    /// renders every frame this way, with the rest of the patch still cached.
    pub fn invalidate_sinks(&mut self) {
        for (node, state) in self.network.nodes().iter().zip(&mut self.states) {
            if node.def.as_ref().is_some_and(|d| d.sink) {
                state.dirty = true;
            }
        }
    }

    /// Re-evaluate every node next frame (benchmarks measure the full cost this way).
    pub fn invalidate_all(&mut self) {
        for state in &mut self.states {
            state.dirty = true;
        }
    }

    pub fn registry(&self) -> &Registry {
        &self.registry
    }

    /// Swap in a registry with types added, replaced or removed at run time;
    /// the next [`Runtime::load`] compiles against it and re-instantiates
    /// every node whose type definition changed, keeping its values and links.
    pub fn set_registry(&mut self, registry: Registry) {
        self.registry = registry;
    }

    /// Compile `patch` and make it the running one. Nodes that already ran
    /// keep their state and outputs where their type, values and links are
    /// unchanged, so editing one corner of a patch re-evaluates only that corner.
    pub fn load(&mut self, patch: &Patch) -> &[Problem] {
        let library = self.refreshed_library();
        let network = Network::compile_with(patch, &self.registry, &library);
        let mut old_states: Vec<Option<NodeState>> = std::mem::take(&mut self.states)
            .into_iter()
            .map(Some)
            .collect();
        let mut states = Vec::with_capacity(network.nodes().len());
        for node in network.nodes() {
            let reused = self
                .network
                .index_of(node.id)
                .filter(|&i| same_def(&self.network.nodes()[i], node))
                .and_then(|i| old_states[i].take().map(|s| (i, s)));
            let state = match reused {
                Some((old_index, mut state)) => {
                    let old = &self.network.nodes()[old_index];
                    if !same_inputs(&self.network, old, &network, node) {
                        state.dirty = true;
                        state.seen.fill(UNSEEN);
                    }
                    set_constants(&mut state, node);
                    state
                }
                None => new_state(node),
            };
            states.push(state);
        }
        self.stats.nodes = network
            .nodes()
            .iter()
            .enumerate()
            .map(|(i, n)| NodeStat {
                id: *network.path(i).last().unwrap_or(&n.id),
                within: network.path(i)[..network.path(i).len() - 1].to_vec(),
                type_name: n.type_name.clone(),
                run: NodeRun::Skipped,
                cpu_ns: 0,
            })
            .collect();
        self.states = states;
        self.demand = self.demand_of(&network);
        self.network = Arc::new(network);
        self.network.problems()
    }

    pub fn network(&self) -> &Network {
        &self.network
    }

    pub fn problems(&self) -> &[Problem] {
        self.network.problems()
    }

    /// Evaluate one frame at the given clock.
    pub fn evaluate(&mut self, clock: FrameClock) -> &FrameStats {
        let stats = &mut self.stats;
        stats.frame = clock.frame;
        stats.time = clock.time;
        (
            stats.evaluated,
            stats.failed,
            stats.reused,
            stats.skipped,
            stats.cpu_ns,
        ) = (0, 0, 0, 0, 0);

        let after = self.services.get::<AfterEvaluate>();
        for (i, node) in self.network.nodes().iter().enumerate() {
            let stat = &mut stats.nodes[i];
            stat.cpu_ns = 0;
            let def = match &node.def {
                Some(def) if self.demand[i] => def,
                _ => {
                    stat.run = NodeRun::Skipped;
                    stats.skipped += 1;
                    continue;
                }
            };
            // Links point only to earlier nodes, so upstream states are all in `before`.
            let (before, rest) = self.states.split_at_mut(i);
            let state = &mut rest[0];
            let mut changed = state.dirty || state.version == 0 || def.time_dependent;
            for (k, source) in node.inputs.iter().enumerate() {
                if let InputSource::Link {
                    node: up,
                    output,
                    convert,
                } = *source
                {
                    let upstream = &before[up];
                    if state.seen[k] != upstream.version {
                        changed = true;
                        state.seen[k] = upstream.version;
                        let spread = &upstream.outputs[output];
                        state.inputs[k] = match convert {
                            None => spread.clone(),
                            Some(ty) => {
                                Arc::new(spread.convert_to(ty).unwrap_or_else(|| Spread::empty(ty)))
                            }
                        };
                    }
                }
            }
            if !changed {
                stat.run = NodeRun::Reused;
                stats.reused += 1;
                continue;
            }
            for (slot, empty) in state.outputs.iter_mut().zip(&state.empties) {
                *slot = empty.clone();
            }
            if node.bypass {
                bypass(state, def);
                stat.run = NodeRun::Evaluated;
                stats.evaluated += 1;
                self.versions += 1;
                state.version = self.versions;
                state.dirty = false;
                continue;
            }
            let Some(instance) = state.instance.as_mut() else {
                continue;
            };
            let start = Instant::now();
            let (result, again, reported) = {
                let mut cx = EvalContext::new(
                    &clock,
                    &state.inputs,
                    &def.inputs,
                    &mut state.outputs,
                    &mut self.probes,
                    &self.services,
                    node.id,
                );
                let result = instance.evaluate(&mut cx);
                (result, cx.wants_reevaluation(), cx.take_report())
            };
            let result = match (result, after.as_ref().and_then(|check| (check.0)())) {
                (result, None) => result,
                (Ok(()), Some(caused)) => Err(NodeError::Other(caused)),
                (Err(e), Some(caused)) => Err(NodeError::Other(format!("{e}; and {caused}"))),
            };
            stat.cpu_ns = start.elapsed().as_nanos() as u64;
            stats.cpu_ns += stat.cpu_ns;
            stats.evaluated += 1;
            match result {
                Ok(()) => {
                    state.error = reported;
                    stat.run = NodeRun::Evaluated;
                }
                Err(e) => {
                    for (slot, empty) in state.outputs.iter_mut().zip(&state.empties) {
                        *slot = empty.clone();
                    }
                    state.error = Some(explain_unknown_input(&self.network, i, def, e));
                    stat.run = NodeRun::Failed;
                    stats.failed += 1;
                }
            }
            self.versions += 1;
            state.version = self.versions;
            state.dirty = again;
        }
        &self.stats
    }

    /// The statistics of the last evaluated frame.
    pub fn stats(&self) -> &FrameStats {
        &self.stats
    }

    /// Values recorded by `Probe` nodes, by probe name (the latest of each).
    pub fn probes(&self) -> &ProbeLog {
        &self.probes
    }

    /// The current spread on an output pin of a node of the top patch.
    pub fn output(&self, node: NodeId, pin: &str) -> Option<&Arc<Spread>> {
        self.output_at(&[node], pin)
    }

    /// The current spread on an output pin of the node at `path` (the
    /// subpatch nodes around it, then its own id); for a subpatch node, its
    /// output pin.
    pub fn output_at(&self, path: &[NodeId], pin: &str) -> Option<&Arc<Spread>> {
        if let Some(i) = self.network.index_at(path) {
            let k = self.network.nodes()[i].def.as_ref()?.output_index(pin)?;
            return self.states[i].outputs.get(k);
        }
        let i = self.network.instance_output(path, pin)?;
        self.states[i].outputs.first()
    }

    /// The error a node of the top patch returned in the frame it last ran, if any.
    pub fn node_error(&self, node: NodeId) -> Option<&NodeError> {
        self.node_error_at(&[node])
    }

    /// The last error of the node at `path`.
    pub fn node_error_at(&self, path: &[NodeId]) -> Option<&NodeError> {
        let i = self.network.index_at(path)?;
        self.states[i].error.as_ref()
    }

    /// Every node's last error, in evaluation order, by the node of the top
    /// patch it is (or lies in, for nodes inside subpatches).
    pub fn node_errors(&self) -> impl Iterator<Item = (NodeId, &NodeError)> {
        self.node_errors_at().map(|(path, e)| (path[0], e))
    }

    /// Every node's last error with its whole path (subpatch nodes, then its own id).
    pub fn node_errors_at(&self) -> impl Iterator<Item = (&[NodeId], &NodeError)> {
        self.states
            .iter()
            .enumerate()
            .filter_map(|(i, s)| s.error.as_ref().map(|e| (self.network.path(i), e)))
    }

    /// A read-only picture of the last frame (outputs, errors, statistics),
    /// cheap to take (spreads and the network are shared, not copied): a host
    /// that evaluates on another thread hands this to its UI.
    pub fn snapshot(&self) -> RuntimeSnapshot {
        RuntimeSnapshot {
            network: self.network.clone(),
            outputs: self.states.iter().map(|s| s.outputs.clone()).collect(),
            errors: self.states.iter().map(|s| s.error.clone()).collect(),
            stats: self.stats.clone(),
            probes: self.probes.clone(),
            library: self.library.clone(),
        }
    }

    /// The path of the node with flat id `id` (what GPU passes name as their owner).
    pub fn path_of(&self, id: NodeId) -> Option<&[NodeId]> {
        Some(self.network.path(self.network.index_of(id)?))
    }
}

/// A bypassed node's outputs: its first input goes to its first output of the
/// same type (or one it converts to, as a link would), the rest stay empty.
/// The node itself does not run, so it declares no GPU work either.
fn bypass(state: &mut NodeState, def: &crate::registry::NodeDef) {
    state.error = None;
    let (Some(input), Some(pin)) = (state.inputs.first(), def.inputs.first()) else {
        return;
    };
    let same = def.outputs.iter().position(|o| o.ty == pin.ty);
    let converted = || {
        def.outputs
            .iter()
            .enumerate()
            .find_map(|(k, o)| Some((k, input.convert_to(o.ty)?)))
    };
    match same {
        Some(k) => state.outputs[k] = input.clone(),
        None => {
            if let Some((k, spread)) = converted() {
                state.outputs[k] = Arc::new(spread);
            }
        }
    }
}

fn empty(ty: crate::value::PinType) -> Arc<Spread> {
    Arc::new(Spread::empty(ty))
}

fn new_state(node: &NetworkNode) -> NodeState {
    let (instance, outputs) = match &node.def {
        Some(def) => (
            Some(def.instantiate()),
            def.outputs.iter().map(|p| empty(p.ty)).collect(),
        ),
        None => (None, Vec::new()),
    };
    let mut state = NodeState {
        instance,
        inputs: Vec::new(),
        seen: vec![UNSEEN; node.inputs.len()],
        empties: outputs.clone(),
        outputs,
        version: 0,
        dirty: true,
        error: None,
    };
    set_constants(&mut state, node);
    state
}

fn set_constants(state: &mut NodeState, node: &NetworkNode) {
    state
        .inputs
        .resize_with(node.inputs.len(), || Arc::new(Spread::Float(Vec::new())));
    state.seen.resize(node.inputs.len(), UNSEEN);
    for (slot, source) in state.inputs.iter_mut().zip(&node.inputs) {
        if let InputSource::Constant(value) = source {
            *slot = value.clone();
        }
    }
}

/// Whether two compiled nodes run the same type definition (the same `Arc`:
/// a type replaced in the registry gives its nodes fresh instances).
fn same_def(a: &NetworkNode, b: &NetworkNode) -> bool {
    a.type_name == b.type_name
        && match (&a.def, &b.def) {
            (Some(x), Some(y)) => Arc::ptr_eq(x, y),
            (None, None) => true,
            _ => false,
        }
}

/// Whether a node reads the same things in two networks: the same constants
/// and links from the same upstream node ids and pins, bypassed alike.
fn same_inputs(a_net: &Network, a: &NetworkNode, b_net: &Network, b: &NetworkNode) -> bool {
    // Bypassing or un-bypassing changes what the node's outputs are.
    a.bypass == b.bypass
        && a.inputs.len() == b.inputs.len()
        && a.inputs.iter().zip(&b.inputs).all(|(x, y)| match (x, y) {
            (InputSource::Constant(u), InputSource::Constant(v)) => Arc::ptr_eq(u, v) || u == v,
            (
                InputSource::Link {
                    node: un,
                    output: uo,
                    convert: uc,
                },
                InputSource::Link {
                    node: vn,
                    output: vo,
                    convert: vc,
                },
            ) => a_net.nodes()[*un].id == b_net.nodes()[*vn].id && uo == vo && uc == vc,
            _ => false,
        })
}

/// An input error on an input linked from an unknown node type ("no
/// texture connected", where a texture is linked) says where the link
/// comes from and why it brings nothing: a misspelled type or a missing
/// shader file is the cause to fix, not this node.
fn explain_unknown_input(
    network: &Network,
    index: usize,
    def: &NodeDef,
    error: NodeError,
) -> NodeError {
    let NodeError::Input { pin, message } = error else {
        return error;
    };
    let source = def
        .input_index(&pin)
        .and_then(|k| network.fed_by_unknown(index, k));
    match source {
        Some(p) => {
            let place: Vec<String> = network.path(p).iter().map(NodeId::to_string).collect();
            NodeError::Input {
                message: format!(
                    "{message} (it is linked from node {} `{}`, an unknown node type that outputs nothing)",
                    place.join(" > "),
                    network.nodes()[p].type_name
                ),
                pin,
            }
        }
        None => NodeError::Input { pin, message },
    }
}
