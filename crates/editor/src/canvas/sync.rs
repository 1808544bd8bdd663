//! Snarl in step with the document: which document node each snarl node
//! shows, nodes and wires added or removed after an edit, and moves made on
//! the canvas back in patch units.

use std::collections::HashMap;

use egui::Pos2;
use egui_snarl::{InPinId, OutPinId, Snarl};
use spreadlight_graph::{NodeDoc, NodeId, Registry};

pub use crate::canvas_units::{CanvasNode, SCALE};
use crate::model::EditorDoc;

/// Bring snarl in line with the document, every frame: the document's nodes
/// that `keep` accepts (those near the view, `cull.rs`) and only those, and
/// after a change positions changed by undo, and the wires between them.
/// Between changes the canvas positions are the newer ones (a drag in
/// progress). Keeps snarl's ids for nodes that stay, so selection and layout
/// survive edits. A frame without a change to the document or to the nodes
/// kept costs a look at each node's rectangle.
pub fn sync(
    snarl: &mut Snarl<CanvasNode>,
    ids: &mut HashMap<NodeId, egui_snarl::NodeId>,
    doc: &EditorDoc,
    registry: &Registry,
    doc_changed: bool,
    keep: &dyn Fn(&NodeDoc) -> bool,
) {
    let patch = doc.patch();
    let mut kept_changed = false;
    ids.retain(|id, sid| {
        let stay = doc.node(*id).is_some_and(keep);
        if !stay {
            snarl.remove_node(*sid);
            kept_changed = true;
        }
        stay
    });
    for n in &patch.nodes {
        let want = Pos2::new(n.pos.0 * SCALE, n.pos.1 * SCALE);
        match ids.get(&n.id) {
            Some(&sid) => {
                // The document changed (an undone move, say): it wins.
                if doc_changed
                    && let Some(info) = snarl.get_node_info_mut(sid)
                    && (info.pos - want).length() > 0.5 * SCALE
                {
                    info.pos = want;
                }
            }
            None if keep(n) => {
                let sid = snarl.insert_node(want, CanvasNode(n.id));
                ids.insert(n.id, sid);
                kept_changed = true;
            }
            None => {}
        }
    }
    if !doc_changed && !kept_changed {
        return;
    }
    let mut wanted = std::collections::HashSet::new();
    for l in &patch.links {
        let (Some(&a), Some(&b)) = (ids.get(&l.from.node()), ids.get(&l.to.node())) else {
            continue;
        };
        let def = |id: NodeId| doc.node(id).and_then(|n| registry.get(&n.type_name));
        let (Some(da), Some(db)) = (def(l.from.node()), def(l.to.node())) else {
            continue;
        };
        let (Some(o), Some(i)) = (da.output_index(l.from.pin()), db.input_index(l.to.pin())) else {
            continue;
        };
        wanted.insert((
            OutPinId { node: a, output: o },
            InPinId { node: b, input: i },
        ));
    }
    let existing: Vec<(OutPinId, InPinId)> = snarl.wires().collect();
    for w in &existing {
        if !wanted.contains(w) {
            snarl.disconnect(w.0, w.1);
        }
    }
    for w in wanted {
        snarl.connect(w.0, w.1);
    }
}

/// Moves finished on the canvas, in patch units (rounded to whole units so saved files stay clean).
pub fn moved_nodes(snarl: &Snarl<CanvasNode>, doc: &EditorDoc) -> Vec<(NodeId, (f32, f32))> {
    snarl
        .nodes_pos_ids()
        .filter_map(|(_, pos, node)| {
            let n = doc.node(node.0)?;
            let want = Pos2::new(n.pos.0 * SCALE, n.pos.1 * SCALE);
            ((pos - want).length() > 0.5 * SCALE)
                .then(|| (node.0, ((pos.x / SCALE).round(), (pos.y / SCALE).round())))
        })
        .collect()
}
