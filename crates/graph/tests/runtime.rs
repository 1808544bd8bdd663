//! The runtime's promises, asserted through its statistics: only what feeds a
//! sink runs, unchanged nodes are reused, failures stay local, edits
//! re-evaluate only what they touch. Uses small test-only node types so the
//! graph crate is tested on its own.

use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};

use spreadlight_graph::stats::NodeRun;
use spreadlight_graph::{
    EvalContext, FrameClock, Node, NodeDef, NodeDoc, NodeError, NodeId, Patch, PinType,
    ProblemKind, Registry, Runtime, Spread, format,
};

fn registry() -> Registry {
    let mut r = Registry::new();
    r.add(
        NodeDef::new("Const", "Test", "")
            .input("Value", 1.0f32)
            .output::<f32>("Output")
            .per_slice1(|v: &f32| *v),
    );
    r.add(
        NodeDef::new("Int", "Test", "")
            .input("Value", 1i64)
            .output::<i64>("Output")
            .per_slice1(|v: &i64| *v),
    );
    r.add(
        NodeDef::new("Add", "Test", "")
            .input("A", 0.0f32)
            .input("B", 0.0f32)
            .output::<f32>("Output")
            .per_slice2(|a: &f32, b: &f32| a + b),
    );
    r.add(
        NodeDef::new("Time", "Test", "")
            .output::<f32>("Output")
            .time_dependent()
            .evaluate(|cx| {
                let t = cx.clock.time as f32;
                cx.set(0, vec![t]);
                Ok(())
            }),
    );
    r.add(
        NodeDef::new("FailNegative", "Test", "")
            .input("Input", 0.0f32)
            .output::<f32>("Output")
            .evaluate(|cx| {
                let v = cx.slices::<f32>(0)?.to_vec();
                if v.iter().any(|x| *x < 0.0) {
                    return Err(cx.input_error(0, "negative"));
                }
                cx.set(0, v);
                Ok(())
            }),
    );
    r.add(
        NodeDef::new("Needs", "Test", "")
            .input_spread("Input", PinType::Float, Spread::Float(vec![]))
            .output::<f32>("Output")
            .evaluate(|cx| {
                let v = cx.slices::<f32>(0)?.to_vec();
                if v.is_empty() {
                    return Err(cx.input_error(0, "nothing connected"));
                }
                cx.set(0, v);
                Ok(())
            }),
    );
    r.add(
        NodeDef::new("Counter", "Test", "")
            .input("Input", 0.0f32)
            .output::<i64>("Runs")
            .stateful()
            .construct(|| Counter(0)),
    );
    r.add(
        NodeDef::new("Previous", "Test", "")
            .input("Input", 0.0f32)
            .output::<f32>("Output")
            .remembers(1)
            .per_slice1(|v: &f32| *v),
    );
    r.add(
        NodeDef::new("Sink", "Test", "")
            .input_spread("Input", PinType::Any, Spread::Float(vec![]))
            .input("Name", "sink".to_owned())
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

/// Counts its own evaluations: state that must survive edits elsewhere.
struct Counter(i64);

impl Node for Counter {
    fn evaluate(&mut self, cx: &mut EvalContext<'_>) -> Result<(), NodeError> {
        self.0 += 1;
        cx.set(0, vec![self.0]);
        Ok(())
    }
}

fn sink(id: u32, name: &str) -> NodeDoc {
    NodeDoc::new(id, "Sink").with("Name", vec![name.to_owned()])
}

fn run_frames(rt: &mut Runtime, frames: u64) -> Vec<spreadlight_graph::FrameStats> {
    (0..frames)
        .map(|f| rt.evaluate(FrameClock::fixed(f, 60.0)).clone())
        .collect()
}

fn count(frames: &[spreadlight_graph::FrameStats], id: u32, run: NodeRun) -> usize {
    frames
        .iter()
        .filter(|s| s.node(NodeId(id)).map(|n| n.run) == Some(run))
        .count()
}

fn probe(rt: &Runtime, name: &str) -> Spread {
    rt.probes()
        .get(name)
        .map(|s| (**s).clone())
        .unwrap_or_else(|| panic!("probe {name} recorded nothing"))
}

#[test]
fn a_network_remembers_what_its_running_nodes_remember() {
    use spreadlight_graph::{Memory, Network};
    let memory = |p: &Patch| Network::compile(p, &registry()).memory();
    let mut p = Patch::default();
    p.add(NodeDoc::new(1, "Const"));
    p.add(sink(2, "out"));
    p.link(1, "Output", 2, "Input");
    assert_eq!(memory(&p), (Memory::None, vec![]));
    // A stateful node that reaches no sink never runs: it does not count.
    p.add(NodeDoc::new(3, "Counter"));
    assert_eq!(memory(&p), (Memory::None, vec![]));
    p.add(NodeDoc::new(4, "Previous"));
    p.add(sink(5, "previous"));
    p.link(4, "Output", 5, "Input");
    assert_eq!(memory(&p), (Memory::Frames(1), vec!["Previous".to_owned()]));
    // Memories add up along a chain: the previous frame's previous frame.
    p.add(NodeDoc::new(7, "Previous"));
    p.add(sink(8, "previous previous"));
    p.link(4, "Output", 7, "Input");
    p.link(7, "Output", 8, "Input");
    assert_eq!(memory(&p), (Memory::Frames(2), vec!["Previous".to_owned()]));
    p.add(sink(6, "runs"));
    p.link(3, "Runs", 6, "Input");
    assert_eq!(memory(&p), (Memory::Unbounded, vec!["Counter".to_owned()]));
    assert!(Memory::None < Memory::Frames(1) && Memory::Frames(1) < Memory::Frames(2));
    assert!(Memory::Frames(u32::MAX) < Memory::Unbounded);
}

#[test]
fn a_disconnected_chain_is_never_evaluated() {
    let mut p = Patch::default();
    p.add(NodeDoc::new(1, "Const"));
    p.add(sink(2, "out"));
    p.link(1, "Output", 2, "Input");
    // A chain that reaches no sink, including a time-dependent node.
    p.add(NodeDoc::new(10, "Time"));
    p.add(NodeDoc::new(11, "Add"));
    p.add(NodeDoc::new(12, "Add"));
    p.link(10, "Output", 11, "A");
    p.link(11, "Output", 12, "A");
    let mut rt = Runtime::new(registry());
    assert!(rt.load(&p).is_empty());
    let frames = run_frames(&mut rt, 10);
    for id in [10, 11, 12] {
        assert_eq!(count(&frames, id, NodeRun::Skipped), 10, "node {id}");
    }
    assert!(frames.iter().all(|s| s.skipped == 3));
    assert_eq!(probe(&rt, "out"), Spread::Float(vec![1.0]));
}

#[test]
fn a_pin_demanded_by_the_host_evaluates_its_branch_and_only_there() {
    // The editor's previews: a branch that feeds no sink runs for the host
    // that looks at it; a runtime without that demand (`render`) still skips it.
    let mut p = Patch::default();
    p.add(NodeDoc::new(1, "Const"));
    p.add(sink(2, "out"));
    p.link(1, "Output", 2, "Input");
    p.add(NodeDoc::new(10, "Const").with("Value", vec![4.0f32]));
    p.add(NodeDoc::new(11, "Add").with("B", vec![1.0f32]));
    p.add(NodeDoc::new(12, "Add"));
    p.link(10, "Output", 11, "A");
    p.link(11, "Output", 12, "A");
    let mut plain = Runtime::new(registry());
    let mut looked_at = Runtime::new(registry());
    assert!(plain.load(&p).is_empty());
    assert!(looked_at.load(&p).is_empty());
    looked_at.demand_also(vec![(vec![NodeId(11)], "Output".to_owned())]);
    let plain_frames = run_frames(&mut plain, 2);
    let frames = run_frames(&mut looked_at, 2);
    for id in [10, 11] {
        assert_eq!(
            count(&frames, id, NodeRun::Evaluated),
            1,
            "node {id} ran once"
        );
        assert_eq!(count(&plain_frames, id, NodeRun::Skipped), 2, "node {id}");
    }
    assert_eq!(
        count(&frames, 12, NodeRun::Skipped),
        2,
        "downstream of the pin: not demanded"
    );
    let index = looked_at.network().index_of(NodeId(11)).expect("node 11");
    assert!(looked_at.is_demanded(index) && !plain.is_demanded(index));
    assert!(
        !looked_at.network().is_needed(index),
        "the network's own demand is unchanged"
    );
    let value = looked_at.output(NodeId(11), "Output").expect("evaluated");
    assert_eq!(**value, Spread::Float(vec![5.0]));
    // Demand survives a reload and goes with an empty list.
    assert!(looked_at.load(&p).is_empty());
    assert!(looked_at.is_demanded(index));
    looked_at.demand_also(Vec::new());
    let frames = run_frames(&mut looked_at, 1);
    assert_eq!(count(&frames, 11, NodeRun::Skipped), 1);
    assert_eq!(probe(&looked_at, "out"), Spread::Float(vec![1.0]));
}

#[test]
fn an_unchanged_subgraph_is_evaluated_once_over_ten_frames() {
    let mut p = Patch::default();
    p.add(NodeDoc::new(1, "Const").with("Value", vec![2.0f32, 3.0]));
    p.add(NodeDoc::new(2, "Add").with("B", vec![10.0f32]));
    p.add(sink(3, "sum"));
    p.link(1, "Output", 2, "A");
    p.link(2, "Output", 3, "Input");
    let mut rt = Runtime::new(registry());
    rt.load(&p);
    let frames = run_frames(&mut rt, 10);
    for id in [1, 2, 3] {
        assert_eq!(count(&frames, id, NodeRun::Evaluated), 1, "node {id}");
        assert_eq!(count(&frames, id, NodeRun::Reused), 9, "node {id}");
    }
    assert_eq!(frames[0].evaluated, 3);
    assert!(
        frames[1..]
            .iter()
            .all(|s| s.evaluated == 0 && s.reused == 3)
    );
    assert_eq!(probe(&rt, "sum"), Spread::Float(vec![12.0, 13.0]));
}

#[test]
fn time_dependent_nodes_and_their_dependents_run_every_frame() {
    let mut p = Patch::default();
    p.add(NodeDoc::new(1, "Time"));
    p.add(NodeDoc::new(2, "Add").with("B", vec![1.0f32]));
    p.add(NodeDoc::new(3, "Const"));
    p.add(NodeDoc::new(4, "Add"));
    p.add(sink(5, "t"));
    p.add(sink(6, "c"));
    p.link(1, "Output", 2, "A");
    p.link(2, "Output", 5, "Input");
    p.link(3, "Output", 4, "A");
    p.link(4, "Output", 6, "Input");
    let mut rt = Runtime::new(registry());
    rt.load(&p);
    let frames = run_frames(&mut rt, 10);
    assert_eq!(count(&frames, 1, NodeRun::Evaluated), 10);
    assert_eq!(count(&frames, 2, NodeRun::Evaluated), 10);
    assert_eq!(count(&frames, 5, NodeRun::Evaluated), 10);
    // The static branch beside it is not dragged along.
    assert_eq!(count(&frames, 4, NodeRun::Evaluated), 1);
    assert_eq!(probe(&rt, "t"), Spread::Float(vec![1.0 + 9.0 / 60.0]));
}

#[test]
fn a_failing_node_outputs_nothing_and_the_rest_keeps_running() {
    let mut p = Patch::default();
    p.add(NodeDoc::new(1, "FailNegative").with("Input", vec![-1.0f32]));
    p.add(NodeDoc::new(2, "Add").with("B", vec![1.0f32]));
    p.add(sink(3, "after_failure"));
    p.add(NodeDoc::new(4, "Const"));
    p.add(sink(5, "healthy"));
    p.link(1, "Output", 2, "A");
    p.link(2, "Output", 3, "Input");
    p.link(4, "Output", 5, "Input");
    let mut rt = Runtime::new(registry());
    rt.load(&p);
    let stats = rt.evaluate(FrameClock::fixed(0, 60.0)).clone();
    assert_eq!(stats.failed, 1);
    assert_eq!(stats.node(NodeId(1)).map(|n| n.run), Some(NodeRun::Failed));
    let err = rt.node_error(NodeId(1)).expect("error is kept on the node");
    assert_eq!(
        err,
        &NodeError::Input {
            pin: "Input".into(),
            message: "negative".into()
        }
    );
    assert_eq!(
        probe(&rt, "after_failure"),
        Spread::Float(vec![]),
        "empty input spreads to empty output"
    );
    assert_eq!(probe(&rt, "healthy"), Spread::Float(vec![1.0]));

    // Fixing the value clears the error and re-evaluates the chain.
    p.node_mut(NodeId(1))
        .expect("node")
        .values
        .insert("Input".into(), Spread::Float(vec![4.0]));
    rt.load(&p);
    rt.evaluate(FrameClock::fixed(1, 60.0));
    assert!(rt.node_error(NodeId(1)).is_none());
    assert_eq!(probe(&rt, "after_failure"), Spread::Float(vec![5.0]));
}

#[test]
fn an_edit_re_evaluates_only_what_it_touches_and_keeps_node_state() {
    let mut p = Patch::default();
    p.add(NodeDoc::new(1, "Const"));
    p.add(NodeDoc::new(2, "Counter"));
    p.add(sink(3, "runs"));
    p.link(1, "Output", 2, "Input");
    p.link(2, "Runs", 3, "Input");
    p.add(NodeDoc::new(4, "Const"));
    p.add(sink(5, "other"));
    p.link(4, "Output", 5, "Input");
    let mut rt = Runtime::new(registry());
    rt.load(&p);
    run_frames(&mut rt, 3);
    assert_eq!(probe(&rt, "runs"), Spread::Int(vec![1]));

    // Edit the other branch: the counter branch stays reused.
    p.node_mut(NodeId(4))
        .expect("node")
        .values
        .insert("Value".into(), Spread::Float(vec![7.0]));
    rt.load(&p);
    let stats = rt.evaluate(FrameClock::fixed(3, 60.0)).clone();
    assert_eq!(stats.evaluated, 2, "the edited constant and its sink");
    assert_eq!(stats.node(NodeId(2)).map(|n| n.run), Some(NodeRun::Reused));
    assert_eq!(probe(&rt, "other"), Spread::Float(vec![7.0]));

    // Edit upstream of the counter: it runs again, and its state (the count) survived the reload.
    p.node_mut(NodeId(1))
        .expect("node")
        .values
        .insert("Value".into(), Spread::Float(vec![2.0]));
    rt.load(&p);
    rt.evaluate(FrameClock::fixed(4, 60.0));
    assert_eq!(probe(&rt, "runs"), Spread::Int(vec![2]));
}

#[test]
fn relinking_an_input_re_evaluates_it() {
    let mut p = Patch::default();
    p.add(NodeDoc::new(1, "Const").with("Value", vec![1.0f32]));
    p.add(NodeDoc::new(2, "Const").with("Value", vec![2.0f32]));
    p.add(sink(3, "out"));
    p.link(1, "Output", 3, "Input");
    let mut rt = Runtime::new(registry());
    rt.load(&p);
    run_frames(&mut rt, 2);
    p.links[0] = spreadlight_graph::LinkDoc::new(2, "Output", 3, "Input");
    rt.load(&p);
    rt.evaluate(FrameClock::fixed(2, 60.0));
    assert_eq!(probe(&rt, "out"), Spread::Float(vec![2.0]));
}

#[test]
fn int_outputs_feed_float_inputs() {
    let mut p = Patch::default();
    p.add(NodeDoc::new(1, "Int").with("Value", vec![3i64, 4]));
    p.add(NodeDoc::new(2, "Add").with("B", vec![0.5f32]));
    p.add(sink(3, "out"));
    p.link(1, "Output", 2, "A");
    p.link(2, "Output", 3, "Input");
    let mut rt = Runtime::new(registry());
    assert!(rt.load(&p).is_empty());
    rt.evaluate(FrameClock::default());
    assert_eq!(probe(&rt, "out"), Spread::Float(vec![3.5, 4.5]));
}

#[test]
fn a_cycle_is_reported_and_the_rest_of_the_patch_runs() {
    let mut p = Patch::default();
    p.add(NodeDoc::new(1, "Add").with("B", vec![1.0f32]));
    p.add(NodeDoc::new(2, "Add"));
    p.add(sink(3, "out"));
    p.link(1, "Output", 2, "A");
    p.link(2, "Output", 1, "A");
    p.link(2, "Output", 3, "Input");
    let mut rt = Runtime::new(registry());
    let problems = rt.load(&p).to_vec();
    assert_eq!(problems.len(), 1, "{problems:?}");
    assert!(matches!(&problems[0].kind, ProblemKind::Cycle { path, .. } if path.len() == 3));
    rt.evaluate(FrameClock::default());
    assert_eq!(probe(&rt, "out"), Spread::Float(vec![1.0]));
}

/// A node that needs what an unknown type was linked to give it fails,
/// and its error says the link comes from that unknown type (the cause to
/// fix), not only that nothing is connected.
#[test]
fn an_input_fed_by_an_unknown_type_names_it_in_the_error() {
    let mut p = Patch::default();
    p.add(NodeDoc::new(1, "Cosnt"));
    p.add(NodeDoc::new(2, "Needs"));
    p.add(sink(3, "out"));
    p.link(1, "Output", 2, "Input");
    p.link(2, "Output", 3, "Input");
    let mut rt = Runtime::new(registry());
    let problems = rt.load(&p).to_vec();
    assert_eq!(problems.len(), 1, "{problems:?}");
    assert!(
        matches!(&problems[0].kind, ProblemKind::UnknownNodeType { suggestion: Some(s), .. } if s == "Const"),
        "{problems:?}"
    );
    rt.evaluate(FrameClock::default());
    assert_eq!(
        rt.node_error(NodeId(2)).map(ToString::to_string).as_deref(),
        Some(
            "input `Input`: nothing connected (it is linked from node #1 `Cosnt`, an unknown node type that outputs nothing)"
        )
    );
}

#[test]
fn an_unknown_node_type_is_a_placeholder_that_keeps_everything() {
    let text = r#"(version: 1, nodes: [
        (id: 1, type: "FutureNode", pos: (5.0, 6.0), values: {"Strength": Float([0.5]), "Mode": Enum(["Fast"])}),
        (id: 2, type: "Add", values: {"B": Float([1.0])}),
        (id: 3, type: "Sink", values: {"Name": String(["out"])}),
    ], links: [
        (from: (1, "Result"), to: (2, "A")),
        (from: (2, "Output"), to: (1, "Feedback")),
        (from: (2, "Output"), to: (3, "Input")),
    ])"#;
    let patch = format::from_str(text, std::path::Path::new("future.ron")).expect("parses");
    let mut rt = Runtime::new(registry());
    let problems = rt.load(&patch).to_vec();
    assert_eq!(problems.len(), 1, "{problems:?}");
    // Its work was meant for the Sink, through the Add.
    assert_eq!(
        problems[0].kind,
        ProblemKind::UnknownNodeType {
            suggestion: None,
            feeds: Some(spreadlight_graph::FedSink {
                path: vec![NodeId(3)],
                node_type: "Sink".to_owned()
            }),
        }
    );
    assert_eq!(problems[0].node_type, "FutureNode");
    let stats = rt.evaluate(FrameClock::default()).clone();
    assert_eq!(stats.node(NodeId(1)).map(|n| n.run), Some(NodeRun::Skipped));
    assert_eq!(
        probe(&rt, "out"),
        Spread::Float(vec![]),
        "a placeholder outputs nothing"
    );

    let saved = format::to_string(&patch).expect("encode");
    let again = format::from_str(&saved, std::path::Path::new("again.ron")).expect("parses");
    assert_eq!(again, patch);
    assert!(
        saved.contains("FutureNode") && saved.contains("\"Feedback\"") && saved.contains("Fast")
    );
}

