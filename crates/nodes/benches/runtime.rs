//! Runtime overhead, per node and per slice. Run with
//! `cargo bench -p spreadlight-nodes --bench runtime`.
//!
//! - `chain_evaluated`: LFO -> N x `Add (Value)` -> Probe, one slice. The LFO
//!   changes every frame, so every node runs: time per frame / N is the cost of
//!   running a trivial node (input gathering, version checks, the call, stats).
//! - `chain_reused`: the same chain behind a constant: every node is reused,
//!   which is the cost of deciding not to run.
//! - `spread_add`: an `LFO` and an `Add (Value)` over S slices each, re-run
//!   every frame: time / 2S is the cost per slice of a spread-processing node.

use spreadlight_graph::{FrameClock, NodeDoc, Patch, Runtime};

fn main() {
    divan::main();
}

fn chain(len: u32, animated: bool) -> Runtime {
    let mut p = Patch::default();
    p.add(if animated {
        NodeDoc::new(1, "LFO")
    } else {
        NodeDoc::new(1, "IOBox (Value)")
    });
    let mut prev = (1, "Output");
    for i in 0..len {
        let id = 2 + i;
        p.add(NodeDoc::new(id, "Add (Value)").with("Input 2", vec![1.0f32]));
        p.link(prev.0, prev.1, id, "Input 1");
        prev = (id, "Output");
    }
    let probe = 2 + len;
    p.add(NodeDoc::new(probe, "Probe").with("Name", vec!["end".to_owned()]));
    p.link(prev.0, prev.1, probe, "Input");
    let mut rt = Runtime::new(spreadlight_nodes::registry());
    assert!(rt.load(&p).is_empty(), "benchmark patch has problems");
    rt
}

#[divan::bench(args = [1000], counter = divan::counter::ItemsCount::new(1000usize))]
fn chain_evaluated(bencher: divan::Bencher, len: u32) {
    let mut rt = chain(len, true);
    let mut frame = 0;
    bencher.bench_local(|| {
        frame += 1;
        let stats = rt.evaluate(FrameClock::fixed(frame, 60.0));
        assert_eq!(stats.evaluated as u32, len + 2);
    });
}

#[divan::bench(args = [1000], counter = divan::counter::ItemsCount::new(1000usize))]
fn chain_reused(bencher: divan::Bencher, len: u32) {
    let mut rt = chain(len, false);
    rt.evaluate(FrameClock::fixed(0, 60.0));
    let mut frame = 0;
    bencher.bench_local(|| {
        frame += 1;
        let stats = rt.evaluate(FrameClock::fixed(frame, 60.0));
        assert_eq!(stats.reused as u32, len + 2);
    });
}

/// Counts 2 x S items: the LFO and the Add each process S slices per frame.
#[divan::bench(args = [100_000], counter = divan::counter::ItemsCount::new(200_000usize))]
fn spread_add(bencher: divan::Bencher, slices: usize) {
    let mut p = Patch::default();
    // An LFO per slice keeps the spread changing, so the Add runs every frame.
    p.add(NodeDoc::new(1, "LFO").with("Period", vec![1.0f32; slices]));
    p.add(
        NodeDoc::new(2, "Add (Value)")
            .with("Input 2", (0..slices).map(|i| i as f32).collect::<Vec<_>>()),
    );
    p.add(NodeDoc::new(3, "Probe").with("Name", vec!["sum".to_owned()]));
    p.link(1, "Output", 2, "Input 1");
    p.link(2, "Output", 3, "Input");
    let mut rt = Runtime::new(spreadlight_nodes::registry());
    assert!(rt.load(&p).is_empty());
    let mut frame = 0;
    bencher.bench_local(|| {
        frame += 1;
        rt.evaluate(FrameClock::fixed(frame, 60.0));
    });
}
