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
    let mut def = NodeDef::new(
        name,
        super::CATEGORY,
        "Joins up to four spreads into one, in pin order.",
    );
    for input in inputs {
        def = def.input_spread(input, ty, Spread::Resource(kind, vec![]));
    }
    def.output_typed(output, ty).construct(move || Group(kind))
}

/// Joins its inputs' handles; knows its kind so an empty result is typed right.
struct Group(ResourceKind);

impl spreadlight_graph::Node for Group {
    fn evaluate(
        &mut self,
        cx: &mut spreadlight_graph::EvalContext<'_>,
    ) -> Result<(), spreadlight_graph::NodeError> {
        let mut joined = Vec::new();
        for pin in 0..4 {
            if let Spread::Resource(_, handles) = cx.input(pin) {
                joined.extend(handles.iter().cloned());
            }
        }
        cx.set_output(0, Spread::Resource(self.0, joined));
        Ok(())
    }
}
