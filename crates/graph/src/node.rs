//! What a node's code sees: the [`Node`] trait and the [`EvalContext`] it
//! evaluates in (its input spreads, its output slots, the clock, the probes).

use std::collections::BTreeMap;
use std::sync::Arc;

use thiserror::Error;

use crate::clock::FrameClock;
use crate::pin::PinDef;
use crate::spread::{SliceValue, Spread};

/// An error of one node's evaluation. The node outputs nothing that frame;
/// the rest of the graph keeps evaluating.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum NodeError {
    #[error("input `{pin}`: {message}")]
    Input { pin: String, message: String },
    #[error("{0}")]
    Other(String),
}

/// The code of a node type. One instance per node in the running patch; it may keep state.
pub trait Node: Send {
    fn evaluate(&mut self, cx: &mut EvalContext<'_>) -> Result<(), NodeError>;
}

/// Values recorded by `Probe` nodes, by probe name.
pub type ProbeLog = BTreeMap<String, Arc<Spread>>;

/// Shared services the host provides to nodes, by type: the renderer, for
/// instance. The graph crate knows none of them; nodes ask by type.
#[derive(Clone, Default)]
pub struct Services {
    by_type: BTreeMap<std::any::TypeId, Arc<dyn std::any::Any + Send + Sync>>,
}

impl Services {
    pub fn provide<T: std::any::Any + Send + Sync>(&mut self, service: Arc<T>) {
        self.by_type.insert(std::any::TypeId::of::<T>(), service);
    }

    pub fn get<T: std::any::Any + Send + Sync>(&self) -> Option<Arc<T>> {
        self.by_type
            .get(&std::any::TypeId::of::<T>())
            .and_then(|s| s.clone().downcast::<T>().ok())
    }
}

/// Everything a node may read or write while it evaluates.
pub struct EvalContext<'a> {
    pub clock: &'a FrameClock,
    inputs: &'a [Arc<Spread>],
    input_defs: &'a [PinDef],
    outputs: &'a mut [Arc<Spread>],
    probes: &'a mut ProbeLog,
    services: &'a Services,
    /// The node's id, for nodes that label GPU work or errors with it.
    pub node_id: crate::document::NodeId,
    reevaluate: bool,
    reported: Option<NodeError>,
}

/// A check a host runs after every node evaluates, whose message (when it
/// returns one) fails that node: for what the node's work caused beyond its
/// own code's sight. A GPU host reports here the device errors that no error
/// scope caught while the node ran, so they name the node instead of
/// panicking in wgpu's default handler or surfacing later elsewhere.
pub struct AfterEvaluate(pub Box<dyn Fn() -> Option<String> + Send + Sync>);

/// The folder of the patch being evaluated: a service hosts provide so that
/// relative file names on pins resolve beside the patch.
#[derive(Clone, Debug)]
pub struct PatchDir(pub std::path::PathBuf);

impl<'a> EvalContext<'a> {
    pub fn new(
        clock: &'a FrameClock,
        inputs: &'a [Arc<Spread>],
        input_defs: &'a [PinDef],
        outputs: &'a mut [Arc<Spread>],
        probes: &'a mut ProbeLog,
        services: &'a Services,
        node_id: crate::document::NodeId,
    ) -> Self {
        EvalContext {
            clock,
            inputs,
            input_defs,
            outputs,
            probes,
            services,
            node_id,
            reevaluate: false,
            reported: None,
        }
    }

    /// A service the host provided (e.g. the renderer), if any.
    pub fn service<T: std::any::Any + Send + Sync>(&self) -> Option<Arc<T>> {
        self.services.get::<T>()
    }

    /// A file name from a pin as a path: relative names are relative to the
    /// patch's folder when the host says where the patch is ([`PatchDir`]),
    /// as in vvvv, so a patch and its files move together.
    pub fn resolve_path(&self, name: &str) -> std::path::PathBuf {
        let path = std::path::Path::new(name);
        match self.service::<PatchDir>() {
            Some(dir) if path.is_relative() => dir.0.join(path),
            _ => path.to_path_buf(),
        }
    }

    /// Evaluate this node again next frame even if its inputs do not change:
    /// for outputs that depend on the previous frame (velocity after a move settles to zero).
    pub fn reevaluate_next_frame(&mut self) {
        self.reevaluate = true;
    }

    pub(crate) fn wants_reevaluation(&self) -> bool {
        self.reevaluate
    }

    /// Show `error` on the node although it produced its outputs: a shader
    /// node whose file broke keeps rendering its last good version.
    pub fn report(&mut self, error: NodeError) {
        self.reported = Some(error);
    }

    pub(crate) fn take_report(&mut self) -> Option<NodeError> {
        self.reported.take()
    }

    /// How many input pins the node has.
    pub fn input_count(&self) -> usize {
        self.inputs.len()
    }

    pub fn input(&self, index: usize) -> &Spread {
        &self.inputs[index]
    }

    /// The shared input spread itself (cheap to pass on unchanged).
    pub fn input_arc(&self, index: usize) -> &Arc<Spread> {
        &self.inputs[index]
    }

    /// The slices of input `index` as their Rust type.
    pub fn slices<T: SliceValue>(&self, index: usize) -> Result<&[T], NodeError> {
        T::slices(&self.inputs[index]).ok_or_else(|| NodeError::Input {
            pin: self.input_defs[index].name.to_string(),
            message: format!(
                "expected {}, got {}",
                T::PIN_TYPE,
                self.inputs[index].type_name()
            ),
        })
    }

    /// The option names of an enum input.
    pub fn enum_slices(&self, index: usize) -> Result<&[String], NodeError> {
        match &*self.inputs[index] {
            Spread::Enum(v) => Ok(v),
            other => Err(self.input_error(
                index,
                format!("expected an enum, got {}", other.type_name()),
            )),
        }
    }

    /// An error naming input `index`, for node code to return.
    pub fn input_error(&self, index: usize, message: impl Into<String>) -> NodeError {
        NodeError::Input {
            pin: self.input_defs[index].name.to_string(),
            message: message.into(),
        }
    }

    pub fn set_output(&mut self, index: usize, spread: Spread) {
        self.outputs[index] = Arc::new(spread);
    }

    /// Pass an already shared spread on without copying it.
    pub fn set_output_arc(&mut self, index: usize, spread: Arc<Spread>) {
        self.outputs[index] = spread;
    }

    pub fn set<T: SliceValue>(&mut self, index: usize, values: Vec<T>) {
        self.set_output(index, T::into_spread(values));
    }

    /// Record a probed value under `name` (what `spreadlight eval --probe` prints).
    pub fn record_probe(&mut self, name: &str, value: Arc<Spread>) {
        match self.probes.get_mut(name) {
            Some(slot) => *slot = value,
            None => {
                self.probes.insert(name.to_owned(), value);
            }
        }
    }
}
