//! The real editor, driven through egui_kittest: clicks, drags, keys and text
//! go through egui's input like a user's, on a wgpu device (lavapipe in CI).

use crate::common;

use std::path::{Path, PathBuf};

use egui::accesskit::Role;
use egui::{Event, Key, Modifiers, PointerButton, Pos2, Vec2};
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use spreadlight_editor::{EditorApp, EditorOptions};
use spreadlight_graph::{LinkDoc, NodeDoc, NodeId, Patch, Spread, format};

struct Env {
    dir: tempfile::TempDir,
}

impl Env {
    fn new() -> Self {
        Env {
            dir: tempfile::tempdir().expect("tempdir"),
        }
    }

    fn config(&self) -> PathBuf {
        self.dir.path().join("config")
    }

    fn options(&self, path: Option<PathBuf>) -> EditorOptions {
        common::options(path, self.config())
    }

    fn patch_file(&self, name: &str, patch: &Patch) -> PathBuf {
        let path = self.dir.path().join(name);
        format::save(patch, &path).expect("save");
        path
    }
}

fn harness(options: EditorOptions) -> Harness<'static, EditorApp> {
    let mut h = common::editor(options, Vec2::new(1400.0, 800.0));
    h.run_steps(2);
    h
}

fn lfo_probe() -> Patch {
    let mut p = Patch::default();
    p.add(NodeDoc::new(1, "LFO").at(20.0, 20.0));
    p.add(NodeDoc::new(2, "Probe").at(120.0, 20.0));
    p
}

/// Two clicks within egui's double-click time. The harness gives each queued
/// event its own quarter-second step, longer than that, so both clicks go
/// into the raw input of one frame.
fn double_click(h: &mut Harness<'_, EditorApp>, pos: Pos2) {
    h.hover_at(pos);
    h.step();
    for _ in 0..2 {
        for pressed in [true, false] {
            h.input_mut().events.push(Event::PointerButton {
                pos,
                button: PointerButton::Primary,
                pressed,
                modifiers: Modifiers::NONE,
            });
        }
    }
    h.step();
}

/// Where a canvas widget is on screen: its accessibility rect is in canvas
/// coordinates, before the canvas's pan and zoom.
fn on_canvas(h: &Harness<'_, EditorApp>, rect: egui::Rect) -> egui::Rect {
    let a = h.state().canvas_to_screen(&h.ctx, rect.min);
    let b = h.state().canvas_to_screen(&h.ctx, rect.max);
    egui::Rect::from_min_max(a, b)
}

/// Click a canvas label (a node's title, a pin's name) where it is on screen.
fn click_on_canvas(h: &mut Harness<'_, EditorApp>, label: &str, modifiers: Modifiers) {
    let rect = h.get_all_by_label(label).next().expect("label").rect();
    let at = on_canvas(h, rect).center();
    h.hover_at(at);
    h.step();
    for pressed in [true, false] {
        h.event_modifiers(
            Event::PointerButton {
                pos: at,
                button: PointerButton::Primary,
                pressed,
                modifiers,
            },
            modifiers,
        );
    }
    h.run();
}

fn hover_on_canvas(h: &mut Harness<'_, EditorApp>, label: &str) {
    let rect = h.get_all_by_label(label).next().expect("label").rect();
    let at = on_canvas(h, rect).center();
    h.hover_at(at);
    h.run();
}

/// Drag a wire from one pin to another the way a mouse does: press, move in steps, release.
fn drag(h: &mut Harness<'_, EditorApp>, from: Pos2, to: Pos2) {
    drag_over(h, from, to);
    h.drop_at(to);
    h.step();
    h.step();
}

/// Press at `from` and move to `to` in steps, not letting go yet.
fn drag_over(h: &mut Harness<'_, EditorApp>, from: Pos2, to: Pos2) {
    h.hover_at(from);
    h.step();
    h.drag_at(from);
    h.step();
    for k in 1..=6 {
        let t = k as f32 / 6.0;
        h.hover_at(from + (to - from) * t);
        h.step();
    }
}

fn pin(h: &Harness<'_, EditorApp>, node: u32, pin: &str, input: bool) -> Pos2 {
    h.state()
        .pin_pos(NodeId(node), pin, input)
        .unwrap_or_else(|| panic!("pin {node}.{pin} was not drawn"))
}

fn cmd(h: &Harness<'_, EditorApp>, key: Key) {
    h.key_press_modifiers(Modifiers::COMMAND, key);
}

#[test]
fn a_node_is_created_through_the_browser_and_undone_and_redone() {
    let env = Env::new();
    let mut h = harness(env.options(None));
    assert!(h.state().doc().patch().nodes.is_empty());
    let at = Pos2::new(300.0, 300.0);
    double_click(&mut h, at);
    h.run();
    h.get_by_label("LFO");
    h.event(Event::Text("lfo".into()));
    h.run();
    h.key_press(Key::Enter);
    h.run();
    let nodes = &h.state().doc().patch().nodes;
    assert_eq!(nodes.len(), 1);
    assert_eq!(nodes[0].type_name, "LFO");
    assert!(
        h.state().title().starts_with('*'),
        "unsaved mark: {}",
        h.state().title()
    );

    cmd(&h, Key::Z);
    h.run();
    assert!(h.state().doc().patch().nodes.is_empty(), "undo removes it");
    cmd(&h, Key::Y);
    h.run();
    assert_eq!(
        h.state().doc().patch().nodes.len(),
        1,
        "redo brings it back"
    );
}

#[test]
fn the_browser_closes_on_escape_and_on_a_click_elsewhere() {
    let env = Env::new();
    let mut h = harness(env.options(None));
    let at = Pos2::new(300.0, 300.0);
    double_click(&mut h, at);
    h.run();
    assert!(h.query_by_label("LFO").is_some(), "open");
    h.key_press(Key::Escape);
    h.run();
    assert!(h.query_by_label("LFO").is_none(), "Esc closes it");
    double_click(&mut h, at);
    h.run();
    assert!(h.query_by_label("LFO").is_some(), "open again");
    h.hover_at(Pos2::new(700.0, 600.0));
    h.step();
    h.drag_at(Pos2::new(700.0, 600.0));
    h.drop_at(Pos2::new(700.0, 600.0));
    h.run();
    assert!(
        h.query_by_label("LFO").is_none(),
        "a click elsewhere closes it"
    );
    assert!(
        h.state().doc().patch().nodes.is_empty(),
        "and places nothing"
    );
}

#[test]
fn the_browser_filters_by_category_and_places_with_the_arrow_keys() {
    let env = Env::new();
    let mut h = harness(env.options(None));
    let at = Pos2::new(400.0, 200.0);
    double_click(&mut h, at);
    h.run();
    h.event(Event::Text("lighting".into()));
    h.run();
    assert!(h.query_by_label("PointLightBuffer").is_some());
    assert!(
        h.query_by_label("LFO").is_none(),
        "the filter hides other categories"
    );
    h.key_press(Key::ArrowDown);
    h.run();
    h.key_press(Key::Enter);
    h.run();
    let nodes = &h.state().doc().patch().nodes;
    assert_eq!(nodes.len(), 1);
    let second = spreadlight_editor::browser::filter(h.state().registry(), "lighting")[1];
    assert_eq!(nodes[0].type_name, second);
}

