//! Per-frame runtime statistics: what ran, what was reused, what was not
//! needed, and what each node cost. Tests assert on these; the editor shows them.

use serde::Serialize;

use crate::document::NodeId;

/// What happened to one node in one frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub enum NodeRun {
    /// Its code ran and succeeded.
    Evaluated,
    /// Its code ran and returned an error; it outputs nothing.
    Failed,
    /// Its inputs had not changed and it does not depend on time: last outputs reused.
    Reused,
    /// It feeds no sink (or is a placeholder): not evaluated at all.
    Skipped,
}

#[derive(Clone, Debug, Serialize)]
pub struct NodeStat {
    pub id: NodeId,
    pub type_name: String,
    pub run: NodeRun,
    /// CPU time of the node's own code this frame, in nanoseconds (0 unless it ran).
    pub cpu_ns: u64,
}

#[derive(Clone, Debug, Default, Serialize)]
pub struct FrameStats {
    pub frame: u64,
    pub time: f64,
    /// Nodes whose code ran (including those that failed).
    pub evaluated: usize,
    pub failed: usize,
    pub reused: usize,
    /// Nodes not needed by any sink, and placeholders.
    pub skipped: usize,
    /// Sum of the nodes' CPU times, in nanoseconds.
    pub cpu_ns: u64,
    /// One entry per node, in evaluation order.
    pub nodes: Vec<NodeStat>,
}

impl FrameStats {
    pub fn node(&self, id: NodeId) -> Option<&NodeStat> {
        self.nodes.iter().find(|n| n.id == id)
    }
}
