//! The one-key layout: nodes in layers in data-flow order, left to right
//! (L) or top to bottom (Shift+L) (a node one layer after the nearest node
//! it feeds, so links stay short), ordered within a layer to keep links from
//! crossing, stacked without overlap. Also aligning a selection in a row or
//! a column. Pure functions of the patch: the model records their moves as
//! one undo step.

use std::collections::{BTreeMap, HashMap, HashSet};

use spreadlight_graph::{NodeId, Patch, Registry};

use spreadlight_graph::subpatch::{INLET, OUTLET};

use super::measure::node_size;

/// Room between layers and between nodes of a layer, in canvas units.
pub const LAYER_GAP: f32 = 16.0;
pub const NODE_GAP: f32 = 6.0;

/// Which way data flows in a layout: the direction its layers follow each other.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Direction {
    /// Layers are columns, sources at the left (L).
    #[default]
    LeftToRight,
    /// Layers are rows, sources at the top (Shift+L), as vvvv patches read.
    TopToBottom,
}

/// New positions for `ids` (all nodes when empty), laid out from the top-left
/// corner of where they are now, layers following each other in `direction`.
/// Nodes not named keep their places.
///
/// The layout is worked out in "across" and "along" coordinates: layers
/// follow each other across (x left to right, y top to bottom) and nodes of a
/// layer stack along (y, or x). Pins stay on the nodes' sides either way.
pub fn layout(
    patch: &Patch,
    registry: &Registry,
    ids: &[NodeId],
    direction: Direction,
) -> Vec<(NodeId, (f32, f32))> {
    let down = direction == Direction::TopToBottom;
    let chosen: Vec<NodeId> = if ids.is_empty() {
        patch.nodes.iter().map(|n| n.id).collect()
    } else {
        let set: HashSet<NodeId> = ids.iter().copied().collect();
        let mut seen = HashSet::new();
        patch
            .nodes
            .iter()
            .map(|n| n.id)
            .filter(|id| set.contains(id) && seen.insert(*id))
            .collect()
    };
    if chosen.is_empty() {
        return Vec::new();
    }
    let index: HashMap<NodeId, usize> = chosen.iter().enumerate().map(|(i, &id)| (id, i)).collect();
    let n = chosen.len();
    // Looked up once: `Patch::node` is a linear search, and the sorts below ask often.
    let docs: HashMap<NodeId, &spreadlight_graph::NodeDoc> =
        patch.nodes.iter().map(|d| (d.id, d)).collect();
    let docs: Vec<Option<&spreadlight_graph::NodeDoc>> =
        chosen.iter().map(|id| docs.get(id).copied()).collect();
    let node = |i: usize| docs[i];
    // Each node's (across, along) extent and position.
    let swap = |(a, b): (f32, f32)| if down { (b, a) } else { (a, b) };
    let sizes: Vec<(f32, f32)> = (0..n)
        .map(|i| swap(node(i).map_or((40.0, 20.0), |d| node_size(d, registry, patch))))
        .collect();
    let along_pos = |i: usize| node(i).map_or(0.0, |d| swap(d.pos).1);
    // Edges among the chosen nodes, once per pair, with the input's index (to order by pin).
    let mut succ: Vec<Vec<usize>> = vec![Vec::new(); n];
    let mut pred: Vec<Vec<(usize, usize)>> = vec![Vec::new(); n];
    for l in &patch.links {
        let (Some(&a), Some(&b)) = (index.get(&l.from.node()), index.get(&l.to.node())) else {
            continue;
        };
        if a == b || succ[a].contains(&b) {
            continue;
        }
        let pin = node(b)
            .and_then(|d| registry.get(&d.type_name))
            .and_then(|def| def.input_index(l.to.pin()))
            .unwrap_or(0);
        succ[a].push(b);
        pred[b].push((a, pin));
    }
    let order = topological(&succ, &pred);
    // Longest path from the sources...
    let mut layer = vec![0usize; n];
    for &v in &order {
        for &w in &succ[v] {
            layer[w] = layer[w].max(layer[v] + 1);
        }
    }
    // ...then each node as far right as what it feeds allows: short links from constants.
    for &v in order.iter().rev() {
        if let Some(min) = succ[v].iter().map(|&w| layer[w]).min()
            && min > layer[v] + 1
        {
            layer[v] = min - 1;
        }
    }
    // A subpatch's Inlets stay first and its Outlets last: their order left
    // to right is its node's pin order (`graph::subpatch::ioboxes`).
    let last = layer.iter().copied().max().unwrap_or(0);
    let kind = |v: usize| node(v).map(|d| d.type_name.as_str());
    for (v, l) in layer.iter_mut().enumerate() {
        match kind(v) {
            Some(INLET) => *l = 0,
            Some(OUTLET) => *l = last.max(1),
            _ => {}
        }
    }
    let layers = layer.iter().copied().max().unwrap_or(0) + 1;
    let mut rows: Vec<Vec<usize>> = vec![Vec::new(); layers];
    // Start from the current order along a layer, so a layout keeps what the artist arranged.
    let mut by_y: Vec<usize> = (0..n).collect();
    by_y.sort_by(|&a, &b| along_pos(a).total_cmp(&along_pos(b)).then(a.cmp(&b)));
    for v in by_y {
        rows[layer[v]].push(v);
    }
    // Barycentre sweeps: each node moves towards the mean place of its neighbours.
    let mut place = vec![0.0f32; n];
    let set_places = |rows: &Vec<Vec<usize>>, place: &mut Vec<f32>| {
        for row in rows {
            for (k, &v) in row.iter().enumerate() {
                place[v] = k as f32;
            }
        }
    };
    set_places(&rows, &mut place);
    for sweep in 0..6 {
        let forward = sweep % 2 == 0;
        let range: Vec<usize> = if forward {
            (1..layers).collect()
        } else {
            (0..layers.saturating_sub(1)).rev().collect()
        };
        for l in range {
            let mut keyed: Vec<(f32, usize)> = rows[l]
                .iter()
                .map(|&v| {
                    let near: Vec<f32> = if forward {
                        pred[v]
                            .iter()
                            .map(|&(u, pin)| place[u] + pin as f32 * 0.01)
                            .collect()
                    } else {
                        succ[v].iter().map(|&w| place[w]).collect()
                    };
                    let key = if near.is_empty() {
                        place[v]
                    } else {
                        near.iter().sum::<f32>() / near.len() as f32
                    };
                    (key, v)
                })
                .collect();
            keyed.sort_by(|a, b| a.0.total_cmp(&b.0).then(place[a.1].total_cmp(&place[b.1])));
            rows[l] = keyed.into_iter().map(|(_, v)| v).collect();
            set_places(&rows, &mut place);
        }
    }
    if down {
        pin_order(
            &mut rows,
            &|v| kind(v),
            &|v| node(v).map_or(0.0, |d| d.pos.0),
            &chosen,
        );
    }
    // Columns (rows, top to bottom): each layer as wide as its widest node.
    let mut x = vec![0.0f32; layers];
    for l in 1..layers {
        let widest = rows[l - 1].iter().map(|&v| sizes[v].0).fold(0.0, f32::max);
        x[l] = x[l - 1] + widest + LAYER_GAP;
    }
    // Heights: the first layer stacked; later ones beside what feeds them, pushed down to not overlap.
    let mut y = vec![0.0f32; n];
    for (l, row) in rows.iter().enumerate() {
        let mut bottom = f32::NEG_INFINITY;
        for &v in row {
            let fed: Vec<f32> = pred[v]
                .iter()
                .filter(|&&(u, _)| layer[u] < l)
                .map(|&(u, _)| y[u])
                .collect();
            let want = if fed.is_empty() || l == 0 {
                bottom.max(0.0)
            } else {
                fed.iter().sum::<f32>() / fed.len() as f32
            };
            y[v] = if bottom.is_finite() {
                want.max(bottom + NODE_GAP)
            } else {
                want
            };
            bottom = y[v] + sizes[v].1;
        }
    }
    // Sources follow what they feed (a constant beside its consumer), still without overlap.
    for row in rows.iter().rev() {
        let mut bottom = f32::NEG_INFINITY;
        for &v in row {
            if pred[v].is_empty() && !succ[v].is_empty() {
                let want = succ[v].iter().map(|&w| y[w]).sum::<f32>() / succ[v].len() as f32;
                y[v] = want;
            }
            if bottom.is_finite() {
                y[v] = y[v].max(bottom + NODE_GAP);
            }
            bottom = y[v] + sizes[v].1;
        }
    }
    let origin = docs
        .iter()
        .filter_map(|d| d.map(|d| d.pos))
        .fold((f32::INFINITY, f32::INFINITY), |a, p| {
            (a.0.min(p.0), a.1.min(p.1))
        });
    // Keep the IOBoxes' order left to right (by x, then id): their pin order.
    let mut shift = vec![0.0f32; n];
    for k in [INLET, OUTLET] {
        let mut boxes: Vec<usize> = (0..n).filter(|&v| kind(v) == Some(k)).collect();
        boxes.sort_by(|&a, &b| {
            let xa = node(a).map_or(0.0, |d| d.pos.0);
            let xb = node(b).map_or(0.0, |d| d.pos.0);
            xa.total_cmp(&xb).then(chosen[a].cmp(&chosen[b]))
        });
        // Top to bottom they are a row, ordered so already (`pin_order`);
        // left to right a column, kept in order by a unit's shift right.
        if !down {
            for (rank, v) in boxes.into_iter().enumerate() {
                shift[v] = rank as f32;
            }
        }
    }
    let top = y.iter().copied().fold(f32::INFINITY, f32::min);
    (0..n)
        .map(|v| {
            let across = x[layer[v]] + shift[v];
            let along = y[v] - top;
            let (dx, dy) = if down {
                (along, across)
            } else {
                (across, along)
            };
            (
                chosen[v],
                ((origin.0 + dx).round(), (origin.1 + dy).round()),
            )
        })
        .collect()
}

