//! Pairs of passes the graph runs as one when it can.
//!
//! A recipe whose two passes could share one dispatch declares them as
//! usual, so each is culled, ordered and run on its own when it must be,
//! and adds a run for both:
//! - [`FrameGraph::runs_together`]: two passes that share their reads (the
//!   G-buffer's surface and motion resolves read the same visibility). When
//!   both survive culling and the second reads nothing made at or after the
//!   first, the first pass takes the second's reads, writes and the joint
//!   run, and the second leaves the order.
//! - [`FrameGraph::chains_into`]: the second reads the first's output at each
//!   pixel (Fog, then Sky over it). When nothing else reads the first's
//!   outputs (no other pass, not the caller), the joint run reads what both
//!   read and writes the second's outputs only: the first's are never made.
//!
//! Either way: one pass boundary fewer, and what both read is read once.
//! Otherwise each runs alone. A merged pass of two nodes names the second's
//! as its partner (`PassReport::partner`): its errors go to both.

use super::{FrameGraph, GraphParts, Lifetime, PassContext, PassFn, PassName};
use crate::error::RenderError;

#[derive(Clone, Copy, PartialEq, Eq)]
enum Kind {
    Pair,
    Chain,
}

/// Which pass comes first: the one declared before the second, or the one
/// that writes a texture (found when the graph is complete).
enum First {
    Before,
    Writing(String),
}

/// Two passes, and what runs them together.
pub(super) struct Merge<'a> {
    first: First,
    second: usize,
    kind: Kind,
    name: PassName,
    both: PassFn<'a>,
}

impl<'a> FrameGraph<'a> {
    /// The last two passes declared run as one pass `name`, by `both`, when
    /// the frame needs both of them; when it needs one, that one runs alone.
    pub fn runs_together(
        &mut self,
        name: impl Into<PassName>,
        both: impl FnOnce(&mut PassContext<'_>) -> Result<(), RenderError> + 'a,
    ) {
        self.merge_last(First::Before, Kind::Pair, name.into(), Box::new(both));
    }

    /// The last pass declared reads `source` pixel by pixel: `both` runs it
    /// and the pass that writes `source` as one pass `name`, writing only
    /// the last one's outputs, when nothing else reads the first's.
    pub fn chains_into(
        &mut self,
        source: &str,
        name: impl Into<PassName>,
        both: impl FnOnce(&mut PassContext<'_>) -> Result<(), RenderError> + 'a,
    ) {
        let first = First::Writing(source.to_owned());
        self.merge_last(first, Kind::Chain, name.into(), Box::new(both));
    }

    fn merge_last(&mut self, first: First, kind: Kind, name: PassName, both: PassFn<'a>) {
        let n = self.passes.len();
        if n < 2 {
            return;
        }
        self.merges.push(Merge {
            first,
            second: n - 1,
            kind,
            name,
            both,
        });
    }
}

impl Merge<'_> {
    /// What was declared, its run aside: the texture the first pass writes
    /// (`None`: the pass declared before the second), the second pass,
    /// whether it is a chain, and the joint pass's name (plan.rs compares it).
    pub(super) fn shape(&self) -> (Option<&str>, usize, bool, &PassName) {
        let first = match &self.first {
            First::Before => None,
            First::Writing(name) => Some(name.as_str()),
        };
        (first, self.second, self.kind == Kind::Chain, &self.name)
    }
}

/// A merge that applied: its index among the graph's merges, its first
/// pass and its second.
pub(super) type Applied = (usize, usize, usize);

/// Hand this frame's joint runs to the passes a kept plan merged (plan.rs):
/// the first pass of each takes the joint run, the second none.
pub(super) fn rerun<'a>(
    runs: &mut [Option<PassFn<'a>>],
    merges: Vec<Merge<'a>>,
    applied: &[Applied],
) {
    let mut applied = applied.iter().peekable();
    for (index, merge) in merges.into_iter().enumerate() {
        if let Some(&(_, first, second)) = applied.next_if(|(i, _, _)| *i == index) {
            runs[first] = Some(merge.both);
            runs[second] = None;
        }
    }
}

/// Folds each pair that can be one pass into its first pass (see the
/// module), noting which in `parts.merged`.
pub(super) fn apply<'a>(parts: &mut GraphParts<'a>, merges: Vec<Merge<'a>>) {
    // A pass folds into at most one other.
    let mut merged = vec![false; parts.names.len()];
    for (index, merge) in merges.into_iter().enumerate() {
        let second = merge.second;
        let first = match &merge.first {
            First::Before => second.checked_sub(1),
            First::Writing(name) => {
                (0..second).find(|&p| parts.writes[p].iter().any(|(w, _)| w == name))
            }
        };
        let Some(first) = first.filter(|&f| !merged[f] && !merged[second]) else {
            continue;
        };
        let position = |pass: usize| parts.order.iter().position(|&p| p == pass);
        let (Some(first_at), Some(second_at)) = (position(first), position(second)) else {
            continue;
        };
        // A chain's second reads the first's outputs in place; whatever
        // else it reads must exist before the first runs.
        let in_place = |name: &String| {
            merge.kind == Kind::Chain && parts.writes[first].iter().any(|(w, _)| w == name)
        };
        let made_after_first = |name: &String| {
            parts.order[first_at..]
                .iter()
                .any(|&p| parts.writes[p].iter().any(|(w, _)| w == name))
        };
        let (mut chained, mut outside) = (false, false);
        for read in &parts.reads[second] {
            if in_place(read) {
                chained = true;
            } else {
                outside |= made_after_first(read);
            }
        }
        if first_at > second_at || outside {
            continue;
        }
        if merge.kind == Kind::Chain {
            // The first's outputs: temporaries read by the second alone.
            let read_elsewhere = parts.writes[first].iter().any(|(w, d)| {
                d.lifetime != Lifetime::Temporary
                    || parts.requested.contains(w)
                    || parts
                        .order
                        .iter()
                        .any(|&p| p != second && parts.reads[p].contains(w))
            });
            if !chained || read_elsewhere {
                continue;
            }
            let dropped = std::mem::take(&mut parts.writes[first]);
            parts.keys[first].clear();
            let reads = std::mem::take(&mut parts.reads[second]);
            for r in reads {
                if !dropped.iter().any(|(w, _)| *w == r) && !parts.reads[first].contains(&r) {
                    parts.reads[first].push(r);
                }
            }
        } else {
            let reads = std::mem::take(&mut parts.reads[second]);
            parts.reads[first].extend(reads);
        }
        parts.order.remove(second_at);
        let writes = std::mem::take(&mut parts.writes[second]);
        let keys = std::mem::take(&mut parts.keys[second]);
        parts.writes[first].extend(writes);
        parts.keys[first].extend(keys);
        if parts.owners[second] != parts.owners[first] {
            parts.partners[first] = parts.owners[second];
        }
        // Two nodes' passes chained read as both ("Fog #1 and Sky #2"); a
        // pair of one node's passes as the step the merge names.
        parts.names[first] = match merge.kind {
            Kind::Chain => format!("{} and {}", parts.names[first], parts.names[second]),
            Kind::Pair => merge.name.text(parts.owners[first]),
        };
        parts.labels[first] = merge.name;
        parts.runs[first] = Some(merge.both);
        parts.runs[second] = None;
        parts.merged.push((index, first, second));
        merged[first] = true;
        merged[second] = true;
    }
}
