//! The patch's window is the first viewport (the whole window in the show
//! window): `WindowSize (Window)` reports its pixel size, `Mouse (Window)` the
//! pointer across it, `KeyMatch (Keyboard)` the keys held while the pointer
//! is over it. Driven through egui's input, on a paused patch (input alone
//! re-evaluates a patch that reads it).

use crate::common;

use egui::{Key, Vec2};
use egui_kittest::Harness;
use spreadlight_editor::EditorApp;
use spreadlight_graph::{NodeDoc, NodeId, Patch, Spread, format};

fn patch() -> Patch {
    let mut p = Patch::default();
    p.add(NodeDoc::new(1, "Mouse (Window)"));
    p.add(
        NodeDoc::new(2, "Probe")
            .at(80.0, 0.0)
            .with("Name", vec!["x".to_owned()]),
    );
    p.add(NodeDoc::new(3, "WindowSize (Window)").at(0.0, 60.0));
    p.add(
        NodeDoc::new(4, "Probe")
            .at(80.0, 60.0)
            .with("Name", vec!["w".to_owned()]),
    );
    p.add(
        NodeDoc::new(5, "KeyMatch (Keyboard)")
            .at(0.0, 120.0)
            .with("Key Match", vec!["A".to_owned()]),
    );
    p.add(
        NodeDoc::new(6, "Probe")
            .at(80.0, 120.0)
            .with("Name", vec!["a".to_owned()]),
    );
    p.add(
        NodeDoc::new(7, "Probe")
            .at(80.0, 180.0)
            .with("Name", vec!["inside".to_owned()]),
    );
    p.link(1, "X", 2, "Input");
    p.link(3, "Width", 4, "Input");
    p.link(5, "Output", 6, "Input");
    p.link(1, "Inside", 7, "Input");
    p
}

fn harness(dir: &tempfile::TempDir, show: bool) -> Harness<'static, EditorApp> {
    let path = dir.path().join("input.ron");
    format::save(&patch(), &path).expect("save");
    let options = common::options(Some(path), dir.path().join("config"));
    let mut h = common::editor_with(options, Vec2::new(900.0, 600.0), 40, move |app| {
        app.set_show_mode(show);
    });
    h.run_steps(4);
    h
}

fn out(h: &Harness<'_, EditorApp>, node: u32, pin: &str) -> Spread {
    h.state()
        .runtime()
        .output(NodeId(node), pin)
        .map(|s| (**s).clone())
        .unwrap_or_else(|| panic!("{node}.{pin} was not evaluated"))
}

fn key(h: &mut Harness<'_, EditorApp>, key: Key, pressed: bool) {
    common::key_event(h, key, pressed);
    h.run_steps(3);
}

#[test]
fn the_first_viewport_is_the_patch_s_window_for_its_input_nodes() {
    let dir = tempfile::tempdir().expect("tempdir");
    let mut h = harness(&dir, false);
    let area = h.state().patch_window_rect().expect("the viewport's area");
    let (w, _) = h.state().viewport_pixels(0).expect("a viewport");
    assert!(w > 16, "the viewport has a real size: {w}");
    assert_eq!(out(&h, 3, "Width"), Spread::Int(vec![i64::from(w)]));

    // Three quarters across the viewport: X is 0.5 (-1 at the left edge, 1 at the right).
    h.hover_at(area.center() + Vec2::new(area.width() / 4.0, 0.0));
    h.run_steps(3);
    let Spread::Float(x) = out(&h, 1, "X") else {
        panic!("X is a float")
    };
    assert!((x[0] - 0.5).abs() < 0.02, "X {x:?}");
    assert_eq!(out(&h, 1, "Inside"), Spread::Bool(vec![true]));

    // Keys reach the patch while the pointer is over its window.
    key(&mut h, Key::A, true);
    assert_eq!(out(&h, 5, "Output"), Spread::Bool(vec![true]));
    key(&mut h, Key::A, false);
    assert_eq!(out(&h, 5, "Output"), Spread::Bool(vec![false]));

    // Over the canvas the pointer is outside the patch's window, and keys stay in the editor.
    let canvas = h.state().canvas_rect().expect("canvas");
    h.hover_at(canvas.center());
    h.run_steps(3);
    assert_eq!(out(&h, 1, "Inside"), Spread::Bool(vec![false]));
    key(&mut h, Key::A, true);
    assert_eq!(out(&h, 5, "Output"), Spread::Bool(vec![false]));
}

#[test]
fn in_the_show_window_the_whole_window_is_the_patch_s() {
    let dir = tempfile::tempdir().expect("tempdir");
    let mut h = harness(&dir, true);
    let ppp = h.ctx.pixels_per_point();
    let expected = (900.0 * ppp) as i64;
    assert_eq!(out(&h, 3, "Width"), Spread::Int(vec![expected]));
    h.hover_at(egui::pos2(0.0, 300.0));
    h.run_steps(3);
    let Spread::Float(x) = out(&h, 1, "X") else {
        panic!("X is a float")
    };
    assert!((x[0] + 1.0).abs() < 0.02, "the left edge is -1: {x:?}");
    // Keys always reach the show window's patch.
    key(&mut h, Key::A, true);
    assert_eq!(out(&h, 5, "Output"), Spread::Bool(vec![true]));
}
