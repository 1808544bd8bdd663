//! The node set the editor runs: the library's, with one change. An `Output`
//! that writes no file does not render on its own in the editor: the
//! viewport renders its texture (on egui's device, at the panel's size), so
//! rendering it in the node too would draw every frame twice on the GPU.

use spreadlight_graph::{EvalContext, Node, NodeDef, NodeError, Registry, Spread};

/// The library's registry with the editor's `Output`.
pub fn registry() -> Registry {
    let library = spreadlight_nodes::registry();
    let mut r = Registry::new();
    for def in library.iter() {
        if def.name == "Output" {
            r.add(shown_output(def));
        } else {
            r.add((**def).clone());
        }
    }
    r
}

fn shown_output(def: &NodeDef) -> NodeDef {
    let inner = def.clone();
    let texture = def.input_index("Texture");
    let filename = def.input_index("Filename");
    let write = def.input_index("Write");
    def.clone().construct(move || ShownOutput {
        inner: inner.instantiate(),
        texture,
        filename,
        write,
    })
}

struct ShownOutput {
    inner: Box<dyn Node>,
    texture: Option<usize>,
    filename: Option<usize>,
    write: Option<usize>,
}

impl Node for ShownOutput {
    fn evaluate(&mut self, cx: &mut EvalContext<'_>) -> Result<(), NodeError> {
        // If the library's Output changes its pins, behave exactly as it does.
        let (Some(texture), Some(filename), Some(write)) =
            (self.texture, self.filename, self.write)
        else {
            return self.inner.evaluate(cx);
        };
        let writes = cx.slices::<bool>(write)?.first().copied().unwrap_or(true)
            && cx
                .slices::<String>(filename)?
                .first()
                .is_some_and(|f| !f.is_empty());
        if writes {
            return self.inner.evaluate(cx);
        }
        match cx.input(texture) {
            Spread::Resource(_, handles) if !handles.is_empty() => Ok(()),
            _ => Err(cx.input_error(texture, "no texture connected")),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use spreadlight_graph::{FrameClock, NodeDoc, NodeId, Patch, Runtime};

    fn output_error(values: NodeDoc) -> String {
        let mut p = Patch::default();
        p.add(values);
        let mut rt = Runtime::new(registry());
        rt.load(&p);
        rt.evaluate(FrameClock::fixed(0, 60.0));
        rt.node_error(NodeId(1))
            .map(ToString::to_string)
            .unwrap_or_default()
    }

    #[test]
    fn every_library_type_is_there() {
        let library = spreadlight_nodes::registry();
        let editor = registry();
        assert_eq!(editor.len(), library.len());
        for def in library.iter() {
            let mine = editor.get(&def.name).expect("registered");
            assert_eq!(mine.inputs.len(), def.inputs.len());
            assert_eq!(mine.outputs.len(), def.outputs.len());
            assert_eq!(mine.sink, def.sink);
        }
    }

    #[test]
    fn an_output_renders_itself_only_when_it_writes_a_file() {
        // Without a renderer, the library's Output fails asking for one: that
        // error shows whether the node tried to render.
        let shown = output_error(NodeDoc::new(1, "Output"));
        assert!(shown.contains("no texture connected"), "{shown}");
        let writing =
            output_error(NodeDoc::new(1, "Output").with("Filename", vec!["out.png".to_owned()]));
        assert!(writing.contains("no GPU renderer"), "{writing}");
    }
}
