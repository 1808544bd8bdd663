//! IOBoxes show their spread as rows on the canvas: every slice editable in
//! place, slices added and undone; a linked IOBox shows its live value,
//! updating as time runs. At a small window size.

use crate::common;

use egui::Vec2;
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use spreadlight_editor::EditorApp;
use spreadlight_graph::{NodeDoc, NodeId, Patch, Spread, format};

fn harness(dir: &tempfile::TempDir, patch: &Patch) -> Harness<'static, EditorApp> {
    harness_sized(dir, patch, Vec2::new(800.0, 500.0))
}

fn harness_sized(
    dir: &tempfile::TempDir,
    patch: &Patch,
    size: Vec2,
) -> Harness<'static, EditorApp> {
    let path = dir.path().join("iobox.ron");
    format::save(patch, &path).expect("save");
    let options = common::options(Some(path), dir.path().join("config"));
    let mut h = common::editor(options, size);
    h.run();
    h
}

fn value(h: &Harness<'_, EditorApp>, id: u32) -> Option<Spread> {
    h.state()
        .doc()
        .patch()
        .node(NodeId(id))
        .and_then(|n| n.values.get("Input").cloned())
}

#[test]
fn an_iobox_shows_and_edits_its_rows_and_a_linked_one_its_live_value() {
    let dir = tempfile::tempdir().expect("tempdir");
    let mut p = Patch::default();
    p.add(NodeDoc::new(1, "IOBox (Value)").with("Input", vec![1.5f32, 2.5, 3.5]));
    p.add(NodeDoc::new(2, "LFO").at(0.0, 60.0));
    p.add(NodeDoc::new(3, "IOBox (Value)").at(60.0, 60.0));
    p.add(NodeDoc::new(4, "Probe").at(120.0, 60.0));
    p.link(2, "Output", 3, "Input");
    // What feeds no sink is not evaluated: the IOBox watches a value on its way to the probe.
    p.link(3, "Output", 4, "Input");
    let mut h = harness(&dir, &p);
    // Three rows, each slice with its own editor and its own remove button.
    assert_eq!(h.query_all_by_label("−").count(), 3, "a row per slice");
    // Canvas widgets' accessibility rects are in canvas coordinates: click where they are on screen.
    let rect = h.get_by_label("+ slice").rect();
    let at = egui::Rect::from_min_max(
        h.state().canvas_to_screen(&h.ctx, rect.min),
        h.state().canvas_to_screen(&h.ctx, rect.max),
    )
    .center();
    h.hover_at(at);
    h.step();
    for pressed in [true, false] {
        h.event(egui::Event::PointerButton {
            pos: at,
            button: egui::PointerButton::Primary,
            pressed,
            modifiers: egui::Modifiers::NONE,
        });
    }
    h.run();
    assert_eq!(value(&h, 1), Some(Spread::Float(vec![1.5, 2.5, 3.5, 3.5])));
    h.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::Z);
    h.run();
    assert_eq!(value(&h, 1), Some(Spread::Float(vec![1.5, 2.5, 3.5])));
    // The linked IOBox shows what flows in, and follows it.
    let live = |h: &Harness<'_, EditorApp>| {
        let out = h
            .state()
            .runtime()
            .output(NodeId(3), "Output")
            .expect("evaluated");
        spreadlight_editor::iobox::slice_text(out, 0)
    };
    let before = live(&h);
    assert!(h.query_by_label(&before).is_some(), "live row {before}");
    h.state_mut().set_playing(true);
    for _ in 0..5 {
        h.step();
    }
    h.state_mut().set_playing(false);
    h.run();
    let after = live(&h);
    assert_ne!(before, after, "time ran");
    assert!(
        h.query_by_label(&after).is_some(),
        "the row follows: {after}"
    );
}

#[test]
fn an_output_pinned_as_a_watch_shows_its_live_value() {
    let dir = tempfile::tempdir().expect("tempdir");
    let mut p = Patch::default();
    p.add(NodeDoc::new(1, "LFO"));
    p.add(NodeDoc::new(2, "Probe").at(80.0, 0.0));
    p.link(1, "Output", 2, "Input");
    // Tall enough for the inspector to reach the LFO's outputs below its inputs.
    let mut h = harness_sized(&dir, &p, Vec2::new(800.0, 1100.0));
    h.state_mut().select(&[NodeId(1)]);
    h.run();
    // The first output's eye (an LFO has more than one output), clicked as a mouse does.
    let at = h
        .get_all_by_label("👁")
        .next()
        .expect("an eye")
        .rect()
        .center();
    h.hover_at(at);
    h.step();
    for pressed in [true, false] {
        h.event(egui::Event::PointerButton {
            pos: at,
            button: egui::PointerButton::Primary,
            pressed,
            modifiers: egui::Modifiers::NONE,
        });
    }
    h.run();
    assert_eq!(
        h.state().watches(),
        [(vec![NodeId(1)], "Output".to_owned())]
    );
    let shown = |h: &Harness<'_, EditorApp>| {
        let out = h
            .state()
            .runtime()
            .output(NodeId(1), "Output")
            .expect("evaluated");
        spreadlight_editor::canvas::preview(out)
    };
    let before = shown(&h);
    assert!(h.query_by_label(&before).is_some(), "watch shows {before}");
    // It stays in the list with nothing selected, and follows the value.
    h.state_mut().select(&[]);
    h.state_mut().set_playing(true);
    for _ in 0..5 {
        h.step();
    }
    h.state_mut().set_playing(false);
    h.run();
    let after = shown(&h);
    assert_ne!(before, after);
    assert!(h.query_by_label(&after).is_some(), "watch follows: {after}");
}