#[test]
fn dragging_a_wire_links_two_nodes_and_undo_unlinks() {
    let env = Env::new();
    let path = env.patch_file("p.ron", &lfo_probe());
    let mut h = harness(env.options(Some(path)));
    let from = pin(&h, 1, "Output", false);
    let to = pin(&h, 2, "Input", true);
    drag(&mut h, from, to);
    h.run();
    assert_eq!(
        h.state().doc().patch().links,
        vec![LinkDoc::new(1, "Output", 2, "Input")]
    );
    cmd(&h, Key::Z);
    h.run();
    assert!(h.state().doc().patch().links.is_empty());
    h.key_press_modifiers(Modifiers::COMMAND | Modifiers::SHIFT, Key::Z);
    h.run();
    assert_eq!(h.state().doc().patch().links.len(), 1, "redo relinks");
}

#[test]
fn incompatible_and_cyclic_links_are_refused_where_they_are_dropped() {
    let env = Env::new();
    let mut p = Patch::default();
    p.add(NodeDoc::new(1, "Camera").at(20.0, 20.0));
    p.add(NodeDoc::new(2, "Add (Value)").at(150.0, 20.0));
    p.add(NodeDoc::new(3, "Add (Value)").at(150.0, 120.0));
    p.link(2, "Output", 3, "Input 1");
    let path = env.patch_file("p.ron", &p);
    let mut h = harness(env.options(Some(path)));

    let from = pin(&h, 1, "View", false);
    let to = pin(&h, 2, "Input 1", true);
    drag(&mut h, from, to);
    assert_eq!(h.state().doc().patch().links.len(), 1, "nothing was linked");
    let refusal = h.state().refusal().expect("a refusal message").to_owned();
    assert!(
        refusal.contains("Mat4") && refusal.contains("Float"),
        "{refusal}"
    );
    let shown = h.get_by_label_contains("Link refused");
    assert!(
        (shown.rect().min - to).length() < 60.0,
        "the message sits where the wire was dropped"
    );

    let from = pin(&h, 3, "Output", false);
    let to = pin(&h, 2, "Input 2", true);
    drag(&mut h, from, to);
    assert_eq!(h.state().doc().patch().links.len(), 1);
    assert!(h.state().refusal().expect("refused").contains("cycle"));
}

#[test]
fn a_value_is_edited_in_the_inspector_with_one_undo_step_per_drag() {
    let env = Env::new();
    let path = env.patch_file("p.ron", &lfo_probe());
    let mut h = harness(env.options(Some(path)));
    click_on_canvas(&mut h, "LFO", Modifiers::NONE);
    assert_eq!(h.state().selected(), vec![NodeId(1)]);
    assert!(h.query_by_label_contains("Inspector").is_some());
    // The inspector's editor is named after its pin (the canvas shows a second one).
    let editors = h
        .get_all_by_role_and_label(Role::SpinButton, "Period")
        .collect::<Vec<_>>();
    assert_eq!(editors.len(), 2, "one on the node, one in the inspector");
    // The inspector sits right of the canvas and is not zoomed with it.
    let target = editors
        .iter()
        .map(|e| e.rect())
        .max_by(|a, b| a.left().total_cmp(&b.left()))
        .expect("inspector editor")
        .center();
    drop(editors);
    drag(&mut h, target, target + Vec2::new(60.0, 0.0));
    h.run();
    let period = |h: &Harness<'_, EditorApp>| {
        h.state()
            .doc()
            .patch()
            .node(NodeId(1))
            .and_then(|n| n.values.get("Period").cloned())
    };
    let Some(Spread::Float(v)) = period(&h) else {
        panic!("Period was not set: {:?}", period(&h));
    };
    assert!(
        v[0] > 1.0,
        "dragging right increased the default 1.0: {v:?}"
    );
    cmd(&h, Key::Z);
    h.run();
    assert_eq!(period(&h), None, "one undo takes back the whole drag");
    cmd(&h, Key::Y);
    h.run();
    assert_eq!(period(&h), Some(Spread::Float(v)));
}

#[test]
fn an_enum_is_picked_from_its_drop_down() {
    let env = Env::new();
    let mut p = Patch::default();
    p.add(NodeDoc::new(1, "Map (Value)").at(20.0, 20.0));
    let path = env.patch_file("p.ron", &p);
    let mut h = harness(env.options(Some(path)));
    click_on_canvas(&mut h, "Map (Value)", Modifiers::NONE);
    let def = h
        .state()
        .registry()
        .get("Map (Value)")
        .expect("def")
        .clone();
    let pin = def
        .inputs
        .iter()
        .find(|p| matches!(p.ty, spreadlight_graph::PinType::Enum(_)))
        .expect("an enum pin");
    let spreadlight_graph::PinType::Enum(options) = pin.ty else {
        unreachable!()
    };
    let other = options.options[1];
    // The inspector's drop-down, right of the canvas (whose widgets are zoomed).
    let inspector_combo = h
        .get_all_by_role_and_label(Role::ComboBox, &pin.name)
        .map(|n| n.rect())
        .max_by(|a, b| a.left().total_cmp(&b.left()))
        .expect("inspector combo");
    h.hover_at(inspector_combo.center());
    h.step();
    h.drag_at(inspector_combo.center());
    h.step();
    h.event(Event::PointerButton {
        pos: inspector_combo.center(),
        button: PointerButton::Primary,
        pressed: false,
        modifiers: Modifiers::NONE,
    });
    h.run();
    h.get_all_by_label(other).last().expect("option").click();
    h.run();
    assert_eq!(
        h.state()
            .doc()
            .patch()
            .node(NodeId(1))
            .and_then(|n| n.values.get(&*pin.name)),
        Some(&Spread::Enum(vec![other.to_owned()]))
    );
}

#[test]
fn spreads_get_slices_added_and_removed_in_the_inspector() {
    let env = Env::new();
    let path = env.patch_file("p.ron", &lfo_probe());
    let mut h = harness(env.options(Some(path)));
    click_on_canvas(&mut h, "LFO", Modifiers::NONE);
    h.get_all_by_label("+ slice")
        .next()
        .expect("add slice")
        .click();
    h.run();
    let period = |h: &Harness<'_, EditorApp>| {
        h.state()
            .doc()
            .patch()
            .node(NodeId(1))
            .and_then(|n| n.values.get("Period").cloned())
    };
    assert_eq!(period(&h), Some(Spread::Float(vec![1.0, 1.0])));
    h.get_all_by_label("−")
        .next()
        .expect("remove slice")
        .click();
    h.run();
    assert_eq!(period(&h), Some(Spread::Float(vec![1.0])));
    cmd(&h, Key::Z);
    h.run();
    assert_eq!(period(&h), Some(Spread::Float(vec![1.0, 1.0])));
}