/// A subpatch's `Inlet`s and `Outlet`s, each a row when laid out top to
/// bottom: their order along it is their node's pin order (by x, then id), so
/// each row's places held by one kind go to that kind in pin order.
fn pin_order<'p>(
    rows: &mut [Vec<usize>],
    kind: &dyn Fn(usize) -> Option<&'p str>,
    x: &dyn Fn(usize) -> f32,
    chosen: &[NodeId],
) {
    for k in [INLET, OUTLET] {
        for row in rows.iter_mut() {
            let slots: Vec<usize> = (0..row.len())
                .filter(|&s| kind(row[s]) == Some(k))
                .collect();
            let mut boxes: Vec<usize> = slots.iter().map(|&s| row[s]).collect();
            boxes.sort_by(|&a, &b| x(a).total_cmp(&x(b)).then(chosen[a].cmp(&chosen[b])));
            for (s, v) in slots.into_iter().zip(boxes) {
                row[s] = v;
            }
        }
    }
}

/// Kahn's order; nodes on a cycle (a broken patch) follow in document order.
fn topological(succ: &[Vec<usize>], pred: &[Vec<(usize, usize)>]) -> Vec<usize> {
    let n = succ.len();
    let mut indegree: Vec<usize> = pred.iter().map(Vec::len).collect();
    let mut ready: Vec<usize> = (0..n).filter(|&v| indegree[v] == 0).rev().collect();
    let mut order = Vec::with_capacity(n);
    let mut done = vec![false; n];
    while let Some(v) = ready.pop() {
        order.push(v);
        done[v] = true;
        for &w in &succ[v] {
            indegree[w] -= 1;
            if indegree[w] == 0 {
                ready.push(w);
            }
        }
    }
    order.extend((0..n).filter(|&v| !done[v]));
    order
}

