//! The sequences a patch writes: one per `Output` node, named by its Name
//! pin, read from the patch document (so a resumed or dry run knows its
//! files without opening a GPU), with the preroll each declares.

use spreadlight_graph::{Patch, Spread};

/// One `Output` node's sequence.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Declared {
    pub name: String,
    /// Frames its temporal effects need before its image is valid (its Preroll pin).
    pub preroll: u64,
}

/// Every `Output` of `patch`, by Name (sorted; two Outputs may not share a Name).
pub fn declared(patch: &Patch) -> Result<Vec<Declared>, String> {
    let mut outputs = Vec::new();
    for node in patch.nodes.iter().filter(|n| n.type_name == "Output") {
        let linked = |pin: &str| {
            patch
                .links
                .iter()
                .any(|l| l.to.node() == node.id && l.to.pin() == pin)
        };
        if linked("Name") || linked("Preroll") {
            return Err(format!(
                "Output {}: its Name and Preroll must be values, not links, to render a sequence",
                node.id
            ));
        }
        let name = match node.values.get("Name") {
            Some(Spread::String(v)) => v.first().cloned().unwrap_or_else(|| "output".to_owned()),
            _ => "output".to_owned(),
        };
        let preroll = match node.values.get("Preroll") {
            Some(Spread::Int(v)) => v.first().copied().unwrap_or(0),
            _ => 0,
        };
        let preroll = u64::try_from(preroll)
            .map_err(|_| format!("Output {}: Preroll {preroll} is negative", node.id))?;
        if outputs.iter().any(|o: &Declared| o.name == name) {
            return Err(format!(
                "two Output nodes are named `{name}`: give each its own Name, or their sequences would overwrite each other"
            ));
        }
        outputs.push(Declared { name, preroll });
    }
    outputs.sort_by(|a, b| a.name.cmp(&b.name));
    Ok(outputs)
}

#[cfg(test)]
mod tests {
    use spreadlight_graph::NodeDoc;

    use super::*;

    #[test]
    fn outputs_are_named_by_their_name_pin_with_their_preroll() {
        let mut patch = Patch::default();
        patch.nodes.push(
            NodeDoc::new(1, "Output")
                .with("Name", vec!["beauty".to_owned()])
                .with("Preroll", vec![8i64]),
        );
        patch.nodes.push(NodeDoc::new(2, "Output"));
        patch.nodes.push(NodeDoc::new(3, "LFO"));
        let names = declared(&patch).expect("ok");
        assert_eq!(
            names,
            [
                Declared {
                    name: "beauty".into(),
                    preroll: 8
                },
                Declared {
                    name: "output".into(),
                    preroll: 0
                }
            ]
        );
        patch.nodes.push(NodeDoc::new(4, "Output"));
        assert!(declared(&patch).expect_err("clash").contains("`output`"));
    }
}