#[test]
fn hovering_a_pin_shows_its_slices() {
    let env = Env::new();
    let mut p = Patch::default();
    p.add(NodeDoc::new(1, "LinearSpread").with("Spread Count", vec![5i64]));
    p.add(NodeDoc::new(2, "Probe").at(150.0, 0.0));
    p.link(1, "Output", 2, "Input");
    let path = env.patch_file("p.ron", &p);
    let mut h = harness(env.options(Some(path)));
    hover_on_canvas(&mut h, "Output");
    // The first four slices, then the count.
    assert!(h.query_by_label_contains(", ...] (5 slices)").is_some());

    // The wire shows the same, hovered halfway along.
    let a = pin(&h, 1, "Output", false);
    let b = pin(&h, 2, "Input", true);
    h.hover_at(a + (b - a) * 0.5);
    h.run();
    let tip = h.get_by_label_contains("→");
    let text = format!("{tip:?}");
    assert!(text.contains("(5 slices)"), "{text}");
}

#[test]
fn a_failing_node_is_red_with_its_message_and_the_rest_runs() {
    let env = Env::new();
    let mut p = lfo_probe();
    p.nodes[0]
        .values
        .insert("Nope".into(), Spread::Float(vec![1.0]));
    p.add(NodeDoc::new(3, "LFO").at(20.0, 120.0));
    p.add(NodeDoc::new(4, "Probe").at(120.0, 120.0));
    p.link(3, "Output", 4, "Input");
    let path = env.patch_file("p.ron", &p);
    let mut h = harness(env.options(Some(path)));
    // Node 1 is the upper LFO.
    let top = h
        .get_all_by_label("LFO")
        .map(|n| n.rect())
        .min_by(|a, b| a.top().total_cmp(&b.top()))
        .expect("the first LFO");
    h.hover_at(on_canvas(&h, top).center());
    h.run();
    assert!(
        h.query_by_label_contains("Nope").is_some(),
        "the error shows on hover"
    );
    // The header is red: sample it beside the title.
    let image = h.render().expect("render");
    let title = on_canvas(&h, top);
    let ppp = h.ctx.pixels_per_point();
    let px = image.get_pixel(
        // Just left of the title, inside the header's margin (nodes are compact: no collapse button).
        ((title.left() - 3.0) * ppp) as u32,
        (title.center().y * ppp) as u32,
    );
    assert!(px[0] > 100 && px[1] < 60, "red header, got {px:?}");
    let stats = h.state().runtime().stats();
    assert!(
        stats
            .node(NodeId(3))
            .is_some_and(|s| s.run == spreadlight_graph::NodeRun::Evaluated)
    );
}

#[test]
fn copy_paste_duplicate_and_delete_keep_inner_links() {
    let env = Env::new();
    let mut p = lfo_probe();
    p.link(1, "Output", 2, "Input");
    let path = env.patch_file("p.ron", &p);
    let mut h = harness(env.options(Some(path)));
    click_on_canvas(&mut h, "LFO", Modifiers::NONE);
    click_on_canvas(&mut h, "Probe", Modifiers::SHIFT);
    assert_eq!(h.state().selected(), vec![NodeId(1), NodeId(2)]);
    cmd(&h, Key::D);
    h.run();
    assert_eq!(h.state().doc().patch().nodes.len(), 4);
    assert_eq!(
        h.state().doc().patch().links.len(),
        2,
        "the duplicate has its inner link"
    );
    cmd(&h, Key::C);
    h.run();
    cmd(&h, Key::V);
    h.run();
    assert_eq!(h.state().doc().patch().nodes.len(), 6);
    assert_eq!(h.state().doc().patch().links.len(), 3);
    h.key_press(Key::Delete);
    h.run();
    assert_eq!(
        h.state().doc().patch().nodes.len(),
        4,
        "Del removes the pasted selection"
    );
    assert_eq!(h.state().doc().patch().links.len(), 2);
    cmd(&h, Key::Z);
    h.run();
    assert_eq!(h.state().doc().patch().nodes.len(), 6);
}

#[test]
fn moving_a_node_is_one_undoable_step() {
    let env = Env::new();
    let path = env.patch_file("p.ron", &lfo_probe());
    let mut h = harness(env.options(Some(path)));
    // A drag on the title moves the node (a click there would select it).
    let grab = on_canvas(&h, h.get_by_label("LFO").rect()).center();
    drag(&mut h, grab, grab + Vec2::new(90.0, 60.0));
    h.run();
    let pos = h.state().doc().patch().node(NodeId(1)).expect("node").pos;
    assert!(pos.0 > 20.0 && pos.1 > 20.0, "moved: {pos:?}");
    assert_eq!(h.state().doc().undo_label(), Some("move node"));
    cmd(&h, Key::Z);
    h.run();
    assert_eq!(
        h.state().doc().patch().node(NodeId(1)).expect("node").pos,
        (20.0, 20.0)
    );
}

#[test]
fn save_and_reload_give_back_the_same_patch() {
    let env = Env::new();
    let path = env.patch_file("p.ron", &lfo_probe());
    let mut h = harness(env.options(Some(path.clone())));
    let from = pin(&h, 1, "Output", false);
    let to = pin(&h, 2, "Input", true);
    drag(&mut h, from, to);
    h.run();
    assert!(h.state().title().starts_with("*p.ron"));
    cmd(&h, Key::S);
    h.run();
    assert!(
        h.state().title().starts_with("p.ron"),
        "saved: {}",
        h.state().title()
    );
    let edited = h.state().doc().patch().clone();
    assert_eq!(format::load(&path).expect("reload"), edited);

    let h2 = harness(env.options(Some(path.clone())));
    assert_eq!(h2.state().doc().patch(), &edited, "reopened unchanged");
    assert!(!h2.state().doc().is_dirty());
    assert!(
        !h2.state().recovery_offered(),
        "a saved patch leaves no autosave behind"
    );
}

#[test]
fn save_as_goes_through_the_file_dialog_and_is_remembered() {
    let env = Env::new();
    let mut h = harness(env.options(None));
    h.state_mut().doc_mut().add_node("LFO", (0.0, 0.0));
    h.run();
    h.key_press_modifiers(Modifiers::COMMAND | Modifiers::SHIFT, Key::S);
    h.run();
    // The dialog opens in the patch's folder (here the working directory, as
    // the patch is untitled) with the name field focused: type a whole path.
    let target = env.dir.path().join("scene.ron");
    h.key_press_modifiers(Modifiers::COMMAND, Key::A);
    h.event(Event::Text(target.display().to_string()));
    h.run();
    h.get_by_label("Save").click();
    h.run();
    assert_eq!(h.state().path(), Some(target.as_path()));
    assert_eq!(format::load(&target).expect("saved").nodes.len(), 1);
    let recent = spreadlight_editor::files::load_recent(&env.config());
    assert_eq!(
        recent.first().and_then(|p| p.file_name()),
        target.file_name()
    );
}

