//! Subpatches, asserted through the runtime's statistics: an instance runs as
//! its inside would, spreads pass through, an unchanged instance is reused
//! node by node, state is per instance, demand sees through subpatch borders;
//! files from the library, placeholders for missing ones, recursion and
//! problems named by their chain, lossless round trips.

use std::sync::Arc;

use spreadlight_graph::stats::NodeRun;
use spreadlight_graph::subpatch::{self, INLET, Library, OUTLET};
use spreadlight_graph::{
    FrameClock, Node, NodeDef, NodeDoc, NodeId, Patch, PatchDir, PinType, ProblemKind, Registry,
    Runtime, Severity, Spread, format,
};

fn registry() -> Registry {
    let mut r = Registry::new();
    subpatch::register(&mut r);
    r.add(
        NodeDef::new("Plus", "Test", "")
            .input("A", 0.0f32)
            .input("B", 0.0f32)
            .output::<f32>("Output")
            .per_slice2(|a: &f32, b: &f32| a + b),
    );
    r.add(
        NodeDef::new("Round", "Test", "")
            .input("Input", 0.0f32)
            .output::<i64>("Output")
            .per_slice1(|v: &f32| v.round() as i64),
    );
    r.add(
        NodeDef::new("Clock", "Test", "")
            .output::<f32>("Output")
            .time_dependent()
            .evaluate(|cx| {
                cx.set(0, vec![cx.clock.frame as f32]);
                Ok(())
            }),
    );
    r.add(
        NodeDef::new("Runs", "Test", "")
            .input("Input", 0.0f32)
            .output::<i64>("Output")
            .construct(|| Runs(0)),
    );
    r.add(
        NodeDef::new("Probe", "Test", "")
            .input_spread("Input", PinType::Any, Spread::Float(vec![]))
            .input("Name", "probe".to_owned())
            .sink()
            .evaluate(|cx| {
                let name = cx.slices::<String>(1)?[0].clone();
                let value = cx.input_arc(0).clone();
                cx.record_probe(&name, value);
                Ok(())
            }),
    );
    r
}

/// Counts how often it ran: state that must be one per instance.
struct Runs(i64);

impl Node for Runs {
    fn evaluate(
        &mut self,
        cx: &mut spreadlight_graph::EvalContext<'_>,
    ) -> Result<(), spreadlight_graph::NodeError> {
        self.0 += 1;
        cx.set(0, vec![self.0]);
        Ok(())
    }
}

fn iobox(id: u32, kind: &str, name: &str, x: f32) -> NodeDoc {
    NodeDoc::new(id, kind)
        .at(x, 0.0)
        .with("Name", vec![name.to_owned()])
}

/// `Twice`: X -> Plus(X, X) -> Y, and a second output `Count` from a run counter.
fn twice() -> Patch {
    let mut p = Patch::default();
    p.add(iobox(1, INLET, "X", 0.0));
    p.add(NodeDoc::new(2, "Plus"));
    p.add(iobox(3, OUTLET, "Y", 0.0));
    p.add(NodeDoc::new(4, "Runs"));
    p.add(iobox(5, OUTLET, "Count", 100.0));
    p.link(1, "Output", 2, "A");
    p.link(1, "Output", 2, "B");
    p.link(2, "Output", 3, "Input");
    p.link(1, "Output", 4, "Input");
    p.link(4, "Output", 5, "Input");
    p
}

fn probe(id: u32, name: &str) -> NodeDoc {
    NodeDoc::new(id, "Probe").with("Name", vec![name.to_owned()])
}

fn floats(rt: &Runtime, name: &str) -> Vec<f32> {
    match rt.probes().get(name).map(|s| &**s) {
        Some(Spread::Float(v)) => v.clone(),
        other => panic!("probe {name}: {other:?}"),
    }
}

fn ints(rt: &Runtime, name: &str) -> Vec<i64> {
    match rt.probes().get(name).map(|s| &**s) {
        Some(Spread::Int(v)) => v.clone(),
        other => panic!("probe {name}: {other:?}"),
    }
}

fn loaded(patch: &Patch) -> Runtime {
    let mut rt = Runtime::new(registry());
    let problems = rt.load(patch).to_vec();
    assert!(problems.is_empty(), "{problems:?}");
    rt
}