/// A type whose pins are not known now (a shader file that never compiled)
/// leaves out its values and links quietly: its one error is its own, and
/// the type that has the pins again takes them all back.
#[test]
fn a_type_with_unknown_pins_keeps_its_values_and_links_without_a_problem_each() {
    let mut broken = registry();
    broken.replace(
        NodeDef::new("Add", "Test", "its file does not compile")
            .output::<f32>("Output")
            .pins_unknown()
            .evaluate(|_| Err(NodeError::Other("add.wgsl:3:9: the cause".into()))),
    );
    let mut p = Patch::default();
    p.add(NodeDoc::new(1, "Const").with("Value", vec![2.0f32]));
    p.add(NodeDoc::new(2, "Add").with("B", vec![5.0f32]));
    p.add(sink(3, "out"));
    p.link(1, "Output", 2, "A");
    p.link(2, "Output", 3, "Input");
    let mut rt = Runtime::new(broken);
    assert_eq!(rt.load(&p).to_vec(), [], "no problem per value or link");
    rt.evaluate(FrameClock::default());
    let errors: Vec<String> = rt
        .node_errors()
        .map(|(id, e)| format!("{id}: {e}"))
        .collect();
    assert_eq!(errors, ["#2: add.wgsl:3:9: the cause"]);

    // Fixed: the same document, every value and link back.
    rt.set_registry(registry());
    assert_eq!(rt.load(&p).to_vec(), []);
    rt.evaluate(FrameClock::default());
    assert_eq!(probe(&rt, "out"), Spread::Float(vec![7.0]));
}