/// `ids` lined up: in a row (same top) when they spread wider than tall, else
/// in a column (same left), in their current order and spaced so none overlap.
pub fn align(patch: &Patch, registry: &Registry, ids: &[NodeId]) -> Vec<(NodeId, (f32, f32))> {
    let mut nodes: Vec<_> = ids
        .iter()
        .filter_map(|&id| patch.node(id))
        .map(|n| (n.id, n.pos, node_size(n, registry, patch)))
        .collect();
    if nodes.len() < 2 {
        return Vec::new();
    }
    let span = |f: fn(&(f32, f32)) -> f32| {
        let v: Vec<f32> = nodes.iter().map(|n| f(&n.1)).collect();
        v.iter().copied().fold(f32::MIN, f32::max) - v.iter().copied().fold(f32::MAX, f32::min)
    };
    let row = span(|p| p.0) >= span(|p| p.1);
    if row {
        nodes.sort_by(|a, b| a.1.0.total_cmp(&b.1.0));
    } else {
        nodes.sort_by(|a, b| a.1.1.total_cmp(&b.1.1));
    }
    let line = if row {
        nodes.iter().map(|n| n.1.1).fold(f32::MAX, f32::min)
    } else {
        nodes.iter().map(|n| n.1.0).fold(f32::MAX, f32::min)
    };
    let mut next = f32::MIN;
    let mut moves = BTreeMap::new();
    for (id, pos, size) in nodes {
        let along = if row { pos.0 } else { pos.1 }.max(next);
        let p = if row { (along, line) } else { (line, along) };
        next = along + if row { size.0 } else { size.1 } + NODE_GAP;
        moves.insert(id, (p.0.round(), p.1.round()));
    }
    moves.into_iter().collect()
}

