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
    /// The node's id in its own document.
    pub id: NodeId,
    /// The subpatch nodes it lies in, outermost first (empty at the top).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub within: Vec<NodeId>,
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
    /// A node of the top patch.
    pub fn node(&self, id: NodeId) -> Option<&NodeStat> {
        self.nodes
            .iter()
            .find(|n| n.id == id && n.within.is_empty())
    }

    /// The node at a path: the subpatch nodes around it, then its own id.
    pub fn node_at(&self, path: &[NodeId]) -> Option<&NodeStat> {
        let (id, within) = path.split_last()?;
        self.nodes
            .iter()
            .find(|n| n.id == *id && n.within == within)
    }

    /// Every node inside the subpatch instance at `path`, at any depth.
    pub fn inside<'a>(&'a self, path: &'a [NodeId]) -> impl Iterator<Item = &'a NodeStat> + 'a {
        self.nodes
            .iter()
            .filter(move |n| n.within.starts_with(path))
    }
}