#[test]
fn a_bad_value_falls_back_to_the_default_and_is_reported_on_its_pin() {
    let mut p = Patch::default();
    p.add(
        NodeDoc::new(1, "Add")
            .with("A", vec!["two".to_owned()])
            .with("B", vec![f32::NAN]),
    );
    p.add(sink(2, "out"));
    p.link(1, "Output", 2, "Input");
    let mut rt = Runtime::new(registry());
    let problems = rt.load(&p).to_vec();
    let pins: Vec<_> = problems
        .iter()
        .map(|p| p.pin.clone().unwrap_or_default())
        .collect();
    assert_eq!(pins, ["A", "B"]);
    assert!(
        problems[0]
            .to_string()
            .contains("value is String, the pin takes Float"),
        "{}",
        problems[0]
    );
    rt.evaluate(FrameClock::default());
    assert_eq!(probe(&rt, "out"), Spread::Float(vec![0.0]));
}

#[test]
fn constants_are_shared_not_copied_each_frame() {
    // A 100,000-slice constant goes through a pass-through sink without a copy per frame:
    // the spread the sink recorded is the very allocation the document value produced.
    static EVALS: AtomicUsize = AtomicUsize::new(0);
    let mut r = registry();
    r.add(
        NodeDef::new("Pass", "Test", "")
            .input("Input", 0.0f32)
            .output::<f32>("Output")
            .evaluate(|cx| {
                EVALS.fetch_add(1, Ordering::Relaxed);
                let input: Arc<Spread> = cx.input_arc(0).clone();
                cx.set_output_arc(0, input);
                Ok(())
            }),
    );
    let mut p = Patch::default();
    p.add(NodeDoc::new(1, "Pass").with("Input", vec![1.0f32; 100_000]));
    p.add(sink(2, "out"));
    p.link(1, "Output", 2, "Input");
    let mut rt = Runtime::new(r);
    rt.load(&p);
    run_frames(&mut rt, 5);
    assert_eq!(EVALS.load(Ordering::Relaxed), 1);
    assert_eq!(
        rt.output(NodeId(1), "Output").map(|s| s.len()),
        Some(100_000)
    );
}