/// Positions that place `comments` (by index) in a column above the nodes'
/// and frames' bounds, first on top: where `spreadlight fmt --layout` puts them.
pub fn comments_above(patch: &Patch) -> Vec<(f32, f32)> {
    // Above the frames too: a comment must not cover a frame's title.
    let (left, top) = patch
        .nodes
        .iter()
        .map(|n| n.pos)
        .chain(patch.frames.iter().map(|f| f.pos))
        .fold((f32::INFINITY, f32::INFINITY), |a, p| {
            (a.0.min(p.0), a.1.min(p.1))
        });
    let (left, top) = if left.is_finite() {
        (left, top)
    } else {
        (0.0, 0.0)
    };
    let heights: Vec<f32> = patch
        .comments
        .iter()
        .map(|c| super::measure::comment_size(&c.text).1)
        .collect();
    let total: f32 = heights.iter().map(|h| h + NODE_GAP).sum();
    let mut y = top - total;
    heights
        .iter()
        .map(|h| {
            let p = (left, y.round());
            y += h + NODE_GAP;
            p
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::organise::measure::overlapping_nodes;
    use spreadlight_graph::NodeDoc;

    #[test]
    fn a_pile_of_nodes_is_laid_out_in_data_flow_order_without_overlap() {
        let registry = crate::nodes::registry();
        let mut p = Patch::default();
        // Everything on one spot, listed backwards.
        p.add(NodeDoc::new(3, "Probe").at(5.0, 5.0));
        p.add(NodeDoc::new(2, "Sin (Value)").at(5.0, 5.0));
        p.add(NodeDoc::new(1, "LFO").at(5.0, 5.0));
        p.add(NodeDoc::new(4, "Multiply (Value)").at(5.0, 5.0));
        p.link(1, "Output", 2, "Input");
        p.link(2, "Output", 4, "Input 1");
        p.link(4, "Output", 3, "Input");
        assert!(!overlapping_nodes(&p, &registry).is_empty());
        let moves = layout(&p, &registry, &[], Direction::LeftToRight);
        for (id, pos) in &moves {
            p.node_mut(*id).expect("node").pos = *pos;
        }
        assert!(overlapping_nodes(&p, &registry).is_empty());
        let x = |id: u32| p.node(NodeId(id)).expect("node").pos.0;
        assert!(x(1) < x(2) && x(2) < x(4) && x(4) < x(3), "{moves:?}");
        // Laid out from where the nodes were.
        assert_eq!(x(1), 5.0);
    }

    #[test]
    fn top_to_bottom_puts_each_layer_below_the_one_feeding_it_without_overlap() {
        let registry = crate::nodes::registry();
        let mut p = Patch::default();
        // A diamond, piled up: LFO feeds Sin and Cos, both feed Multiply.
        p.add(NodeDoc::new(1, "LFO").at(5.0, 5.0));
        p.add(NodeDoc::new(2, "Sin (Value)").at(5.0, 5.0));
        p.add(NodeDoc::new(3, "Cos (Value)").at(5.0, 5.0));
        p.add(NodeDoc::new(4, "Multiply (Value)").at(5.0, 5.0));
        p.add(NodeDoc::new(5, "Probe").at(5.0, 5.0));
        p.link(1, "Output", 2, "Input");
        p.link(1, "Output", 3, "Input");
        p.link(2, "Output", 4, "Input 1");
        p.link(3, "Output", 4, "Input 2");
        p.link(4, "Output", 5, "Input");
        let moves = layout(&p, &registry, &[], Direction::TopToBottom);
        assert_eq!(moves.len(), 5);
        for (id, pos) in &moves {
            p.node_mut(*id).expect("node").pos = *pos;
        }
        assert!(overlapping_nodes(&p, &registry).is_empty(), "{moves:?}");
        let at = |id: u32| p.node(NodeId(id)).expect("node").pos;
        let bottom = |id: u32| {
            let n = p.node(NodeId(id)).expect("node");
            n.pos.1 + node_size(n, &registry, &p).1
        };
        // Each layer starts below the bottom of the layer that feeds it.
        assert!(at(2).1 >= bottom(1) && at(3).1 >= bottom(1), "{moves:?}");
        assert!(at(4).1 >= bottom(2).max(bottom(3)), "{moves:?}");
        assert!(at(5).1 >= bottom(4), "{moves:?}");
        // Sin and Cos share a row, side by side.
        assert_eq!(at(2).1, at(3).1);
        assert_ne!(at(2).0, at(3).0);
        // Laid out from where the nodes were.
        assert_eq!(at(1).1, 5.0);
        let left = p
            .nodes
            .iter()
            .map(|n| n.pos.0)
            .fold(f32::INFINITY, f32::min);
        assert_eq!(left, 5.0);
    }

    #[test]
    fn top_to_bottom_keeps_a_subpatch_s_pin_order() {
        use spreadlight_graph::subpatch::{INLET, OUTLET};
        let registry = crate::nodes::registry();
        let mut p = Patch::default();
        let iobox = |id: u32, kind: &str, x: f32, name: &str| {
            NodeDoc::new(id, kind)
                .at(x, 0.0)
                .with("Name", vec![name.to_owned()])
        };
        // Pin order B (x 0), A (x 50); they feed the adder crosswise.
        p.add(iobox(1, INLET, 50.0, "A"));
        p.add(iobox(2, INLET, 0.0, "B"));
        p.add(NodeDoc::new(3, "Add (Value)").at(0.0, 0.0));
        p.add(iobox(4, OUTLET, 0.0, "Sum"));
        p.link(1, "Output", 3, "Input 1");
        p.link(2, "Output", 3, "Input 2");
        p.link(3, "Output", 4, "Input");
        let before: Vec<String> = spreadlight_graph::subpatch::ioboxes(&p, INLET)
            .iter()
            .map(|n| spreadlight_graph::subpatch::pin_name(n))
            .collect();
        for (id, pos) in layout(&p, &registry, &[], Direction::TopToBottom) {
            p.node_mut(id).expect("node").pos = pos;
        }
        let after: Vec<String> = spreadlight_graph::subpatch::ioboxes(&p, INLET)
            .iter()
            .map(|n| spreadlight_graph::subpatch::pin_name(n))
            .collect();
        assert_eq!(before, after);
        assert!(overlapping_nodes(&p, &registry).is_empty());
        let y = |id: u32| p.node(NodeId(id)).expect("node").pos.1;
        assert!(y(1) == y(2) && y(2) < y(3) && y(3) < y(4));
    }

    #[test]
    fn aligning_makes_a_row_without_overlap() {
        let registry = crate::nodes::registry();
        let mut p = Patch::default();
        p.add(NodeDoc::new(1, "LFO").at(0.0, 10.0));
        p.add(NodeDoc::new(2, "LFO").at(20.0, 0.0));
        p.add(NodeDoc::new(3, "LFO").at(200.0, 30.0));
        let ids = [NodeId(1), NodeId(2), NodeId(3)];
        for (id, pos) in align(&p, &registry, &ids) {
            p.node_mut(id).expect("node").pos = pos;
        }
        let ys: Vec<f32> = p.nodes.iter().map(|n| n.pos.1).collect();
        assert_eq!(ys, vec![0.0, 0.0, 0.0]);
        assert!(overlapping_nodes(&p, &registry).is_empty());
        assert_eq!(
            p.node(NodeId(3)).expect("node").pos.0,
            200.0,
            "far enough already"
        );
    }
}