fn recovery_of(path: &Path) -> PathBuf {
    spreadlight_editor::files::recovery_path(Some(path), Path::new("unused"))
}

#[test]
fn an_autosave_is_offered_after_a_crash_and_restores_the_edits() {
    let env = Env::new();
    let path = env.patch_file("p.ron", &lfo_probe());
    // Make the patch file older than any autosave, as it is when edits follow a save.
    let old = std::time::SystemTime::now() - std::time::Duration::from_secs(60);
    std::fs::File::options()
        .write(true)
        .open(&path)
        .and_then(|f| f.set_modified(old))
        .expect("touch");
    let edited = {
        let mut h = harness(env.options(Some(path.clone())));
        let from = pin(&h, 1, "Output", false);
        let to = pin(&h, 2, "Input", true);
        drag(&mut h, from, to);
        h.run();
        assert!(recovery_of(&path).exists(), "autosaved while dirty");
        h.state().doc().patch().clone()
        // The harness is dropped without saving: a crash, as far as the files know.
    };
    let mut h = harness(env.options(Some(path.clone())));
    assert!(h.state().recovery_offered());
    assert_eq!(
        h.state().doc().patch(),
        &lfo_probe(),
        "nothing restored before the answer"
    );
    h.get_by_label("Restore").click();
    h.run();
    assert_eq!(h.state().doc().patch(), &edited);
    assert!(
        h.state().doc().is_dirty(),
        "restored edits are unsaved until saved"
    );
    cmd(&h, Key::S);
    h.run();
    assert!(!recovery_of(&path).exists(), "saving removes the autosave");
}

#[test]
fn quitting_with_unsaved_changes_asks_first() {
    let env = Env::new();
    let path = env.patch_file("p.ron", &lfo_probe());
    let mut h = harness(env.options(Some(path)));
    h.state_mut().doc_mut().add_node("LFO", (0.0, 0.0));
    h.run();
    h.input_mut()
        .viewports
        .entry(egui::ViewportId::ROOT)
        .or_default()
        .events
        .push(egui::ViewportEvent::Close);
    h.run();
    assert!(h.query_by_label("Unsaved changes").is_some());
    h.get_by_label("Cancel").click();
    h.run();
    assert!(h.query_by_label("Unsaved changes").is_none());
    assert_eq!(
        h.state().doc().patch().nodes.len(),
        3,
        "cancel keeps editing"
    );
}

#[test]
fn paused_patches_evaluate_only_on_change_or_step() {
    let env = Env::new();
    let path = env.patch_file("p.ron", &lfo_probe());
    let mut h = harness(env.options(Some(path)));
    let before = h.state().evaluations();
    h.run_steps(5);
    assert_eq!(
        h.state().evaluations(),
        before,
        "nothing changed, nothing ran"
    );
    let frame = h.state().frame();
    h.get_by_label("⏭ Step").click();
    h.run();
    assert_eq!(h.state().frame(), frame + 1);
    assert_eq!(h.state().evaluations(), before + 1);
    h.state_mut()
        .doc_mut()
        .set_value(NodeId(1), "Period", Some(Spread::Float(vec![2.0])), false);
    h.run();
    assert_eq!(h.state().evaluations(), before + 2, "an edit re-evaluates");
    h.get_by_label("▶ Play").click();
    h.run_steps(5);
    assert!(
        h.state().evaluations() >= before + 5,
        "time runs while playing"
    );
}

#[test]
fn links_are_removed_from_the_inspector_and_by_right_clicking_a_pin_or_wire() {
    let env = Env::new();
    let mut p = lfo_probe();
    p.link(1, "Output", 2, "Input");
    let path = env.patch_file("p.ron", &p);
    let mut h = harness(env.options(Some(path)));
    click_on_canvas(&mut h, "Probe", Modifiers::NONE);
    h.get_by_label("unlink").click();
    h.run();
    assert!(
        h.state().doc().patch().links.is_empty(),
        "unlinked in the inspector"
    );
    cmd(&h, Key::Z);
    h.run();
    assert_eq!(h.state().doc().patch().links.len(), 1, "undo relinks");

    let input = pin(&h, 2, "Input", true);
    h.hover_at(input);
    h.step();
    for pressed in [true, false] {
        h.event(Event::PointerButton {
            pos: input,
            button: PointerButton::Secondary,
            pressed,
            modifiers: Modifiers::NONE,
        });
    }
    h.run();
    assert!(
        h.state().doc().patch().links.is_empty(),
        "right-click on the pin unlinks"
    );
    cmd(&h, Key::Z);
    h.run();
    assert_eq!(h.state().doc().patch().links.len(), 1);

    let a = pin(&h, 1, "Output", false);
    let b = pin(&h, 2, "Input", true);
    let middle = a + (b - a) * 0.5;
    h.hover_at(middle);
    h.run();
    for pressed in [true, false] {
        h.event(Event::PointerButton {
            pos: middle,
            button: PointerButton::Secondary,
            pressed,
            modifiers: Modifiers::NONE,
        });
    }
    h.run();
    assert!(
        h.state().doc().patch().links.is_empty(),
        "right-click on the wire unlinks"
    );
    cmd(&h, Key::Z);
    h.run();
    assert_eq!(h.state().doc().patch().links.len(), 1);
}

#[test]
fn patches_open_through_the_dialog_and_the_recent_list() {
    let env = Env::new();
    let first = env.patch_file("first.ron", &lfo_probe());
    let mut other = lfo_probe();
    other.add(NodeDoc::new(3, "LFO").at(50.0, 100.0));
    let second = env.patch_file("second.ron", &other);
    let mut h = harness(env.options(Some(first.clone())));

    cmd(&h, Key::O);
    h.run();
    // The dialog opens in the patch's folder; entries are "icon name".
    // `SPREADLIGHT_DOC_PICTURES=1` keeps a picture of it for docs/editor.md.
    if std::env::var_os("SPREADLIGHT_DOC_PICTURES").is_some() {
        let image = h.render().expect("render");
        let docs = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../docs");
        image
            .save(docs.join("editor-file-dialog.png"))
            .expect("write the picture");
    }
    h.get_by_label_contains("second.ron").click();
    h.run();
    h.get_by_label("Open").click();
    h.run();
    let canonical = |p: &Path| std::fs::canonicalize(p).expect("canonical");
    assert_eq!(h.state().path().map(canonical), Some(canonical(&second)));
    assert_eq!(h.state().doc().patch(), &other);
    assert!(h.state().title().starts_with("second.ron"));

    h.get_by_label("File").click();
    h.run();
    h.get_by_label_contains("Open recent").hover();
    h.run();
    let listed = std::fs::canonicalize(&first).expect("canonical");
    h.get_by_label(&listed.display().to_string()).click();
    h.run();
    assert_eq!(h.state().doc().patch(), &lfo_probe());
}

