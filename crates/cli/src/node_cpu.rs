//! `bench`'s CPU per node: for each node, the median over the timed frames
//! of its own evaluation time (the runtime's `cpu_ns`; a frame it was
//! reused or skipped counts as nothing), the costliest first. A patch's
//! evaluation then shows where it goes on a host with no profiler.
//!
//! Output nodes are left out: their time is their frame graph's recording
//! and their waits for the GPU, which `bench` shows as recording and leaves
//! out of the CPU.

use std::collections::BTreeMap;

use serde::Serialize;
use spreadlight_graph::{FrameStats, NodeId, NodeRun};

/// The sink whose frame graph `bench` times apart.
const OUTPUT: &str = "Output";

/// Each node's CPU times over the frames pushed.
#[derive(Default)]
pub struct NodeCpu {
    /// By path (the subpatch nodes around it, then its id): its type and
    /// its times in milliseconds, one per frame it ran.
    nodes: BTreeMap<Vec<NodeId>, (String, Vec<f64>)>,
    frames: usize,
}

/// One node's median CPU over the frames.
#[derive(Debug, Serialize, PartialEq)]
pub struct NodeCost {
    /// Its path: subpatch node ids, then its own, joined by `/`.
    pub node: String,
    #[serde(rename = "type")]
    pub type_name: String,
    pub median_ms: f64,
    /// The frames its code ran in (of all those pushed).
    pub evaluated: usize,
}

impl NodeCpu {
    /// Adds one frame's statistics.
    pub fn push(&mut self, stats: &FrameStats) {
        self.frames += 1;
        for n in &stats.nodes {
            if matches!(n.run, NodeRun::Evaluated | NodeRun::Failed) && n.type_name != OUTPUT {
                let path = n.within.iter().copied().chain([n.id]).collect();
                let (_, times) = self
                    .nodes
                    .entry(path)
                    .or_insert_with(|| (n.type_name.clone(), Vec::new()));
                times.push(n.cpu_ns as f64 / 1e6);
            }
        }
    }

    /// The `count` nodes of the largest median CPU, the costliest first.
    pub fn costliest(&self, count: usize) -> Vec<NodeCost> {
        let mut costs: Vec<NodeCost> = self
            .nodes
            .iter()
            .map(|(path, (type_name, times))| {
                // The frames it did not run in cost it nothing.
                let mut all = times.clone();
                all.resize(self.frames.max(times.len()), 0.0);
                all.sort_by(f64::total_cmp);
                NodeCost {
                    node: path
                        .iter()
                        .map(|id| id.0.to_string())
                        .collect::<Vec<_>>()
                        .join("/"),
                    type_name: type_name.clone(),
                    median_ms: all[all.len() / 2],
                    evaluated: times.len(),
                }
            })
            .collect();
        costs.sort_by(|a, b| b.median_ms.total_cmp(&a.median_ms));
        costs.truncate(count);
        costs
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use spreadlight_graph::NodeStat;

    fn frame(nodes: &[(u32, &str, NodeRun, u64)]) -> FrameStats {
        FrameStats {
            nodes: nodes
                .iter()
                .map(|&(id, type_name, run, cpu_ns)| NodeStat {
                    id: NodeId(id),
                    within: Vec::new(),
                    type_name: type_name.to_owned(),
                    run,
                    cpu_ns,
                })
                .collect(),
            ..FrameStats::default()
        }
    }

    #[test]
    fn the_costliest_nodes_come_first_and_frames_they_did_not_run_cost_nothing() {
        let mut cpu = NodeCpu::default();
        use NodeRun::*;
        cpu.push(&frame(&[
            (1, "glTF", Evaluated, 900_000),
            (2, "Camera", Evaluated, 10_000),
        ]));
        cpu.push(&frame(&[
            (1, "glTF", Evaluated, 700_000),
            (2, "Camera", Reused, 0),
        ]));
        cpu.push(&frame(&[
            (1, "glTF", Evaluated, 800_000),
            (2, "Camera", Reused, 0),
        ]));
        cpu.push(&frame(&[
            (1, "glTF", Failed, 600_000),
            (3, "Output", Skipped, 0),
        ]));
        let costs = cpu.costliest(5);
        assert_eq!(
            costs.len(),
            2,
            "a node that never ran is not listed: {costs:?}"
        );
        assert_eq!(costs[0].type_name, "glTF");
        assert_eq!(costs[0].evaluated, 4);
        assert!((costs[0].median_ms - 0.8).abs() < 1e-12, "{costs:?}");
        // Camera ran in one frame of four: its median is nothing.
        assert_eq!((costs[1].node.as_str(), costs[1].evaluated), ("2", 1));
        assert_eq!(costs[1].median_ms, 0.0);
        assert_eq!(cpu.costliest(1).len(), 1);
    }
}
