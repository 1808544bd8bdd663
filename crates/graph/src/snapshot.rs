//! A read-only picture of a [`Runtime`](crate::Runtime) after a frame: what a
//! UI shows (live values, errors, statistics) while the runtime itself works
//! on the next frame on another thread. Its readers mirror the runtime's.

use std::sync::Arc;

use crate::diagnostics::Problem;
use crate::document::NodeId;
use crate::network::Network;
use crate::node::{NodeError, ProbeLog};
use crate::spread::Spread;
use crate::stats::FrameStats;
use crate::subpatch::Library;

/// Taken with [`Runtime::snapshot`](crate::Runtime::snapshot). Spreads are
/// shared `Arc`s and the network is shared until the next load, so taking one
/// costs a few pointer copies per node.
#[derive(Clone, Debug, Default)]
pub struct RuntimeSnapshot {
    pub(crate) network: Arc<Network>,
    /// Each node's outputs, in the network's order.
    pub(crate) outputs: Vec<Vec<Arc<Spread>>>,
    pub(crate) errors: Vec<Option<NodeError>>,
    pub(crate) stats: FrameStats,
    pub(crate) probes: ProbeLog,
    pub(crate) library: Option<Library>,
}

impl RuntimeSnapshot {
    pub fn network(&self) -> &Network {
        &self.network
    }

    pub fn problems(&self) -> &[Problem] {
        self.network.problems()
    }

    /// The statistics of the frame.
    pub fn stats(&self) -> &FrameStats {
        &self.stats
    }

    pub fn probes(&self) -> &ProbeLog {
        &self.probes
    }

    /// The subpatch library of the last load.
    pub fn library(&self) -> Option<&Library> {
        self.library.as_ref()
    }

    /// The spread on an output pin of a node of the top patch.
    pub fn output(&self, node: NodeId, pin: &str) -> Option<&Arc<Spread>> {
        self.output_at(&[node], pin)
    }

    /// As [`Runtime::output_at`](crate::Runtime::output_at).
    pub fn output_at(&self, path: &[NodeId], pin: &str) -> Option<&Arc<Spread>> {
        if let Some(i) = self.network.index_at(path) {
            let k = self.network.nodes()[i].def.as_ref()?.output_index(pin)?;
            return self.outputs.get(i)?.get(k);
        }
        let i = self.network.instance_output(path, pin)?;
        self.outputs.get(i)?.first()
    }

    pub fn node_error(&self, node: NodeId) -> Option<&NodeError> {
        self.node_error_at(&[node])
    }

    pub fn node_error_at(&self, path: &[NodeId]) -> Option<&NodeError> {
        let i = self.network.index_at(path)?;
        self.errors.get(i)?.as_ref()
    }

    /// Every node's error, by the node of the top patch it is (or lies in).
    pub fn node_errors(&self) -> impl Iterator<Item = (NodeId, &NodeError)> {
        self.errors
            .iter()
            .enumerate()
            .filter_map(|(i, e)| e.as_ref().map(|e| (self.network.path(i)[0], e)))
    }

    /// The path of the node with flat id `id`.
    pub fn path_of(&self, id: NodeId) -> Option<&[NodeId]> {
        Some(self.network.path(self.network.index_of(id)?))
    }
}

#[cfg(test)]
mod tests {
    use crate::document::{LinkDoc, NodeDoc, Patch};
    use crate::{FrameClock, NodeDef, NodeId, Registry, Runtime, Spread};

    fn registry() -> Registry {
        let mut r = Registry::new();
        r.add(
            NodeDef::new("Source", "Test", "a value")
                .input("In", 2.0f32)
                .output::<f32>("Out")
                .evaluate(|cx| {
                    let v: Vec<f32> = cx.slices::<f32>(0)?.to_vec();
                    cx.set(0, v);
                    Ok(())
                }),
        );
        r.add(
            NodeDef::new("Sink", "Test", "fails on negatives")
                .input("In", 0.0f32)
                .sink()
                .evaluate(|cx| {
                    if cx.slices::<f32>(0)?.iter().any(|v| *v < 0.0) {
                        return Err(cx.input_error(0, "negative"));
                    }
                    Ok(())
                }),
        );
        r
    }

    #[test]
    fn a_snapshot_reads_as_the_runtime_did_and_keeps_its_frame() {
        let mut rt = Runtime::new(registry());
        let mut p = Patch::default();
        p.add(NodeDoc::new(1, "Source").with("In", Spread::Float(vec![-1.0, 3.0])));
        p.add(NodeDoc::new(2, "Sink"));
        p.links.push(LinkDoc::new(1, "Out", 2, "In"));
        rt.load(&p);
        rt.evaluate(FrameClock::default());
        let snap = rt.snapshot();
        assert_eq!(
            snap.output(NodeId(1), "Out").map(|s| (**s).clone()),
            Some(Spread::Float(vec![-1.0, 3.0]))
        );
        assert_eq!(snap.node_error(NodeId(2)), rt.node_error(NodeId(2)));
        assert!(snap.node_error(NodeId(2)).is_some());
        assert_eq!(snap.node_errors().count(), 1);
        assert_eq!(snap.stats().evaluated, rt.stats().evaluated);
        assert_eq!(snap.path_of(NodeId(2)), Some(&[NodeId(2)][..]));

        // The runtime moves on; the snapshot still shows its own frame.
        p.nodes[0]
            .values
            .insert("In".into(), Spread::Float(vec![5.0]));
        rt.load(&p);
        rt.evaluate(FrameClock::default());
        assert_eq!(
            rt.output(NodeId(1), "Out").map(|s| (**s).clone()),
            Some(Spread::Float(vec![5.0]))
        );
        assert_eq!(
            snap.output(NodeId(1), "Out").map(|s| (**s).clone()),
            Some(Spread::Float(vec![-1.0, 3.0]))
        );
        assert!(rt.node_error(NodeId(2)).is_none());
        assert!(snap.node_error(NodeId(2)).is_some());
    }
}