#[test]
fn shift_dragging_a_rectangle_selects_the_nodes_it_touches() {
    let env = Env::new();
    let mut p = lfo_probe();
    p.add(NodeDoc::new(3, "LFO").at(20.0, 200.0));
    let path = env.patch_file("p.ron", &p);
    let mut h = harness(env.options(Some(path)));
    let lfo = on_canvas(&h, h.get_all_by_label("LFO").next().expect("LFO").rect());
    let probe = on_canvas(&h, h.get_by_label("Probe").rect());
    // From above and left of the first LFO to the Probe's title: the two upper nodes, not node 3.
    let from = lfo.left_top() - Vec2::new(30.0, 30.0);
    let to = probe.center();
    h.hover_at(from);
    h.step();
    h.event_modifiers(
        Event::PointerButton {
            pos: from,
            button: PointerButton::Primary,
            pressed: true,
            modifiers: Modifiers::SHIFT,
        },
        Modifiers::SHIFT,
    );
    h.step();
    for k in 1..=5 {
        h.event_modifiers(
            Event::PointerMoved(from + (to - from) * (k as f32 / 5.0)),
            Modifiers::SHIFT,
        );
        h.step();
    }
    h.event_modifiers(
        Event::PointerButton {
            pos: to,
            button: PointerButton::Primary,
            pressed: false,
            modifiers: Modifiers::SHIFT,
        },
        Modifiers::SHIFT,
    );
    h.run();
    assert_eq!(h.state().selected(), vec![NodeId(1), NodeId(2)]);
    assert_eq!(
        h.state().doc().undo_label(),
        None,
        "selecting moved nothing"
    );
}

#[test]
fn nodes_travel_between_windows_as_patch_text_on_the_clipboard() {
    let env = Env::new();
    let mut p = lfo_probe();
    p.link(1, "Output", 2, "Input");
    let path = env.patch_file("p.ron", &p);
    let mut source = harness(env.options(Some(path)));
    click_on_canvas(&mut source, "LFO", Modifiers::NONE);
    click_on_canvas(&mut source, "Probe", Modifiers::SHIFT);
    // A real window turns Ctrl+C into egui's Copy event; one event, one frame, whose output has the text.
    source.event(Event::Copy);
    source.step();
    let text = source
        .output()
        .platform_output
        .commands
        .iter()
        .find_map(|c| match c {
            egui::OutputCommand::CopyText(text) => Some(text.clone()),
            _ => None,
        })
        .expect("the selection went to the system clipboard");
    assert!(
        text.contains("\"LFO\"") && text.contains("\"Probe\""),
        "{text}"
    );

    let mut target = harness(env.options(None));
    target.event(Event::Paste(text));
    target.run();
    let pasted = target.state().doc().patch();
    assert_eq!(pasted.nodes.len(), 2);
    assert_eq!(pasted.links.len(), 1, "with the link between them");
    assert_eq!(pasted.nodes[0].type_name, "LFO");
}

#[test]
fn editing_a_file_that_does_not_exist_yet_saves_it_there() {
    let env = Env::new();
    let path = env.dir.path().join("new.ron");
    let mut h = harness(env.options(Some(path.clone())));
    assert!(h.state().doc().patch().nodes.is_empty());
    assert!(
        h.state().title().starts_with("new.ron"),
        "{}",
        h.state().title()
    );
    h.state_mut().doc_mut().add_node("LFO", (0.0, 0.0));
    h.run();
    cmd(&h, Key::S);
    h.run();
    assert_eq!(format::load(&path).expect("saved").nodes.len(), 1);
}

#[test]
fn a_file_pin_is_set_with_the_file_picker() {
    let env = Env::new();
    std::fs::write(env.dir.path().join("bricks.png"), b"not read by this test").expect("write");
    let mut p = Patch::default();
    p.add(NodeDoc::new(1, "FileTexture").at(20.0, 20.0));
    let path = env.patch_file("p.ron", &p);
    let mut h = harness(env.options(Some(path)));
    click_on_canvas(&mut h, "FileTexture", Modifiers::NONE);
    std::fs::write(env.dir.path().join("notes.txt"), b"not an image").expect("write");
    h.get_by_label("Browse…").click();
    h.run();
    // Filtered to what the node reads: the text file is not listed.
    assert!(h.query_by_label_contains("notes.txt").is_none());
    h.get_by_label_contains("bricks.png").click();
    h.run();
    h.get_by_label("Choose").click();
    h.run();
    let picked = std::fs::canonicalize(env.dir.path().join("bricks.png"))
        .expect("canonical")
        .display()
        .to_string();
    assert_eq!(
        h.state()
            .doc()
            .node(NodeId(1))
            .and_then(|n| n.values.get("Filename")),
        Some(&Spread::String(vec![picked]))
    );
    assert_eq!(h.state().doc().undo_label(), Some("set #1.Filename"));
}

const TINT: &str = "// @input source \"Texture\"
// @target tinted temporary rgba16float scale=1
// @pass tint -> tinted
struct Params {
    gain: f32, // @pin default=1 min=0 max=4
    size: vec2<f32>,
}
@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var source: texture_2d<f32>;
@group(0) @binding(2) var tinted: texture_storage_2d<rgba16float, write>;
@compute @workgroup_size(8, 8)
fn tint(@builtin(global_invocation_id) id: vec3<u32>) {
    if (f32(id.x) >= params.size.x || f32(id.y) >= params.size.y) { return; }
    textureStore(tinted, id.xy, textureLoad(source, id.xy, 0) * params.gain);
}
";

/// Steps that let the editor's shader poll (every quarter second) come round.
fn wait_for_poll(h: &mut Harness<'_, EditorApp>) {
    for _ in 0..4 {
        std::thread::sleep(std::time::Duration::from_millis(100));
        h.run_steps(8);
    }
}

#[test]
fn a_saved_shader_file_updates_its_node_keeping_links_and_values() {
    saved_shader_files_reload(false);
}

/// `spreadlight play` runs the show window alone (the editor's app in show
/// mode, no menus or status bar): it reloads a saved shader as the editor does.
#[test]
fn play_reloads_a_saved_shader_file_as_the_editor_does() {
    saved_shader_files_reload(true);
}

