//! The example patch `patches/core-library.ron`, run frame by frame through
//! the runtime: a beat counter (LFO > 0.5 -> Counter), a keyframe track with
//! easing played by a looping Timeliner, Format, Damper and Expr working together.

use std::path::Path;

use spreadlight_graph::{FrameClock, Runtime, Spread, format};

fn probe(rt: &Runtime, name: &str) -> Spread {
    (**rt
        .probes()
        .get(name)
        .unwrap_or_else(|| panic!("no probe `{name}`")))
    .clone()
}

#[test]
fn the_core_library_example_counts_beats_and_plays_keyframes() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../patches/core-library.ron");
    let patch = format::load(&path).unwrap_or_else(|e| panic!("{e}"));
    let mut rt = Runtime::new(spreadlight_nodes::registry());
    assert!(rt.load(&patch).is_empty());
    let mut beats = Vec::new();
    for frame in 0..=120 {
        rt.evaluate(FrameClock::fixed(frame, 60.0));
        assert!(rt.node_errors().next().is_none(), "frame {frame}");
        let Spread::Int(beat) = probe(&rt, "beat") else {
            panic!("beat is Int")
        };
        beats.push(beat[0]);
        if frame == 90 {
            // The LFO (period 0.5 s) crosses 0.5 at frames 16, 46 and 76.
            assert_eq!(
                probe(&rt, "text"),
                Spread::String(vec!["beat 3 at 5.00".into()])
            );
        }
    }
    let edges: Vec<usize> = (1..beats.len())
        .filter(|&f| beats[f] != beats[f - 1])
        .collect();
    assert_eq!(edges, [16, 46, 76, 106]);
    // Counter's range is 0..3: the fourth beat wraps to 0.
    assert_eq!(beats[106], 0);
    // The keyframes ease 0 -> 10 -> 0 over two seconds; at 2 s the loop is back at 0.
    assert_eq!(probe(&rt, "keyframes"), Spread::Float(vec![0.0]));
    rt.evaluate(FrameClock::fixed(121, 60.0));
    let Spread::Float(k) = probe(&rt, "keyframes") else {
        panic!("keyframes are Float")
    };
    assert!(k[0] > 0.0 && k[0] < 0.01, "the loop starts again: {k:?}");
    let Spread::Vec3(orbit) = probe(&rt, "orbit") else {
        panic!("orbit is Vec3")
    };
    // z follows the damped track, lagging behind it on the way down.
    assert!(orbit[0].z > 0.0 && orbit[0].z < 5.0, "{}", orbit[0]);
}