/// A parent with two `Twice` instances: #2 fed a spread by link, #4 a value.
fn parent() -> Patch {
    let mut p = Patch::default();
    p.subpatches.insert("Twice".to_owned(), twice());
    p.add(NodeDoc::new(1, "Plus").with("A", vec![1.0f32, 2.0, 3.0]));
    p.add(NodeDoc::new(2, "Twice"));
    p.add(probe(3, "linked"));
    p.add(NodeDoc::new(4, "Twice").with("X", vec![10.0f32]));
    p.add(probe(5, "valued"));
    p.link(1, "Output", 2, "X");
    p.link(2, "Y", 3, "Input");
    p.link(4, "Y", 5, "Input");
    p
}

#[test]
fn an_instance_computes_what_its_inside_would_and_spreads() {
    let mut rt = loaded(&parent());
    rt.evaluate(FrameClock::fixed(0, 60.0));
    assert_eq!(
        floats(&rt, "linked"),
        [2.0, 4.0, 6.0],
        "a spread of three in, three out"
    );
    assert_eq!(
        floats(&rt, "valued"),
        [20.0],
        "a value on the pin reaches the Inlet"
    );
    let out = rt
        .output(NodeId(2), "Y")
        .expect("the instance's output pin");
    assert_eq!(**out, Spread::Float(vec![2.0, 4.0, 6.0]));
    let inner = rt
        .output_at(&[NodeId(2), NodeId(2)], "Output")
        .expect("inner node");
    assert_eq!(**inner, Spread::Float(vec![2.0, 4.0, 6.0]));
}

#[test]
fn pins_are_named_ordered_and_typed_from_inside() {
    let mut def = twice();
    // An Int output: the Outlet takes the type of what feeds it.
    def.add(NodeDoc::new(6, "Round"));
    def.add(iobox(7, OUTLET, "Rounded", -50.0));
    def.link(2, "Output", 6, "Input");
    def.link(6, "Output", 7, "Input");
    let (inputs, outputs) = subpatch::pins_of(&def, &registry(), &Library::default());
    let names: Vec<(&str, PinType)> = inputs.iter().map(|p| (p.name.as_str(), p.ty)).collect();
    assert_eq!(names, [("X", PinType::Float)]);
    assert_eq!(
        inputs[0].default,
        Spread::Float(vec![0.0]),
        "the consumer's default"
    );
    let names: Vec<(&str, PinType)> = outputs.iter().map(|p| (p.name.as_str(), p.ty)).collect();
    assert_eq!(
        names,
        [
            ("Rounded", PinType::Int),
            ("Y", PinType::Float),
            ("Count", PinType::Int)
        ],
        "left to right"
    );
}

#[test]
fn an_unchanged_instance_is_reused_node_by_node_and_counted() {
    let mut patch = parent();
    let mut rt = loaded(&patch);
    let first = rt.evaluate(FrameClock::fixed(0, 60.0)).clone();
    let inside: Vec<_> = first.inside(&[NodeId(2)]).collect();
    // Inlet, Plus, Outlet Y (Runs and Outlet Count feed no sink).
    assert_eq!(
        inside
            .iter()
            .filter(|n| n.run == NodeRun::Evaluated)
            .count(),
        3
    );
    assert_eq!(
        first.node_at(&[NodeId(2), NodeId(4)]).map(|n| n.run),
        Some(NodeRun::Skipped),
        "demand: an output nothing reads is not computed"
    );
    for frame in 1..10 {
        let stats = rt.evaluate(FrameClock::fixed(frame, 60.0));
        assert_eq!(stats.evaluated, 0, "frame {frame}: nothing changed");
        assert_eq!(
            stats.reused,
            2 * 3 + 3,
            "both instances' insides and the parent's nodes"
        );
        assert!(
            stats
                .inside(&[NodeId(4)])
                .all(|n| matches!(n.run, NodeRun::Reused | NodeRun::Skipped))
        );
    }
    // Editing one instance's value re-evaluates that instance only.
    patch
        .node_mut(NodeId(4))
        .expect("#4")
        .values
        .insert("X".into(), vec![1.0f32].into());
    rt.load(&patch);
    let stats = rt.evaluate(FrameClock::fixed(10, 60.0)).clone();
    assert_eq!(floats(&rt, "valued"), [2.0]);
    assert!(
        stats
            .inside(&[NodeId(2)])
            .all(|n| n.run != NodeRun::Evaluated)
    );
    assert_eq!(
        stats
            .inside(&[NodeId(4)])
            .filter(|n| n.run == NodeRun::Evaluated)
            .count(),
        3
    );
}

