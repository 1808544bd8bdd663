//! Subpatches in the real editor, driven through egui_kittest at a small
//! window size: making one from the selection (Ctrl+G), opening it by
//! double-click, editing inside, the breadcrumb back, unmaking it
//! (Ctrl+Shift+G), each undone and redone.

use egui::{Event, Key, Modifiers, PointerButton, Pos2, Vec2};
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use spreadlight_editor::{EditorApp, EditorOptions};
use spreadlight_graph::{NodeDoc, NodeId, Patch, format};

fn harness(dir: &tempfile::TempDir, patch: &Patch) -> Harness<'static, EditorApp> {
    let path = dir.path().join("chain.ron");
    format::save(patch, &path).expect("save");
    let options = EditorOptions {
        path: Some(path),
        config_dir: dir.path().join("config"),
        autosave_secs: 0.0,
        automation: None,
        // Each frame shows the patch as of that frame (deterministic); the patch still runs on its worker thread.
        frame_wait: spreadlight_editor::FrameWait::Always,
    };
    let mut h = Harness::builder()
        .with_size(Vec2::new(900.0, 560.0))
        .with_max_steps(40)
        .wgpu_setup(spreadlight_editor::gpu::wgpu_setup(true))
        .build_eframe(move |cc| {
            let mut app = EditorApp::new(cc, options);
            app.set_playing(false);
            app
        });
    h.run();
    h
}

/// LFO -> Multiply (Value) -> Probe.
fn chain() -> Patch {
    let mut p = Patch::default();
    p.add(NodeDoc::new(1, "LFO").at(10.0, 10.0));
    p.add(NodeDoc::new(2, "Multiply (Value)").at(10.0, 60.0));
    p.add(NodeDoc::new(3, "Probe").at(10.0, 110.0));
    p.link(1, "Output", 2, "Input 1");
    p.link(2, "Output", 3, "Input");
    p
}

fn node_center(h: &Harness<'_, EditorApp>, id: NodeId) -> Pos2 {
    h.state()
        .node_screen_rects()
        .iter()
        .find(|(n, _)| *n == id)
        .map(|(_, r)| r.center())
        .unwrap_or_else(|| panic!("node {id} is not drawn"))
}

fn click(h: &mut Harness<'_, EditorApp>, at: Pos2, clicks: usize) {
    h.hover_at(at);
    h.step();
    for _ in 0..clicks {
        for pressed in [true, false] {
            h.input_mut().events.push(Event::PointerButton {
                pos: at,
                button: PointerButton::Primary,
                pressed,
                modifiers: Modifiers::NONE,
            });
        }
    }
    h.run();
}

fn keys(h: &mut Harness<'_, EditorApp>, modifiers: Modifiers, key: Key) {
    h.key_press_modifiers(modifiers, key);
    h.run();
}

fn types(h: &Harness<'_, EditorApp>) -> Vec<String> {
    let mut t: Vec<String> = h
        .state()
        .doc()
        .patch()
        .nodes
        .iter()
        .map(|n| n.type_name.clone())
        .collect();
    t.sort();
    t
}

#[test]
fn making_a_subpatch_from_the_selection_is_one_undo_step() {
    let dir = tempfile::tempdir().expect("tempdir");
    let mut h = harness(&dir, &chain());
    let at = node_center(&h, NodeId(2));
    click(&mut h, at, 1);
    assert_eq!(h.state().selected(), [NodeId(2)]);
    keys(&mut h, Modifiers::COMMAND, Key::G);
    assert_eq!(types(&h), ["LFO", "Probe", "Subpatch"]);
    let made = h.state().selected()[0];
    // Its pins are the links that crossed the selection, drawn with their names.
    assert!(h.state().pin_pos(made, "Input 1", true).is_some());
    assert!(h.state().pin_pos(made, "Output", false).is_some());
    assert!(h.state().runtime().problems().is_empty());
    keys(&mut h, Modifiers::COMMAND, Key::Z);
    assert_eq!(types(&h), ["LFO", "Multiply (Value)", "Probe"]);
    assert!(h.state().doc().top().subpatches.is_empty());
    keys(&mut h, Modifiers::COMMAND | Modifiers::SHIFT, Key::Z);
    assert_eq!(types(&h), ["LFO", "Probe", "Subpatch"]);
}

