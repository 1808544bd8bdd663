//! `Group (Layer)`, `Group (Texture)`, `Group (Lights)` and `Group (Shadows)`:
//! join resource spreads into one, as vvvv's Group: layers for `MRE`, light
//! components for `CompositeLight`, light buffers of several types and
//! their shadow maps for `Transparency`.

use spreadlight_graph::{NodeDef, PinType, Registry, ResourceKind, Spread};

pub fn register(r: &mut Registry) {
    r.add(group(
        "Group (Layer)",
        ResourceKind::Layer,
        ["Layer 1", "Layer 2", "Layer 3", "Layer 4"],
        "Layer",
    ));
    r.add(group(
        "Group (Texture)",
        ResourceKind::Texture,
        ["Texture 1", "Texture 2", "Texture 3", "Texture 4"],
        "Texture",
    ));
    r.add(group(
        "Group (Lights)",
        ResourceKind::LightWorld,
        ["Lights 1", "Lights 2", "Lights 3", "Lights 4"],
        "Lights",
    ));
    r.add(group(
        "Group (Shadows)",
        ResourceKind::Shadows,
        ["Shadows 1", "Shadows 2", "Shadows 3", "Shadows 4"],
        "Shadows",
    ));
}

/// A node joining up to four spreads of `kind`, in pin order.
fn group(
    name: &'static str,
    kind: ResourceKind,
    inputs: [&'static str; 4],
    output: &'static str,
) -> NodeDef {
    let ty = PinType::Resource(kind);
    NodeDef::new(
        name,
        super::CATEGORY,
        "Joins up to four spreads into one, in pin order.",
    )
    .with_pins(|p| {
        let inputs = inputs.map(|input| p.input_any(input, ty, Spread::Resource(kind, vec![])));
        let out = p.output_any(output, ty);
        // Knows its kind so an empty result is typed right.
        move |cx| {
            let mut joined = Vec::new();
            for pin in inputs {
                if let Spread::Resource(_, handles) = cx.spread(pin) {
                    joined.extend(handles.iter().cloned());
                }
            }
            cx.put_spread(out, Spread::Resource(kind, joined));
            Ok(())
        }
    })
}