#[test]
fn state_inside_is_per_instance_and_survives_edits_elsewhere() {
    let mut patch = Patch::default();
    patch.subpatches.insert("Twice".to_owned(), twice());
    patch.add(NodeDoc::new(1, "Clock"));
    patch.add(NodeDoc::new(2, "Twice"));
    patch.add(NodeDoc::new(3, "Twice").with("X", vec![5.0f32]));
    patch.add(probe(4, "ticking"));
    patch.add(probe(5, "still"));
    patch.link(1, "Output", 2, "X");
    patch.link(2, "Count", 4, "Input");
    patch.link(3, "Count", 5, "Input");
    let mut rt = loaded(&patch);
    for frame in 0..5 {
        rt.evaluate(FrameClock::fixed(frame, 60.0));
    }
    assert_eq!(ints(&rt, "ticking"), [5], "fed a clock: runs every frame");
    assert_eq!(ints(&rt, "still"), [1], "its own counter, run once");
    patch.add(NodeDoc::new(6, "Plus").at(400.0, 0.0));
    rt.load(&patch);
    rt.evaluate(FrameClock::fixed(5, 60.0));
    assert_eq!(
        ints(&rt, "ticking"),
        [6],
        "an edit elsewhere keeps inner state"
    );
    assert_eq!(ints(&rt, "still"), [1]);
}

/// A misspelled type inside a subpatch: the message suggests the known
/// name, and names the sink its work was for where the parent has it (the
/// Probe #3 at the top, through the subpatch's Outlet), not by a flat id.
#[test]
fn a_misspelled_type_inside_a_subpatch_names_the_sink_it_feeds() {
    let mut patch = parent();
    let inner = patch.subpatches.get_mut("Twice").expect("inline");
    if let Some(node) = inner.node_mut(NodeId(2)) {
        node.type_name = "Pluss".to_owned();
    }
    let mut rt = Runtime::new(registry());
    let problems = rt.load(&patch).to_vec();
    // Both instances hold the misspelling: #2 feeds the Probe #3, #4 the Probe #5.
    assert_eq!(problems.len(), 2, "{problems:?}");
    let expect = |sink: u32| ProblemKind::UnknownNodeType {
        suggestion: Some("Plus".to_owned()),
        feeds: Some(spreadlight_graph::FedSink {
            path: vec![NodeId(sink)],
            node_type: "Probe".to_owned(),
        }),
    };
    for (problem, (within, sink)) in problems.iter().zip([(2, 3), (4, 5)]) {
        assert_eq!(problem.within, [NodeId(within)]);
        assert_eq!(problem.node, NodeId(2));
        assert_eq!(problem.kind, expect(sink));
    }
    assert!(
        problems[0]
            .to_string()
            .contains("unknown node type (did you mean `Plus`?); kept as a placeholder")
            && problems[0]
                .to_string()
                .contains("so `Probe` #3, which it feeds, runs without its work"),
        "{}",
        problems[0]
    );
}

