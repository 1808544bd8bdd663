//! Values in and out of a patch: the IOBoxes (constant value nodes, as in
//! vvvv), `Switch`, and the `Probe` sink that records what flows into it.

use glam::{Mat4, Vec2, Vec3, Vec4};
use spreadlight_graph::{
    Color, EvalContext, NodeDef, NodeError, PinType, Registry, SliceValue, spread,
};

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
        .input_spread(
            "Input",
            PinType::Any,
            spreadlight_graph::Spread::Float(Vec::new()),
        )
        .input("Name", "probe".to_owned())
        .sink()
        .evaluate(probe),
    );
}

/// A constant value node: its one input is edited in the patch and passed on unchanged.
fn iobox<T: SliceValue>(name: &'static str, default: T) -> NodeDef {
    NodeDef::new(
        name,
        "IO",
        "A constant spread, edited in place: outputs its input value unchanged.",
    )
    .input("Input", default)
    .output::<T>("Output")
    .evaluate(|cx| {
        let input = cx.input_arc(0).clone();
        cx.set_output_arc(0, input);
        Ok(())
    })
}

/// Picks, per slice, one of two inputs by index (wrapping, so -1 picks the last).
fn switch<T: SliceValue + Default>(name: &'static str) -> NodeDef {
    NodeDef::new(
        name,
        "IO",
        "Outputs, slice by slice, the input the Switch index selects (indices wrap around).",
    )
    .input("Switch", 0i64)
    .input("Input 1", T::default())
    .input("Input 2", T::default())
    .output::<T>("Output")
    .evaluate(|cx| {
        let index = cx.slices::<i64>(0)?;
        let inputs = [cx.slices::<T>(1)?, cx.slices::<T>(2)?];
        let n = spread::slice_count([index.len(), inputs[0].len(), inputs[1].len()]);
        let out: Vec<T> = (0..n)
            .map(|i| {
                let which = spread::wrapped(index, i).rem_euclid(inputs.len() as i64) as usize;
                spread::wrapped(inputs[which], i).clone()
            })
            .collect();
        cx.set(0, out);
        Ok(())
    })
}

fn probe(cx: &mut EvalContext<'_>) -> Result<(), NodeError> {
    let names = cx.slices::<String>(1)?;
    let Some(name) = names.first().filter(|n| !n.is_empty()).cloned() else {
        return Err(cx.input_error(1, "a probe needs a name"));
    };
    let value = cx.input_arc(0).clone();
    cx.record_probe(&name, value);
    Ok(())
}