/// A shader file saved three times (a new pin, then broken) while the patch
/// runs, in the editor or in the show window (`show`).
fn saved_shader_files_reload(show: bool) {
    let env = Env::new();
    let shaders = env.dir.path().join("shaders");
    std::fs::create_dir_all(&shaders).expect("mkdir");
    std::fs::write(shaders.join("tint.wgsl"), TINT).expect("write");
    let mut p = Patch::default();
    p.add(NodeDoc::new(1, "Noise (Shader)").at(20.0, 20.0));
    p.add(
        NodeDoc::new(2, "Tint (Shader)")
            .at(20.0, 160.0)
            .with("Gain", vec![0.5f32]),
    );
    p.add(NodeDoc::new(3, "Output").at(20.0, 300.0));
    p.link(1, "Texture", 2, "Texture");
    p.link(2, "Texture", 3, "Texture");
    let path = env.patch_file("shaded.ron", &p);
    // Polling keeps the editor awake: step it rather than `run` it.
    let mut h = if show {
        let mut h = common::editor_with(
            env.options(Some(path)),
            Vec2::new(640.0, 360.0),
            40,
            |app| app.set_show_mode(true),
        );
        h.run_steps(2);
        h
    } else {
        harness(env.options(Some(path)))
    };
    wait_for_poll(&mut h);
    let pins = |h: &Harness<'_, EditorApp>| -> Vec<String> {
        let def = h
            .state()
            .registry()
            .get("Tint (Shader)")
            .expect("registered");
        def.inputs.iter().map(|p| p.name.to_string()).collect()
    };
    assert_eq!(pins(&h), ["Texture", "Gain"]);
    assert!(h.state().runtime().node_error(NodeId(2)).is_none());

    // Saved with a new pin: the node has it, keeps its link and its value.
    let v2 = TINT
        .replace(
            "    size: vec2<f32>,",
            "    offset: f32, // @pin default=0.25\n    size: vec2<f32>,",
        )
        .replace("* params.gain);", "* params.gain + params.offset);");
    std::fs::write(shaders.join("tint.wgsl"), &v2).expect("write");
    wait_for_poll(&mut h);
    assert_eq!(
        pins(&h),
        ["Texture", "Gain", "Offset"],
        "{}",
        h.state().status()
    );
    let doc = h.state().doc().patch();
    assert_eq!(doc.links.len(), 2);
    assert_eq!(
        doc.node(NodeId(2)).and_then(|n| n.values.get("Gain")),
        Some(&Spread::Float(vec![0.5]))
    );
    assert!(h.state().runtime().node_error(NodeId(2)).is_none());

    // Saved broken: the error names the place, on the node and in the status bar.
    std::fs::write(
        shaders.join("tint.wgsl"),
        v2.replace("let", "lett")
            .replace("textureStore(tinted", "textureStore(nowhere"),
    )
    .expect("write");
    wait_for_poll(&mut h);
    let error = h
        .state()
        .runtime()
        .node_error(NodeId(2))
        .map(|e| e.to_string())
        .unwrap_or_default();
    assert!(error.contains("tint.wgsl:15:"), "{error}");
    assert!(
        h.state().status().contains("tint.wgsl:15:"),
        "{}",
        h.state().status()
    );
    assert_eq!(
        pins(&h),
        ["Texture", "Gain", "Offset"],
        "the last good version stays"
    );
}

/// F1 on a node opens its family's help patch (the table in
/// `spreadlight_nodes::help`, as `spreadlight nodes --help` names it): the
/// node under the pointer first, else the selected one.
#[test]
fn f1_opens_the_help_patch_of_the_node_under_the_pointer_or_selected() {
    let env = Env::new();
    let mut p = Patch::default();
    p.add(NodeDoc::new(1, "LFO").at(20.0, 20.0));
    p.add(NodeDoc::new(2, "LinearSpread").at(160.0, 20.0));
    let path = env.patch_file("help.ron", &p);
    let mut h = common::editor_with(
        env.options(Some(path)),
        Vec2::new(1400.0, 800.0),
        40,
        |app| app.set_help_launch(spreadlight_editor::HelpLaunch::Record),
    );
    h.run_steps(2);
    hover_on_canvas(&mut h, "LFO");
    h.key_press(Key::F1);
    h.run();
    let opened = h.state().help_opened().to_vec();
    assert_eq!(opened.len(), 1, "{}", h.state().status());
    assert!(opened[0].ends_with("patches/help/values.ron"), "{opened:?}");
    let help = format::load(&opened[0]).expect("the help patch loads");
    assert!(help.nodes.iter().any(|n| n.type_name == "LFO"));
    assert!(
        h.state().status().contains("help for LFO"),
        "{}",
        h.state().status()
    );
    // Away from every node, F1 takes the selected one.
    h.state_mut().select(&[NodeId(2)]);
    let canvas = h.state().canvas_rect().expect("canvas");
    h.hover_at(canvas.max - Vec2::new(20.0, 20.0));
    h.run();
    h.key_press(Key::F1);
    h.run();
    let opened = h.state().help_opened().to_vec();
    assert_eq!(opened.len(), 2);
    assert!(
        opened[1].ends_with("patches/help/spreads.ron"),
        "{opened:?}"
    );
}

/// A help patch opens read-only: an edit is undone at once, and the banner
/// and the title say so.
#[test]
fn a_read_only_help_patch_undoes_every_edit_and_says_so() {
    let env = Env::new();
    let path = env.patch_file("values.ron", &lfo_probe());
    let before = std::fs::read(&path).expect("written");
    let mut options = env.options(Some(path.clone()));
    options.read_only = true;
    let mut h = harness(options);
    assert!(
        h.state().title().contains("read-only"),
        "{}",
        h.state().title()
    );
    let _ = h.get_by_label(spreadlight_editor::app::READ_ONLY_BANNER);
    h.state_mut().select(&[NodeId(1)]);
    h.key_press(Key::Delete);
    h.run();
    assert_eq!(
        h.state().doc().patch().nodes.len(),
        2,
        "the delete was undone"
    );
    assert_eq!(h.state().refused_edits(), 1);
    assert!(!h.state().doc().is_dirty());
    assert!(
        h.state().status().contains("read-only"),
        "{}",
        h.state().status()
    );
    assert_eq!(
        std::fs::read(&path).expect("readable"),
        before,
        "the file is untouched"
    );
}

// ----- organising: gestures, find, bypass, layout, frames (docs/editor.md) -----

fn middle_click(h: &mut Harness<'_, EditorApp>, pos: Pos2) {
    h.hover_at(pos);
    h.step();
    for pressed in [true, false] {
        h.event(Event::PointerButton {
            pos,
            button: PointerButton::Middle,
            pressed,
            modifiers: Modifiers::NONE,
        });
    }
    h.run();
}

/// A primary click with Ctrl (Cmd on a Mac) held.
fn ctrl_click(h: &mut Harness<'_, EditorApp>, pos: Pos2) {
    h.hover_at(pos);
    h.step();
    for pressed in [true, false] {
        h.event_modifiers(
            Event::PointerButton {
                pos,
                button: PointerButton::Primary,
                pressed,
                modifiers: Modifiers::COMMAND,
            },
            Modifiers::COMMAND,
        );
    }
    h.run();
}

fn links_of(h: &Harness<'_, EditorApp>) -> Vec<LinkDoc> {
    h.state().doc().patch().links.clone()
}

