//! `Group (Layer)`: joins layers into one spread for `MRE`, as vvvv's Group.

use spreadlight_graph::{NodeDef, PinType, Registry, ResourceKind, Spread};

pub fn register(r: &mut Registry) {
    let layer = PinType::Resource(ResourceKind::Layer);
    let empty = || Spread::Resource(ResourceKind::Layer, vec![]);
    r.add(
        NodeDef::new(
            "Group (Layer)",
            super::CATEGORY,
            "Joins up to four layer spreads into one, in pin order.",
        )
        .input_spread("Layer 1", layer, empty())
        .input_spread("Layer 2", layer, empty())
        .input_spread("Layer 3", layer, empty())
        .input_spread("Layer 4", layer, empty())
        .output_typed("Layer", layer)
        .evaluate(|cx| {
            let mut joined = Vec::new();
            for pin in 0..4 {
                if let Spread::Resource(_, handles) = cx.input(pin) {
                    joined.extend(handles.iter().cloned());
                }
            }
            cx.set_output(0, Spread::Resource(ResourceKind::Layer, joined));
            Ok(())
        }),
    );
}
