//! Values in and out of a patch: the IOBoxes (constant value nodes, as in
//! vvvv), `Switch`, and the `Probe` sink that records what flows into it.

use glam::{Mat4, Vec2, Vec3, Vec4};
use spreadlight_graph::{Color, NodeDef, PinType, Registry, spread};

use crate::typed::Value;

pub fn register(r: &mut Registry) {
    r.add(iobox("IOBox (Value)", 0.0f32));
    r.add(iobox("IOBox (Integer)", 0i64));
    r.add(iobox("IOBox (Toggle)", false));
    r.add(iobox("IOBox (String)", String::new()));
    r.add(iobox("IOBox (Vector 2d)", Vec2::ZERO));
    r.add(iobox("IOBox (Vector 3d)", Vec3::ZERO));
    r.add(iobox("IOBox (Vector 4d)", Vec4::ZERO));
    r.add(iobox("IOBox (Color)", Color::WHITE));
    r.add(iobox("IOBox (Transform)", Mat4::IDENTITY));

    r.add(switch::<f32>("Switch (Value Input)"));
    r.add(switch::<i64>("Switch (Integer Input)"));
    r.add(switch::<bool>("Switch (Toggle Input)"));
    r.add(switch::<String>("Switch (String Input)"));
    r.add(switch::<Vec3>("Switch (Vector 3d Input)"));
    r.add(switch::<Color>("Switch (Color Input)"));
    r.add(switch::<Mat4>("Switch (Transform Input)"));

    r.add(
        NodeDef::new(
            "Probe",
            "IO",
            "A sink: records the spread on its input every frame it changes, under its name. \
             `spreadlight eval --probe NAME` prints it; tests read it.",
        )
        .sink()
        .with_pins(|p| {
            let input = p.input_any(
                "Input",
                PinType::Any,
                spreadlight_graph::Spread::Float(Vec::new()),
            );
            let name = p.input("Name", "probe".to_owned());
            move |cx| {
                let names = cx.get(name)?;
                let Some(name) = names.first().filter(|n| !n.is_empty()).cloned() else {
                    return Err(cx.error(name, "a probe needs a name"));
                };
                let value = cx.spread_arc(input).clone();
                cx.record_probe(&name, value);
                Ok(())
            }
        }),
    );
}

/// A constant value node: its one input is edited in the patch and passed on unchanged.
fn iobox<T: Value>(name: &'static str, default: T) -> NodeDef {
    NodeDef::new(
        name,
        "IO",
        "A constant spread, edited in place: outputs its input value unchanged.",
    )
    .with_pins(|p| {
        let input = p.input("Input", default);
        let output = p.output::<T>("Output");
        move |cx| {
            let value = cx.spread_arc(input).clone();
            cx.put_arc(output, value);
            Ok(())
        }
    })
}

/// Picks, per slice, one of two inputs by index (wrapping, so -1 picks the last).
fn switch<T: Value + Default>(name: &'static str) -> NodeDef {
    NodeDef::new(
        name,
        "IO",
        "Outputs, slice by slice, the input the Switch index selects (indices wrap around).",
    )
    .with_pins(|p| {
        let switch = p.input("Switch", 0i64);
        let inputs = ["Input 1", "Input 2"].map(|name| p.input(name, T::default()));
        let output = p.output::<T>("Output");
        move |cx| {
            let index = cx.get(switch)?;
            let [first, second] = inputs;
            let inputs = [cx.get(first)?, cx.get(second)?];
            let n = spread::slice_count(
                [index.len()]
                    .into_iter()
                    .chain(inputs.iter().map(|s| s.len())),
            );
            let out: Vec<T> = (0..n)
                .map(|i| {
                    let which = spread::wrapped(index, i).rem_euclid(inputs.len() as i64) as usize;
                    spread::wrapped(inputs[which], i).clone()
                })
                .collect();
            cx.put(output, out);
            Ok(())
        }
    })
}
