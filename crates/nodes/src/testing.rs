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
    crate::value::register_basics(&mut r);
    crate::vector::register_join_split(&mut r);
    crate::spreads::register_generators(&mut r);
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

/// A node under test inside a running patch, stepped frame by frame at 60 fps:
/// node 1 of the type under test, its first output feeding a `Probe` (node 2)
/// so that demand reaches it. Stateful nodes are tested through this, so the
/// runtime's reuse rule (unchanged nodes are not evaluated) is part of the test.
pub(crate) struct Harness {
    runtime: Runtime,
    patch: Patch,
    frame: u64,
}

impl Harness {
    pub(crate) fn new(name: &str) -> Self {
        let registry = crate::registry();
        let def = registry
            .get(name)
            .unwrap_or_else(|| panic!("no node type `{name}`"))
            .clone();
        let mut patch = Patch::default();
        patch.add(NodeDoc::new(1, name));
        if !def.sink {
            // A probe on its first output keeps the node evaluated.
            let first = def
                .outputs
                .first()
                .unwrap_or_else(|| panic!("`{name}` is no sink and has no output"));
            patch.add(NodeDoc::new(2, "Probe"));
            patch.link(1, &first.name, 2, "Input");
        }
        let mut h = Harness {
            runtime: Runtime::new(registry),
            patch,
            frame: 0,
        };
        h.reload();
        h
    }

    /// Provide a host service to the running patch.
    pub(crate) fn provide<T: std::any::Any + Send + Sync>(&mut self, service: Arc<T>) {
        self.runtime.provide(service);
    }

    fn reload(&mut self) {
        let problems = self.runtime.load(&self.patch);
        assert!(problems.is_empty(), "{problems:?}");
    }

    /// Set input `pin` of the node under test (an edit: the patch is reloaded).
    pub(crate) fn set(&mut self, pin: &str, value: impl Into<Spread>) -> &mut Self {
        let node = self
            .patch
            .node_mut(spreadlight_graph::NodeId(1))
            .expect("node under test");
        node.values.insert(pin.to_owned(), value.into());
        self.reload();
        self
    }

    /// Evaluate the next frame; says whether the node under test ran or was reused.
    pub(crate) fn step(&mut self) -> spreadlight_graph::NodeRun {
        let stats = self.runtime.evaluate(FrameClock::fixed(self.frame, 60.0));
        self.frame += 1;
        let run = stats
            .nodes
            .iter()
            .find(|n| n.id == spreadlight_graph::NodeId(1))
            .expect("node under test")
            .run;
        if let Some(e) = self.runtime.node_error(spreadlight_graph::NodeId(1)) {
            panic!("node failed: {e}");
        }
        run
    }

    /// Output `pin` of the node under test as its Rust type.
    pub(crate) fn out<T: SliceValue>(&self, pin: &str) -> Vec<T> {
        let spread = self
            .runtime
            .output(spreadlight_graph::NodeId(1), pin)
            .unwrap_or_else(|| panic!("no output `{pin}`"));
        T::slices(spread)
            .unwrap_or_else(|| panic!("`{pin}` is not {}", T::PIN_TYPE))
            .to_vec()
    }

    /// Step one frame and read output `pin`.
    pub(crate) fn next<T: SliceValue>(&mut self, pin: &str) -> Vec<T> {
        self.step();
        self.out(pin)
    }
}

/// A String spread from string slices, for test inputs.
pub(crate) fn strings_of(v: &[&str]) -> Spread {
    Spread::String(v.iter().map(|s| (*s).to_owned()).collect())
}

/// Every node of the pure families (no GPU, no network) runs with its defaults
/// and outputs only finite numbers.
#[test]
fn every_core_library_node_evaluates_with_its_defaults() {
    let registry = crate::registry();
    let families = [
        "Spreads",
        "Logic",
        "Animation",
        "Color",
        "String",
        "Input",
        "Value",
        "Vector",
    ];
    let mut checked = 0;
    for def in registry.iter().filter(|d| families.contains(&&*d.category)) {
        let outputs = eval(&def.name, &[])
            .unwrap_or_else(|e| panic!("`{}` failed with its defaults: {e}", def.name));
        assert_eq!(outputs.len(), def.outputs.len());
        for (pin, spread) in def.outputs.iter().zip(&outputs) {
            assert!(
                spread.fits(pin.ty),
                "`{}`.`{}` has the wrong type",
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
        checked += 1;
    }
    assert!(checked > 200, "only {checked} nodes checked");
}

/// Every registered node type, with its defaults, compiles into a patch without problems
/// (the defaults fit their pins, enum defaults are options): what the browser adds.
#[test]
fn every_registered_node_type_loads_into_a_patch() {
    let registry = crate::registry();
    let mut patch = Patch::default();
    for (i, def) in registry.iter().enumerate() {
        let id = u32::try_from(i + 1).expect("few node types");
        patch.add(NodeDoc::new(id, &def.name));
    }
    let mut runtime = Runtime::new(crate::registry());
    let problems = runtime.load(&patch);
    assert!(problems.is_empty(), "{problems:?}");
}
