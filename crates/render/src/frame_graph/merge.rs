//! Pairs of passes the graph runs as one when the frame needs both.
//!
//! A recipe whose two passes could share one dispatch (the G-buffer's
//! surface and motion resolves read the same visibility) declares them as
//! usual, so either can be culled on its own, and adds a run for both
//! ([`FrameGraph::runs_together`]). When both survive culling and the
//! second reads nothing made at or after the first (so it could run in the
//! first's place), the first pass takes the second's reads, writes and the
//! joint run, and the second leaves the order: one pass boundary fewer, and
//! what both read is read once. Otherwise each runs alone.

use super::{FrameGraph, GraphParts, PassContext, PassFn};
use crate::error::RenderError;

/// The last two passes declared, and what runs them together.
pub(super) struct Merge<'a> {
    first: usize,
    second: usize,
    name: String,
    both: PassFn<'a>,
}

impl<'a> FrameGraph<'a> {
    /// The last two passes declared run as one pass `name`, by `both`, when
    /// the frame needs both of them; when it needs one, that one runs alone.
    pub fn runs_together(
        &mut self,
        name: impl Into<String>,
        both: impl FnOnce(&mut PassContext<'_>) -> Result<(), RenderError> + 'a,
    ) {
        let n = self.passes.len();
        if n < 2 {
            return;
        }
        self.merges.push(Merge {
            first: n - 2,
            second: n - 1,
            name: name.into(),
            both: Box::new(both),
        });
    }
}

/// Folds each pair whose passes both run into its first pass (see the module).
pub(super) fn apply<'a>(parts: &mut GraphParts<'a>, merges: Vec<Merge<'a>>) {
    for merge in merges {
        let position = |pass: usize| parts.order.iter().position(|&p| p == pass);
        let (Some(first_at), Some(second_at)) = (position(merge.first), position(merge.second))
        else {
            continue;
        };
        // Every input of the second must exist before the first runs.
        let made_after_first = |name: &String| {
            parts.order[first_at..]
                .iter()
                .any(|&p| parts.writes[p].iter().any(|(w, _)| w == name))
        };
        if first_at > second_at || parts.reads[merge.second].iter().any(made_after_first) {
            continue;
        }
        parts.order.remove(second_at);
        let reads = std::mem::take(&mut parts.reads[merge.second]);
        let writes = std::mem::take(&mut parts.writes[merge.second]);
        let keys = std::mem::take(&mut parts.keys[merge.second]);
        parts.reads[merge.first].extend(reads);
        parts.writes[merge.first].extend(writes);
        parts.keys[merge.first].extend(keys);
        parts.names[merge.first] = merge.name;
        parts.runs[merge.first] = Some(merge.both);
        parts.runs[merge.second] = None;
    }
}