#[test]
fn a_wire_dropped_on_empty_canvas_opens_the_browser_and_links_the_new_node() {
    let env = Env::new();
    let path = env.patch_file("p.ron", &lfo_probe());
    let mut h = harness(env.options(Some(path)));
    let from = pin(&h, 1, "Output", false);
    drag(&mut h, from, from + Vec2::new(40.0, 220.0));
    h.run();
    // The browser lists only types that take a Float: a Probe does, a texture-only node does not.
    h.event(Event::Text("sin (value".into()));
    h.run();
    h.get_by_label("Sin (Value)");
    h.key_press(Key::Enter);
    h.run();
    let patch = h.state().doc().patch().clone();
    assert_eq!(patch.nodes.len(), 3, "{:?}", patch.nodes);
    let new = patch.nodes[2].id;
    assert_eq!(patch.nodes[2].type_name, "Sin (Value)");
    assert_eq!(patch.links, vec![LinkDoc::new(1, "Output", new.0, "Input")]);
    cmd(&h, Key::Z);
    h.run();
    assert_eq!(h.state().doc().patch().nodes.len(), 2, "one undo step");
    assert!(links_of(&h).is_empty());
}

#[test]
fn double_clicking_a_link_inserts_a_node_keeping_both_sides_linked() {
    let env = Env::new();
    let mut p = lfo_probe();
    p.nodes[1].pos = (260.0, 20.0);
    p.link(1, "Output", 2, "Input");
    let path = env.patch_file("p.ron", &p);
    let mut h = harness(env.options(Some(path)));
    let a = pin(&h, 1, "Output", false);
    let b = pin(&h, 2, "Input", true);
    double_click(&mut h, a + (b - a) * 0.5);
    h.run();
    h.event(Event::Text("sin (value".into()));
    h.run();
    h.key_press(Key::Enter);
    h.run();
    let patch = h.state().doc().patch().clone();
    assert_eq!(patch.nodes.len(), 3);
    let new = patch.nodes[2].id.0;
    assert_eq!(
        patch.links,
        vec![
            LinkDoc::new(1, "Output", new, "Input"),
            LinkDoc::new(new, "Output", 2, "Input"),
        ]
    );
    cmd(&h, Key::Z);
    h.run();
    assert_eq!(links_of(&h), vec![LinkDoc::new(1, "Output", 2, "Input")]);
}

#[test]
fn alt_dropping_a_node_onto_a_link_inserts_it_keeping_both_sides_linked() {
    let env = Env::new();
    let mut p = lfo_probe();
    p.nodes[1].pos = (260.0, 20.0);
    p.link(1, "Output", 2, "Input");
    p.add(NodeDoc::new(3, "Sin (Value)").at(120.0, 90.0));
    let before = p.clone();
    let path = env.patch_file("p.ron", &p);
    let mut h = harness(env.options(Some(path)));
    let a = pin(&h, 1, "Output", false);
    let b = pin(&h, 2, "Input", true);
    let onto = a + (b - a) * 0.5;
    let title = h
        .get_all_by_label("Sin (Value)")
        .next()
        .expect("title")
        .rect();
    let from = on_canvas(&h, title).center();
    // Drag the Sin by its title; Alt is held when it is let go over the link.
    drag_over(&mut h, from, onto);
    h.event(Event::ModifiersChanged(Modifiers::ALT));
    h.step();
    h.drop_at(onto);
    h.step();
    h.step();
    h.event(Event::ModifiersChanged(Modifiers::NONE));
    h.run();
    assert_eq!(
        links_of(&h),
        vec![
            LinkDoc::new(1, "Output", 3, "Input"),
            LinkDoc::new(3, "Output", 2, "Input"),
        ],
        "the Sin is in the link, linked on both sides; the old link is gone"
    );
    assert_ne!(
        h.state().doc().node(NodeId(3)).expect("node").pos,
        (120.0, 90.0),
        "moved where it was let go"
    );
    cmd(&h, Key::Z);
    h.run();
    assert_eq!(
        h.state().doc().patch(),
        &before,
        "the move and the insert are one undo step"
    );

    // Let go without Alt: the node only moves.
    drag_over(&mut h, from, onto);
    h.drop_at(onto);
    h.step();
    h.run();
    assert_eq!(links_of(&h), vec![LinkDoc::new(1, "Output", 2, "Input")]);
    assert_ne!(
        h.state().doc().node(NodeId(3)).expect("node").pos,
        (120.0, 90.0)
    );
}

#[test]
fn middle_clicking_an_input_pin_makes_a_linked_iobox_holding_its_spread() {
    let env = Env::new();
    let mut p = lfo_probe();
    p.nodes[0].pos = (200.0, 20.0);
    p.nodes[0]
        .values
        .insert("Period".into(), Spread::Float(vec![2.5, 3.0]));
    let path = env.patch_file("p.ron", &p);
    let mut h = harness(env.options(Some(path)));
    let at = pin(&h, 1, "Period", true);
    middle_click(&mut h, at);
    let patch = h.state().doc().patch().clone();
    let iobox = patch
        .nodes
        .iter()
        .find(|n| n.type_name == "IOBox (Value)")
        .expect("an IOBox");
    assert_eq!(
        iobox.values.get("Input"),
        Some(&Spread::Float(vec![2.5, 3.0]))
    );
    assert_eq!(
        patch.links,
        vec![LinkDoc::new(iobox.id.0, "Output", 1, "Period")]
    );
    assert_eq!(h.state().selected(), vec![iobox.id]);
    cmd(&h, Key::Z);
    h.run();
    assert_eq!(h.state().doc().patch(), &p, "one undo step");

    // Ctrl-click does the same; on a linked pin the IOBox holds what flows in now.
    // (The LFO feeds the Probe, a sink, so what flows into it is evaluated.)
    let registry = h.state().registry().clone();
    h.state_mut()
        .doc_mut()
        .link(
            &registry,
            spreadlight_graph::PinRef(NodeId(1), "Output".into()),
            spreadlight_graph::PinRef(NodeId(2), "Input".into()),
        )
        .expect("link");
    h.run();
    let at = pin(&h, 1, "Period", true);
    ctrl_click(&mut h, at);
    let patch = h.state().doc().patch().clone();
    let iobox = patch
        .nodes
        .iter()
        .find(|n| n.type_name == "IOBox (Value)")
        .expect("an IOBox from Ctrl-click");
    assert_eq!(
        iobox.values.get("Input"),
        Some(&Spread::Float(vec![2.5, 3.0]))
    );
    assert!(
        patch
            .links
            .contains(&LinkDoc::new(iobox.id.0, "Output", 1, "Period"))
    );
    // Its value is now what flows into the LFO's Period: Ctrl-click there again
    // with the IOBox's value changed makes a second IOBox holding the new spread.
    let first = iobox.id;
    h.state_mut().doc_mut().set_value(
        first,
        "Input",
        Some(Spread::Float(vec![7.0, 8.0, 9.0])),
        false,
    );
    h.run();
    let at = pin(&h, 1, "Period", true);
    ctrl_click(&mut h, at);
    let patch = h.state().doc().patch().clone();
    let second = patch
        .nodes
        .iter()
        .find(|n| n.type_name == "IOBox (Value)" && n.id != first)
        .expect("a second IOBox");
    assert_eq!(
        second.values.get("Input"),
        Some(&Spread::Float(vec![7.0, 8.0, 9.0])),
        "the linked pin's live spread"
    );
    assert!(
        patch
            .links
            .contains(&LinkDoc::new(second.id.0, "Output", 1, "Period"))
            && !patch
                .links
                .contains(&LinkDoc::new(first.0, "Output", 1, "Period")),
        "linked in place of the first: {:?}",
        patch.links
    );
}

