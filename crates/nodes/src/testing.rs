//! Test helpers: evaluate one node type directly, outside a patch, with its
//! pin defaults overridden by the values a test gives.

use std::sync::Arc;

use spreadlight_graph::{
    EvalContext, FrameClock, NodeDoc, NodeError, Patch, ProbeLog, Registry, Runtime, SliceValue,
    Spread,
};

/// Evaluate node type `name` once at frame 0, its inputs at their defaults
/// except those named in `values`. Returns every output, in pin order.
///
/// Panics on an unknown node type or pin, or a value that cannot sit on its
/// pin (a bug in the test); the node's own errors are returned.
pub(crate) fn eval(name: &str, values: &[(&str, Spread)]) -> Result<Vec<Spread>, NodeError> {
    let registry = crate::registry();
    let def = registry
        .get(name)
        .unwrap_or_else(|| panic!("no node type `{name}`"));
    let mut inputs: Vec<Arc<Spread>> = def
        .inputs
        .iter()
        .map(|p| Arc::new(p.default.clone()))
        .collect();
    for (pin, value) in values {
        let k = def
            .input_index(pin)
            .unwrap_or_else(|| panic!("`{name}` has no input `{pin}`"));
        let ty = def.inputs[k].ty;
        let value = value
            .convert_to(ty)
            .unwrap_or_else(|| panic!("`{name}`.`{pin}` takes {ty}, got {}", value.type_name()));
        inputs[k] = Arc::new(value);
    }
    let mut outputs: Vec<Arc<Spread>> = def
        .outputs
        .iter()
        .map(|p| Arc::new(Spread::empty(p.ty)))
        .collect();
    let clock = FrameClock::default();
    let mut probes = ProbeLog::new();
    let mut node = def.instantiate();
    let services = spreadlight_graph::Services::default();
    let mut cx = EvalContext::new(
        &clock,
        &inputs,
        &def.inputs,
        &mut outputs,
        &mut probes,
        &services,
        spreadlight_graph::NodeId(1),
    );
    node.evaluate(&mut cx)?;
    Ok(outputs.into_iter().map(Arc::unwrap_or_clone).collect())
}

/// Evaluate like [`eval`], expect success, and return output `pin` as its Rust type.
pub(crate) fn eval_out<T: SliceValue>(name: &str, values: &[(&str, Spread)], pin: &str) -> Vec<T> {
    let registry = crate::registry();
    let def = registry
        .get(name)
        .unwrap_or_else(|| panic!("no node type `{name}`"));
    let k = def
        .output_index(pin)
        .unwrap_or_else(|| panic!("`{name}` has no output `{pin}`"));
    let outputs = eval(name, values).unwrap_or_else(|e| panic!("`{name}` failed: {e}"));
    T::slices(&outputs[k])
        .unwrap_or_else(|| panic!("`{name}`.`{pin}` is not {}", T::PIN_TYPE))
        .to_vec()
}

/// Evaluate like [`eval`] and expect an error naming input `pin`.
pub(crate) fn eval_err(name: &str, values: &[(&str, Spread)], pin: &str) -> NodeError {
    match eval(name, values) {
        Ok(out) => panic!("`{name}` should fail on `{pin}`, gave {out:?}"),
        Err(e) => {
            assert!(
                matches!(&e, NodeError::Input { pin: p, .. } if p == pin),
                "`{name}` failed, but not on `{pin}`: {e}"
            );
            e
        }
    }
}

/// An enum value for an input pin.
pub(crate) fn option(name: &str) -> Spread {
    Spread::Enum(vec![name.to_owned()])
}

/// Assert two float lists are equal within `eps`, slice by slice.
#[track_caller]
pub(crate) fn assert_close(got: &[f32], want: &[f32], eps: f32) {
    assert_eq!(
        got.len(),
        want.len(),
        "slice counts differ: {got:?} vs {want:?}"
    );
    for (i, (g, w)) in got.iter().zip(want).enumerate() {
        assert!(
            (g - w).abs() <= eps,
            "slice {i}: got {g}, want {w} ({got:?} vs {want:?})"
        );
    }
}

/// The node types of the families this crate's tests cover here.
fn covered() -> Registry {
    let mut r = Registry::new();
    crate::value::register(&mut r);
    crate::vector::register(&mut r);
    crate::spreads::register(&mut r);
    crate::transform::register(&mut r);
    crate::camera::register(&mut r);
    r
}

#[test]
fn every_node_evaluates_with_its_defaults_to_finite_values() {
    let r = covered();
    let names: Vec<&str> = r.iter().map(|d| &*d.name).collect();
    assert_eq!(
        names,
        [
            "Add (Value)",
            "Camera",
            "CircularSpread",
            "Clamp (Value)",
            "Cos (Value)",
            "Cross (2d)",
            "Divide (Value)",
            "I (Spreads)",
            "LinearSpread",
            "LookAt (Transform)",
            "Map (Value)",
            "Multiply (Transform)",
            "Multiply (Value)",
            "Perspective (Transform)",
            "Pow (Value)",
            "RandomSpread",
            "Rotate (Transform)",
            "Scale (Transform)",
            "Sin (Value)",
            "Subtract (Value)",
            "Transform (Transform 3d)",
            "Translate (Transform)",
            "Vector (2d Join)",
            "Vector (2d Split)",
            "Vector (3d Join)",
            "Vector (3d Split)",
            "Vector (4d Join)",
            "Vector (4d Split)",
        ]
    );
    for def in r.iter() {
        assert!(!def.help.is_empty(), "`{}` has no help", def.name);
        let outputs = eval(&def.name, &[])
            .unwrap_or_else(|e| panic!("`{}` failed with its defaults: {e}", def.name));
        for (pin, spread) in def.outputs.iter().zip(&outputs) {
            assert!(
                !spread.is_empty(),
                "`{}`.`{}` is empty with the defaults",
                def.name,
                pin.name
            );
            assert_eq!(
                spread.first_non_finite(),
                None,
                "`{}`.`{}` = {spread:?}",
                def.name,
                pin.name
            );
        }
    }
}

#[test]
fn every_node_loads_into_a_patch_without_problems() {
    let covered = covered();
    let mut patch = Patch::default();
    for (i, def) in covered.iter().enumerate() {
        let id = u32::try_from(i + 1).expect("few node types");
        patch.add(NodeDoc::new(id, &def.name));
    }
    let mut runtime = Runtime::new(crate::registry());
    let problems = runtime.load(&patch);
    assert!(problems.is_empty(), "{problems:?}");
}

/// A Float spread from a slice, for test inputs.
pub(crate) fn floats(v: &[f32]) -> Spread {
    Spread::Float(v.to_vec())
}

/// An Int spread from a slice, for test inputs.
pub(crate) fn ints(v: &[i64]) -> Spread {
    Spread::Int(v.to_vec())
}
