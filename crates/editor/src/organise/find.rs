//! Find in patch: every node, pin, value, comment and frame title of the
//! shown document whose text contains the query (case-insensitively).

use spreadlight_graph::{NodeId, Patch, Registry};

/// What a match points at.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Target {
    Node(NodeId),
    Comment(usize),
    Frame(usize),
}

/// One match: what it is, and the line the find panel shows.
#[derive(Clone, Debug, PartialEq)]
pub struct Hit {
    pub target: Target,
    pub text: String,
}

/// The matches of `query` in `patch`, in document order: nodes (by type
/// name, id, pin names and values), then comments, then frames.
pub fn find(patch: &Patch, registry: &Registry, query: &str) -> Vec<Hit> {
    let q = query.trim().to_lowercase();
    if q.is_empty() {
        return Vec::new();
    }
    let has = |s: &str| s.to_lowercase().contains(q.as_str());
    let mut hits = Vec::new();
    for n in &patch.nodes {
        let what = if has(&n.type_name) || has(&n.id.to_string()) {
            Some(String::new())
        } else if let Some((pin, v)) = n
            .values
            .iter()
            .find(|(pin, v)| has(pin.as_str()) || has(&v.preview(4)))
        {
            Some(format!(": {pin} = {}", v.preview(4)))
        } else {
            registry.get(&n.type_name).and_then(|def| {
                def.inputs
                    .iter()
                    .chain(&def.outputs)
                    .find(|p| has(&p.name))
                    .map(|p| format!(": pin {}", p.name))
            })
        };
        if let Some(what) = what {
            hits.push(Hit {
                target: Target::Node(n.id),
                text: format!("{} {}{what}", n.type_name, n.id),
            });
        }
    }
    for (i, c) in patch.comments.iter().enumerate() {
        if let Some(line) = c.text.lines().find(|l| has(l)) {
            hits.push(Hit {
                target: Target::Comment(i),
                text: format!("comment: {}", line.trim()),
            });
        }
    }
    for (i, f) in patch.frames.iter().enumerate() {
        if has(&f.title) {
            hits.push(Hit {
                target: Target::Frame(i),
                text: format!("frame: {}", f.title),
            });
        }
    }
    hits
}

#[cfg(test)]
mod tests {
    use super::*;
    use spreadlight_graph::{CommentDoc, NodeDoc};

    #[test]
    fn nodes_pins_values_and_comments_are_found() {
        let registry = crate::nodes::registry();
        let mut p = Patch::default();
        p.add(NodeDoc::new(1, "LFO").with("Period", vec![7.25f32]));
        p.add(NodeDoc::new(2, "Probe").with("Name", vec!["wobble".to_owned()]));
        p.comments
            .push(CommentDoc::new(0.0, 0.0, "# Title\nthe wobble is slow"));
        let targets = |q: &str| -> Vec<Target> {
            find(&p, &registry, q)
                .into_iter()
                .map(|h| h.target)
                .collect()
        };
        assert_eq!(targets("lfo"), vec![Target::Node(NodeId(1))]);
        assert_eq!(targets("7.25"), vec![Target::Node(NodeId(1))]);
        assert_eq!(
            targets("wobble"),
            vec![Target::Node(NodeId(2)), Target::Comment(0)]
        );
        assert_eq!(targets("period"), vec![Target::Node(NodeId(1))]);
        assert!(targets("").is_empty());
    }
}