#[test]
fn services_reach_nodes_and_a_node_can_ask_to_run_again() {
    struct Greeting(String);
    let mut r = registry();
    r.add(
        NodeDef::new("Greet", "Test", "")
            .output::<String>("Output")
            .evaluate(|cx| {
                let text = cx
                    .service::<Greeting>()
                    .map(|g| g.0.clone())
                    .ok_or_else(|| NodeError::Other("no greeting".into()))?;
                cx.set(0, vec![text]);
                Ok(())
            }),
    );
    r.add(
        NodeDef::new("Settle", "Test", "")
            .output::<i64>("Output")
            .construct(|| Settle(0)),
    );
    let mut p = Patch::default();
    p.add(NodeDoc::new(1, "Greet"));
    p.add(sink(2, "greeting"));
    p.link(1, "Output", 2, "Input");
    p.add(NodeDoc::new(3, "Settle"));
    p.add(sink(4, "settle"));
    p.link(3, "Output", 4, "Input");
    let mut rt = Runtime::new(r);
    rt.provide(Arc::new(Greeting("hello".into())));
    rt.load(&p);
    let frames = run_frames(&mut rt, 6);
    assert_eq!(probe(&rt, "greeting"), Spread::String(vec!["hello".into()]));
    // Settle asks to run again until its count reaches 3, then is reused.
    assert_eq!(count(&frames, 3, NodeRun::Evaluated), 3);
    assert_eq!(probe(&rt, "settle"), Spread::Int(vec![3]));
}

