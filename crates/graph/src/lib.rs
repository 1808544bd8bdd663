//! Spreadlight's graph crate: the patch document and its `.ron` format,
//! spreads and pin types, the node registry, and the dataflow runtime that
//! evaluates a patch frame by frame. No GPU and no UI: everything here runs
//! headless and deterministically.

pub mod clock;
pub mod diagnostics;
pub mod document;
pub mod format;
pub mod network;
pub mod node;
pub mod organise;
pub mod pin;
pub mod registry;
pub mod runtime;
pub mod snapshot;
pub mod spelling;
pub mod spread;
pub mod stats;
pub mod subpatch;
pub mod typed_pins;
pub mod value;

pub use clock::FrameClock;
pub use diagnostics::{FedSink, Problem, ProblemKind, Severity};
pub use document::{FORMAT_VERSION, LinkDoc, NodeDoc, NodeId, Patch, PinRef};
pub use format::FormatError;
pub use network::Network;
pub use node::{AfterEvaluate, EvalContext, Node, NodeError, PatchDir, ProbeLog, Services};
pub use organise::{CommentDoc, FrameDoc};
pub use registry::{Memory, NodeDef, PinDef, Registry};
pub use runtime::Runtime;
pub use snapshot::RuntimeSnapshot;
pub use spread::{SliceValue, Spread};
pub use stats::{FrameStats, NodeRun, NodeStat};
pub use typed_pins::{AnySpread, Choice, Choices, In, Out, Pins, Res};
pub use value::{Color, EnumDef, PinType, Resource, ResourceKind};