#[test]
fn find_selects_the_match_and_bypass_shows_on_the_node() {
    let env = Env::new();
    let mut p = lfo_probe();
    p.nodes[1]
        .values
        .insert("Name".into(), Spread::String(vec!["wobble".into()]));
    let path = env.patch_file("p.ron", &p);
    let mut h = harness(env.options(Some(path)));
    cmd(&h, Key::F);
    h.run();
    h.event(Event::Text("wobble".into()));
    h.run();
    h.key_press(Key::Enter);
    h.run();
    assert_eq!(h.state().selected(), vec![NodeId(2)]);
    // Bypass the found node: saved in the document and marked on the canvas.
    h.key_press(Key::Escape);
    h.run();
    h.state_mut().select(&[NodeId(1)]);
    cmd(&h, Key::B);
    h.run();
    assert!(h.state().doc().patch().nodes[0].bypass);
    assert!(h.query_by_label("bypassed").is_some());
    cmd(&h, Key::Z);
    h.run();
    assert!(!h.state().doc().patch().nodes[0].bypass);
    assert!(h.query_by_label("bypassed").is_none());
}

/// Nodes of many kinds (editors of every width, an IOBox, a texture pin) piled on one spot.
fn pile() -> Patch {
    let mut p = Patch::default();
    let types = [
        "LFO",
        "Sin (Value)",
        "Multiply (Value)",
        "Probe",
        "IOBox (Value)",
        "LinearSpread",
        "IOBox (Color)",
        "IOBox (Vector 3d)",
    ];
    for (k, t) in types.iter().enumerate() {
        p.add(NodeDoc::new(k as u32 + 1, t).at(30.0, 30.0));
    }
    p.nodes[4]
        .values
        .insert("Input".into(), Spread::Float(vec![1.0, 22.5, 333.25]));
    p.link(1, "Output", 2, "Input");
    p.link(2, "Output", 3, "Input 1");
    p.link(5, "Output", 3, "Input 2");
    p.link(3, "Output", 4, "Input");
    p
}

#[test]
fn the_layout_key_leaves_no_drawn_overlap_within_the_measure_and_undo_restores() {
    let env = Env::new();
    let before = pile();
    let path = env.patch_file("p.ron", &before);
    let mut h = harness(env.options(Some(path)));
    h.key_press(Key::L);
    h.run();
    // Fit again, so every node is on screen to be measured.
    h.key_press(Key::F);
    h.run();
    let registry = h.state().registry().clone();
    let patch = h.state().doc().patch().clone();
    assert!(spreadlight_editor::organise::measure::overlapping_nodes(&patch, &registry).is_empty());
    let zoom = h.state().canvas_zoom(&h.ctx).expect("zoom");
    let rects = h.state().node_screen_rects().to_vec();
    assert_eq!(rects.len(), patch.nodes.len());
    for (k, (id, r)) in rects.iter().enumerate() {
        let node = patch.node(*id).expect("node");
        let (w, hgt) = spreadlight_editor::organise::measure::node_size(node, &registry, &patch);
        let scale = spreadlight_editor::canvas::SCALE * zoom;
        assert!(
            r.width() <= w * scale + 0.5 && r.height() <= hgt * scale + 0.5,
            "{} is drawn {:?}, measured {:?}",
            node.type_name,
            r.size() / scale,
            (w, hgt)
        );
        for (other, s) in &rects[k + 1..] {
            assert!(
                !r.shrink(0.5).intersects(s.shrink(0.5)),
                "{id} and {other} overlap on screen"
            );
        }
    }
    cmd(&h, Key::Z);
    h.run();
    assert_eq!(h.state().doc().patch(), &before, "one undo step");

    // Shift+L: the same, top to bottom, each layer below the one feeding it.
    h.key_press_modifiers(Modifiers::SHIFT, Key::L);
    h.run();
    let patch = h.state().doc().patch().clone();
    assert_ne!(&patch, &before, "Shift+L moved the nodes");
    assert!(spreadlight_editor::organise::measure::overlapping_nodes(&patch, &registry).is_empty());
    let node = |id: u32| patch.node(NodeId(id)).expect("node");
    let bottom = |id: u32| {
        node(id).pos.1
            + spreadlight_editor::organise::measure::node_size(node(id), &registry, &patch).1
    };
    // LFO -> Sin -> Multiply -> Probe, a row each.
    for (a, b) in [(1, 2), (2, 3), (3, 4)] {
        assert!(
            node(b).pos.1 >= bottom(a),
            "{} is below {}: {:?} {:?}",
            node(b).type_name,
            node(a).type_name,
            node(b).pos,
            node(a).pos
        );
    }
    assert!(h.state().status().contains("top to bottom"));
    cmd(&h, Key::Z);
    h.run();
    assert_eq!(h.state().doc().patch(), &before, "one undo step");
}

#[test]
fn dragging_a_frame_title_moves_its_nodes() {
    let env = Env::new();
    let mut p = lfo_probe();
    p.frames.push(spreadlight_graph::FrameDoc::new(
        "Source",
        (10.0, 5.0),
        (60.0, 60.0),
    ));
    p.comments.push(spreadlight_graph::CommentDoc::new(
        10.0,
        -30.0,
        "# Title\n- **bold** item",
    ));
    let path = env.patch_file("p.ron", &p);
    let mut h = harness(env.options(Some(path)));
    let title = h
        .state()
        .canvas_to_screen(&h.ctx, Pos2::new(10.0 * 3.0 + 20.0, 5.0 * 3.0 + 8.0));
    drag(&mut h, title, title + Vec2::new(60.0, 30.0));
    h.run();
    let patch = h.state().doc().patch().clone();
    let lfo = patch.node(NodeId(1)).expect("node").pos;
    let probe = patch.node(NodeId(2)).expect("node").pos;
    assert!(
        lfo.0 > 20.0 && lfo.1 > 20.0,
        "the LFO inside moved: {lfo:?}"
    );
    let d = (lfo.0 - 20.0, lfo.1 - 20.0);
    assert_eq!(
        patch.frames[0].pos,
        (10.0 + d.0, 5.0 + d.1),
        "with its frame"
    );
    assert_eq!(probe, (120.0, 20.0), "the Probe outside stays");
    assert_eq!(h.state().doc().undo_label(), Some("move frame"));
    cmd(&h, Key::Z);
    h.run();
    assert_eq!(h.state().doc().patch(), &p);
}