/// Counts up and asks to be evaluated again until it reaches 3: like velocity settling after a move.
struct Settle(i64);

impl Node for Settle {
    fn evaluate(&mut self, cx: &mut EvalContext<'_>) -> Result<(), NodeError> {
        self.0 += 1;
        if self.0 < 3 {
            cx.reevaluate_next_frame();
        }
        cx.set(0, vec![self.0]);
        Ok(())
    }
}

/// A node type made at run time (as a shader file or subpatch makes one): an
/// owned name, replaced in the registry when its source changes.
fn scaled(name: &str, factor: f32, pin: &str) -> NodeDef {
    NodeDef::new(
        name.to_owned(),
        "Runtime".to_owned(),
        format!("times {factor}"),
    )
    .input(pin.to_owned(), 1.0f32)
    .output::<f32>("Output")
    .per_slice1(move |v: &f32| v * factor)
}

#[test]
fn a_type_replaced_at_run_time_re_instantiates_its_nodes_and_keeps_values_and_links() {
    let mut reg = registry();
    reg.add(scaled("Scale", 2.0, "Input"));
    let mut p = Patch::default();
    p.add(NodeDoc::new(1, "Const").with("Value", vec![3.0f32]));
    p.add(NodeDoc::new(2, "Scale"));
    p.add(NodeDoc::new(3, "Counter"));
    p.add(sink(4, "scaled"));
    p.add(sink(5, "runs"));
    p.link(1, "Output", 2, "Input");
    p.link(2, "Output", 4, "Input");
    p.link(1, "Output", 3, "Input");
    p.link(3, "Runs", 5, "Input");
    let mut rt = Runtime::new(reg.clone());
    assert!(rt.load(&p).is_empty());
    run_frames(&mut rt, 2);
    assert_eq!(probe(&rt, "scaled"), Spread::Float(vec![6.0]));

    // The file changes: same name, new definition.
    let old = reg.replace(scaled("Scale", 5.0, "Input"));
    assert!(old.is_some());
    rt.set_registry(reg.clone());
    assert!(rt.load(&p).is_empty());
    let stats = rt.evaluate(FrameClock::fixed(2, 60.0)).clone();
    assert_eq!(probe(&rt, "scaled"), Spread::Float(vec![15.0]));
    assert_eq!(
        stats.node(NodeId(2)).map(|n| n.run),
        Some(NodeRun::Evaluated)
    );
    // Nodes of other types keep their state.
    assert_eq!(stats.node(NodeId(3)).map(|n| n.run), Some(NodeRun::Reused));
    assert_eq!(probe(&rt, "runs"), Spread::Int(vec![1]));

    // A pin renamed away: the link stays in the document and is reported.
    reg.replace(scaled("Scale", 5.0, "Renamed"));
    rt.set_registry(reg.clone());
    let problems = rt.load(&p).to_vec();
    assert!(
        problems.iter().any(|pr| pr.node == NodeId(2)),
        "{problems:?}"
    );
    assert_eq!(p.links.len(), 4);

    // Removed: nodes of it become placeholders, the rest runs on.
    reg.remove("Scale");
    rt.set_registry(reg);
    rt.load(&p);
    rt.evaluate(FrameClock::fixed(3, 60.0));
    assert_eq!(probe(&rt, "runs"), Spread::Int(vec![1]));
}