#[test]
fn a_subpatch_opens_by_double_click_is_edited_inside_and_unmade() {
    let dir = tempfile::tempdir().expect("tempdir");
    let mut h = harness(&dir, &chain());
    let made = {
        let registry = h.state().registry().clone();
        h.state_mut()
            .doc_mut()
            .make_subpatch(&registry, &[NodeId(2)])
            .expect("made")
    };
    h.run();
    let at = node_center(&h, made);
    click(&mut h, at, 2);
    assert_eq!(h.state().doc().scope(), ["Subpatch".to_owned()]);
    assert_eq!(h.state().instance(), [made]);
    assert_eq!(types(&h), ["Inlet", "Multiply (Value)", "Outlet"]);
    // Inside: live values of this instance, and edits land in the definition.
    let inner = node_center(&h, NodeId(2));
    click(&mut h, inner, 1);
    h.key_press(Key::Delete);
    h.run();
    assert_eq!(types(&h), ["Inlet", "Outlet"]);
    keys(&mut h, Modifiers::COMMAND, Key::Z);
    assert_eq!(types(&h), ["Inlet", "Multiply (Value)", "Outlet"]);
    // The breadcrumb goes back to the patch.
    h.get_by_label("⏶ chain").click();
    h.run();
    assert!(h.state().doc().scope().is_empty());
    assert_eq!(types(&h), ["LFO", "Probe", "Subpatch"]);
    let at = node_center(&h, made);
    click(&mut h, at, 1);
    keys(&mut h, Modifiers::COMMAND | Modifiers::SHIFT, Key::G);
    assert_eq!(types(&h), ["LFO", "Multiply (Value)", "Probe"]);
    assert_eq!(h.state().doc().patch().links.len(), 2);
    keys(&mut h, Modifiers::COMMAND, Key::Z);
    assert_eq!(types(&h), ["LFO", "Probe", "Subpatch"]);
}

#[test]
fn a_subpatch_file_opens_by_double_click_with_the_breadcrumb_back() {
    let dir = tempfile::tempdir().expect("tempdir");
    let mut module = Patch::default();
    module.add(NodeDoc::new(1, "Inlet").with("Name", vec!["In".to_owned()]));
    module.add(NodeDoc::new(2, "Multiply (Value)").at(0.0, 40.0));
    module.add(
        NodeDoc::new(3, "Outlet")
            .at(0.0, 80.0)
            .with("Name", vec!["Out".to_owned()]),
    );
    module.link(1, "Output", 2, "Input 1");
    module.link(2, "Output", 3, "Input");
    std::fs::create_dir(dir.path().join("modules")).expect("mkdir");
    let file = dir.path().join("modules/Scale.ron");
    format::save(&module, &file).expect("save");
    let mut p = Patch::default();
    p.add(NodeDoc::new(1, "LFO").at(10.0, 10.0));
    p.add(NodeDoc::new(2, "Scale").at(10.0, 60.0));
    p.add(NodeDoc::new(3, "Probe").at(10.0, 110.0));
    p.link(1, "Output", 2, "In");
    p.link(2, "Out", 3, "Input");
    let mut h = harness(&dir, &p);
    assert!(
        h.state().runtime().problems().is_empty(),
        "{:?}",
        h.state().runtime().problems()
    );
    assert!(
        h.state().pin_pos(NodeId(2), "In", true).is_some(),
        "its pins from the file"
    );
    let at = node_center(&h, NodeId(2));
    click(&mut h, at, 2);
    assert_eq!(h.state().path(), Some(file.as_path()));
    assert_eq!(types(&h), ["Inlet", "Multiply (Value)", "Outlet"]);
    h.get_by_label("⏶ chain").click();
    h.run();
    assert_eq!(
        h.state().path(),
        Some(dir.path().join("chain.ron").as_path())
    );
    assert_eq!(types(&h), ["LFO", "Probe", "Scale"]);
}