#[test]
fn subpatch_files_come_from_modules_beside_the_patch() {
    let dir = tempfile::tempdir().expect("tempdir");
    std::fs::create_dir(dir.path().join("modules")).expect("mkdir");
    format::save(&twice(), &dir.path().join("modules/Twice.ron")).expect("save");
    let mut patch = Patch::default();
    patch.add(NodeDoc::new(1, "Twice").with("X", vec![4.0f32]));
    patch.add(probe(2, "out"));
    patch.link(1, "Y", 2, "Input");
    let mut rt = Runtime::new(registry());
    rt.provide(Arc::new(PatchDir(dir.path().to_owned())));
    assert!(rt.load(&patch).is_empty(), "{:?}", rt.problems());
    rt.evaluate(FrameClock::fixed(0, 60.0));
    assert_eq!(floats(&rt, "out"), [8.0]);
    let library = rt.library().expect("found beside the patch");
    assert!(
        library.entries().any(|(name, _)| name == "Twice"),
        "listed as a node type"
    );

    // The file changes on disk: the next load reads it again.
    let mut thrice = twice();
    thrice.add(NodeDoc::new(9, "Plus"));
    thrice.links.retain(|l| l.to.node() != NodeId(3));
    thrice.link(2, "Output", 9, "A");
    thrice.link(1, "Output", 9, "B");
    thrice.link(9, "Output", 3, "Input");
    std::thread::sleep(std::time::Duration::from_millis(20));
    format::save(&thrice, &dir.path().join("modules/Twice.ron")).expect("save");
    rt.load(&patch);
    rt.evaluate(FrameClock::fixed(1, 60.0));
    assert_eq!(floats(&rt, "out"), [12.0]);
}

#[test]
fn a_missing_subpatch_file_is_a_placeholder_that_keeps_links_and_values() {
    let mut patch = parent();
    patch.add(NodeDoc::new(6, "Gone").with("X", vec![3.0f32]));
    patch.link(1, "Output", 6, "X");
    patch.add(NodeDoc::new(7, "Plus"));
    patch.link(6, "Y", 7, "A");
    let text = format::to_string(&patch).expect("encode");
    let back = format::from_str(&text, std::path::Path::new("p.ron")).expect("decode");
    assert_eq!(back, patch, "lossless");
    let mut rt = Runtime::new(registry());
    let problems = rt.load(&back).to_vec();
    assert_eq!(problems.len(), 1, "{problems:?}");
    // Nothing downstream of it is a sink: it drops no sink's work.
    assert_eq!(
        problems[0].kind,
        ProblemKind::UnknownNodeType {
            suggestion: None,
            feeds: None
        }
    );
    assert_eq!(problems[0].severity, Severity::Warning);
    rt.evaluate(FrameClock::fixed(0, 60.0));
    assert_eq!(floats(&rt, "linked"), [2.0, 4.0, 6.0], "the rest runs");
}

#[test]
fn an_unreadable_subpatch_file_is_an_error_and_a_placeholder() {
    let dir = tempfile::tempdir().expect("tempdir");
    std::fs::create_dir(dir.path().join("modules")).expect("mkdir");
    std::fs::write(
        dir.path().join("modules/Broken.ron"),
        "(version: 1, nodes: [",
    )
    .expect("write");
    let mut patch = Patch::default();
    patch.add(NodeDoc::new(7, "Broken").with("X", vec![1.0f32]));
    let mut rt = Runtime::new(registry());
    rt.set_library(Library::beside(dir.path()));
    let problems = rt.load(&patch).to_vec();
    assert_eq!(problems.len(), 1, "{problems:?}");
    assert_eq!(problems[0].severity, Severity::Error);
    let text = problems[0].to_string();
    assert!(
        text.contains("Broken.ron") && text.contains("placeholder"),
        "{text}"
    );
}

#[test]
fn recursion_is_an_error_naming_the_chain() {
    let mut a = Patch::default();
    a.add(NodeDoc::new(1, "B"));
    let mut b = Patch::default();
    b.add(NodeDoc::new(1, "A"));
    let mut patch = Patch::default();
    patch.subpatches.insert("A".to_owned(), a);
    patch.subpatches.insert("B".to_owned(), b);
    patch.add(NodeDoc::new(1, "A"));
    patch.add(probe(2, "p").with("Input", vec![1.0f32]));
    let mut rt = Runtime::new(registry());
    let problems = rt.load(&patch).to_vec();
    assert_eq!(problems.len(), 1, "{problems:?}");
    assert_eq!(problems[0].within, [NodeId(1), NodeId(1)]);
    assert_eq!(
        problems[0].kind,
        ProblemKind::RecursiveSubpatch {
            chain: vec!["A".into(), "B".into(), "A".into()]
        }
    );
    let text = problems[0].to_string();
    assert!(text.contains("`A` -> `B` -> `A`"), "{text}");
    rt.evaluate(FrameClock::fixed(0, 60.0));
    assert_eq!(floats(&rt, "p"), [1.0], "the rest runs");
}

