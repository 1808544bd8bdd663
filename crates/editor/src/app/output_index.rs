//! The top patch's `Output` nodes and what feeds each one's `Texture`,
//! indexed once per document generation. The first viewport asks for them
//! twice a frame; looking through every node and link each time made a frame
//! grow with the patch (16,000 nodes without an `Output`: a scan of all of
//! them, every time).

use std::cell::RefCell;
use std::collections::HashMap;

use spreadlight_graph::{NodeId, Patch};

/// The index, and the generation of the document it was built for.
#[derive(Default)]
pub(super) struct OutputIndex(RefCell<Option<(u64, Outputs)>>);

#[derive(Clone, Default)]
struct Outputs {
    /// The first `Output` in document order.
    first: Option<NodeId>,
    /// Each `Output` and the output pin linked into its `Texture`, if any.
    fed: HashMap<NodeId, Option<(NodeId, String)>>,
}

impl Outputs {
    fn of(patch: &Patch) -> Self {
        let mut out = Outputs::default();
        for n in patch.nodes.iter().filter(|n| n.type_name == "Output") {
            out.first.get_or_insert(n.id);
            out.fed.entry(n.id).or_insert(None);
        }
        for l in &patch.links {
            if l.to.pin() == "Texture"
                && let Some(slot) = out.fed.get_mut(&l.to.node())
                && slot.is_none()
            {
                *slot = Some((l.from.node(), l.from.pin().to_owned()));
            }
        }
        out
    }
}

impl OutputIndex {
    /// What feeds the `Texture` of the last of `selected` that is an
    /// `Output`, else of the first `Output`: `None` when there is no
    /// `Output`, `Some(None)` when the chosen one has nothing linked.
    pub(super) fn source<'a>(
        &self,
        generation: u64,
        patch: &Patch,
        selected: impl DoubleEndedIterator<Item = &'a NodeId>,
    ) -> Option<Option<(NodeId, String)>> {
        let mut cache = self.0.borrow_mut();
        if cache.as_ref().is_none_or(|(g, _)| *g != generation) {
            *cache = Some((generation, Outputs::of(patch)));
        }
        let (_, outputs) = cache.as_ref()?;
        let chosen = selected
            .rev()
            .find(|id| outputs.fed.contains_key(*id))
            .copied()
            .or(outputs.first)?;
        outputs.fed.get(&chosen).cloned()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use spreadlight_graph::NodeDoc;

    #[test]
    fn the_selected_output_wins_else_the_first_and_an_edit_reindexes() {
        let mut p = Patch::default();
        p.add(NodeDoc::new(1, "FileTexture"));
        p.add(NodeDoc::new(2, "Output"));
        p.add(NodeDoc::new(3, "Output"));
        p.add(NodeDoc::new(4, "Tonemap"));
        p.link(1, "Texture", 2, "Texture");
        p.link(4, "Output", 3, "Texture");
        let index = OutputIndex::default();
        let fed = |n: u32, pin: &str| Some(Some((NodeId(n), pin.to_owned())));
        assert_eq!(index.source(1, &p, [].iter()), fed(1, "Texture"));
        assert_eq!(
            index.source(1, &p, [NodeId(3), NodeId(4)].iter()),
            fed(4, "Output")
        );
        // The same generation answers from the index; a new one looks again.
        p.links.clear();
        assert_eq!(index.source(1, &p, [].iter()), fed(1, "Texture"));
        assert_eq!(index.source(2, &p, [].iter()), Some(None));
        p.nodes.retain(|n| n.type_name != "Output");
        assert_eq!(index.source(3, &p, [].iter()), None);
    }
}