#[test]
fn a_bypassed_node_passes_its_first_input_and_its_other_outputs_are_empty() {
    let mut r = registry();
    r.add(
        NodeDef::new("Split", "Test", "")
            .input("Input", 0.0f32)
            .input("Gain", 10.0f32)
            .output::<i64>("Count")
            .output::<f32>("Output")
            .evaluate(|cx| {
                let v: Vec<f32> = cx.slices::<f32>(0)?.iter().map(|x| x * 10.0).collect();
                cx.set(0, vec![v.len() as i64]);
                cx.set(1, v);
                Ok(())
            }),
    );
    let mut p = Patch::default();
    p.add(NodeDoc::new(1, "Const").with("Value", vec![3.0f32, 4.0]));
    p.add(NodeDoc::new(2, "Split"));
    p.add(sink(3, "passed"));
    p.add(sink(4, "count"));
    p.link(1, "Output", 2, "Input");
    p.link(2, "Output", 3, "Input");
    p.link(2, "Count", 4, "Input");
    let mut rt = Runtime::new(r);
    rt.load(&p);
    rt.evaluate(FrameClock::fixed(0, 60.0));
    assert_eq!(probe(&rt, "passed"), Spread::Float(vec![30.0, 40.0]));
    assert_eq!(probe(&rt, "count"), Spread::Int(vec![2]));

    // Bypassed: the Float input goes to the Float output (the second), unscaled; Count is empty.
    p.node_mut(NodeId(2)).expect("node").bypass = true;
    rt.load(&p);
    rt.evaluate(FrameClock::fixed(1, 60.0));
    assert_eq!(probe(&rt, "passed"), Spread::Float(vec![3.0, 4.0]));
    assert_eq!(probe(&rt, "count"), Spread::Int(vec![]));

    // The bypass is saved, and loading it back bypasses again.
    let text = format::to_string(&p).expect("encode");
    assert!(text.contains("bypass: true"), "{text}");
    let back = format::from_str(&text, std::path::Path::new("b.ron")).expect("decode");
    assert!(back.node(NodeId(2)).expect("node").bypass);

    // Un-bypassed, it runs again.
    p.node_mut(NodeId(2)).expect("node").bypass = false;
    rt.load(&p);
    rt.evaluate(FrameClock::fixed(2, 60.0));
    assert_eq!(probe(&rt, "passed"), Spread::Float(vec![30.0, 40.0]));
}