#[test]
fn problems_name_the_subpatch_they_lie_in_and_pins_by_name() {
    let mut def = twice();
    def.link(2, "Output", 3, "Nope");
    let mut patch = Patch::default();
    patch.subpatches.insert("Twice".to_owned(), def);
    patch.add(NodeDoc::new(8, "Twice").with("Z", vec![1.0f32]));
    patch.add(probe(9, "p"));
    patch.link(8, "W", 9, "Input");
    patch.add(NodeDoc::new(10, "Round"));
    patch.link(10, "Output", 8, "X");
    let mut rt = Runtime::new(registry());
    let problems: Vec<String> = rt.load(&patch).iter().map(|p| p.to_string()).collect();
    let expect = [
        "node #8 > #3 `Outlet`, pin `Nope`: no such input pin",
        "node #8 `Twice`, pin `Z`: value for an input the node does not have (inputs: `X`)",
        "node #8 `Twice`, pin `W`: no such output pin (outputs: `Y`, `Count`)",
    ];
    for e in expect {
        assert!(
            problems.iter().any(|p| p.starts_with(e)),
            "{e}\nin {problems:#?}"
        );
    }
    // An Int into the Float pin is converted as for any node; a Bool would not link.
    assert_eq!(problems.len(), 3, "{problems:#?}");
}

#[test]
fn inline_subpatches_round_trip_and_raise_the_version() {
    // A new patch is of the current version (3 since comments and frames);
    // an old one is raised to what its subpatches need (below).
    let patch = parent();
    let text = format::to_string(&patch).expect("encode");
    let current = spreadlight_graph::FORMAT_VERSION;
    assert!(
        text.starts_with(&format!("(\n    version: {current},")),
        "{text}"
    );
    let back = format::from_str(&text, std::path::Path::new("p.ron")).expect("decode");
    let mut expected = patch.clone();
    expected.version = current;
    assert_eq!(back, expected);
    assert_eq!(format::to_string(&back).expect("encode"), text);

    let mut old = Patch {
        version: 1,
        ..Patch::default()
    };
    old.add(NodeDoc::new(1, "Plus"));
    let text = format::to_string(&old).expect("encode");
    assert!(
        text.contains("version: 1,"),
        "no subpatches: stays version 1"
    );
}

/// Bypass on a subpatch node works as on any node: its first input passes to
/// its first output of the same type, its other outputs are empty, and its
/// inside does not run; un-bypassed, it computes again.
#[test]
fn a_bypassed_instance_passes_its_first_input_and_its_inside_does_not_run() {
    let mut p = parent();
    p.add(probe(6, "count"));
    p.link(2, "Count", 6, "Input");
    let mut rt = loaded(&p);
    rt.evaluate(FrameClock::fixed(0, 60.0));
    assert_eq!(floats(&rt, "linked"), [2.0, 4.0, 6.0]);
    assert_eq!(ints(&rt, "count"), [1]);

    p.node_mut(NodeId(2)).expect("node").bypass = true;
    let problems = rt.load(&p).to_vec();
    assert!(problems.is_empty(), "{problems:?}");
    rt.evaluate(FrameClock::fixed(1, 60.0));
    assert_eq!(
        floats(&rt, "linked"),
        [1.0, 2.0, 3.0],
        "X passes to Y (the first Float output) undoubled"
    );
    assert_eq!(
        ints(&rt, "count"),
        [] as [i64; 0],
        "the other output is empty"
    );
    assert_eq!(
        **rt.output(NodeId(2), "Y").expect("the instance's pin"),
        Spread::Float(vec![1.0, 2.0, 3.0])
    );
    // The other instance, not bypassed, still doubles.
    assert_eq!(floats(&rt, "valued"), [20.0]);

    p.node_mut(NodeId(2)).expect("node").bypass = false;
    rt.load(&p);
    rt.evaluate(FrameClock::fixed(2, 60.0));
    assert_eq!(floats(&rt, "linked"), [2.0, 4.0, 6.0], "runs again");
    assert!(ints(&rt, "count")[0] >= 1);
}
