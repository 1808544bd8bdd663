//! The one-key layout: nodes in layers left to right in data-flow order
//! (a node one layer right of the nearest node it feeds, so links stay
//! short), ordered within a layer to keep links from crossing, stacked
//! without overlap. Also aligning a selection in a row or a column. Pure
//! functions of the patch: the model records their moves as one undo step.

use std::collections::{BTreeMap, HashMap, HashSet};

use spreadlight_graph::{NodeId, Patch, Registry};

use spreadlight_graph::subpatch::{INLET, OUTLET};

use super::measure::node_size;

/// Room between layers and between nodes of a layer, in canvas units.
pub const LAYER_GAP: f32 = 16.0;
pub const NODE_GAP: f32 = 6.0;

/// New positions for `ids` (all nodes when empty), laid out from the top-left
/// corner of where they are now. Nodes not named keep their places.
pub fn layout(patch: &Patch, registry: &Registry, ids: &[NodeId]) -> Vec<(NodeId, (f32, f32))> {
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
    let node = |i: usize| patch.node(chosen[i]);
    let sizes: Vec<(f32, f32)> = (0..n)
        .map(|i| node(i).map_or((40.0, 20.0), |d| node_size(d, registry, patch)))
        .collect();
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
    // Start from the current vertical order, so a layout keeps what the artist arranged.
    let mut by_y: Vec<usize> = (0..n).collect();
    by_y.sort_by(|&a, &b| {
        let ya = node(a).map_or(0.0, |d| d.pos.1);
        let yb = node(b).map_or(0.0, |d| d.pos.1);
        ya.total_cmp(&yb).then(a.cmp(&b))
    });
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
    // Columns: each layer as wide as its widest node.
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
    let origin = chosen
        .iter()
        .filter_map(|&id| patch.node(id).map(|d| d.pos))
        .fold((f32::INFINITY, f32::INFINITY), |a, p| {
            (a.0.min(p.0), a.1.min(p.1))
        });
    // Keep the IOBoxes' order left to right (by x, then id), a unit apart.
    let mut shift = vec![0.0f32; n];
    for k in [INLET, OUTLET] {
        let mut boxes: Vec<usize> = (0..n).filter(|&v| kind(v) == Some(k)).collect();
        boxes.sort_by(|&a, &b| {
            let xa = node(a).map_or(0.0, |d| d.pos.0);
            let xb = node(b).map_or(0.0, |d| d.pos.0);
            xa.total_cmp(&xb).then(chosen[a].cmp(&chosen[b]))
        });
        for (rank, v) in boxes.into_iter().enumerate() {
            shift[v] = rank as f32;
        }
    }
    let top = y.iter().copied().fold(f32::INFINITY, f32::min);
    (0..n)
        .map(|v| {
            (
                chosen[v],
                (
                    (origin.0 + x[layer[v]] + shift[v]).round(),
                    (origin.1 + y[v] - top).round(),
                ),
            )
        })
        .collect()
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
        let moves = layout(&p, &registry, &[]);
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
