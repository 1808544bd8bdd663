//! Subpatches in the real editor, driven through egui_kittest at a small
//! window size: making one from the selection (Ctrl+G), opening it by
//! double-click, editing inside, the breadcrumb back, unmaking it
//! (Ctrl+Shift+G), each undone and redone; a subpatch file opened in place
//! and its edit saved to it, or recovered after a crash.

use crate::common;

use egui::accesskit::Role;
use egui::{Event, Key, Modifiers, PointerButton, Pos2, Vec2};
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use spreadlight_editor::EditorApp;
use spreadlight_graph::{NodeDoc, NodeId, Patch, Spread, format};

fn harness(dir: &tempfile::TempDir, patch: &Patch) -> Harness<'static, EditorApp> {
    format::save(patch, &dir.path().join("chain.ron")).expect("save");
    reopen(dir)
}

/// The editor started on `chain.ron` as it is on disk.
fn reopen(dir: &tempfile::TempDir) -> Harness<'static, EditorApp> {
    let path = dir.path().join("chain.ron");
    let options = common::options(Some(path), dir.path().join("config"));
    let mut h = common::editor(options, Vec2::new(900.0, 560.0));
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
    assert_eq!(
        h.state().doc().undo_label(),
        Some("make subpatch Subpatch"),
        "going back is no edit (the nodes left behind are not moved ones)"
    );
    let at = node_center(&h, made);
    click(&mut h, at, 1);
    keys(&mut h, Modifiers::COMMAND | Modifiers::SHIFT, Key::G);
    assert_eq!(types(&h), ["LFO", "Multiply (Value)", "Probe"]);
    assert_eq!(h.state().doc().patch().links.len(), 2);
    keys(&mut h, Modifiers::COMMAND, Key::Z);
    assert_eq!(types(&h), ["LFO", "Probe", "Subpatch"]);
}

/// The inspector's editor of `pin` (the rightmost of the editors named after it).
fn inspector_editor(h: &Harness<'_, EditorApp>, pin: &str) -> Pos2 {
    h.get_all_by_role_and_label(Role::SpinButton, pin)
        .map(|e| e.rect())
        .max_by(|a, b| a.left().total_cmp(&b.left()))
        .unwrap_or_else(|| panic!("no editor for {pin}"))
        .center()
}

fn drag(h: &mut Harness<'_, EditorApp>, from: Pos2, to: Pos2) {
    h.hover_at(from);
    h.step();
    h.drag_at(from);
    h.step();
    for k in 1..=6 {
        let t = k as f32 / 6.0;
        h.hover_at(from + (to - from) * t);
        h.step();
    }
    h.drop_at(to);
    h.run();
}

/// Inlet -> Multiply (Value) -> Outlet.
fn scale_module() -> Patch {
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
    module
}

/// LFO -> Scale (the module file) -> Probe.
fn uses_scale() -> Patch {
    let mut p = Patch::default();
    p.add(NodeDoc::new(1, "LFO").at(10.0, 10.0));
    p.add(NodeDoc::new(2, "Scale").at(10.0, 60.0));
    p.add(NodeDoc::new(3, "Probe").at(10.0, 110.0));
    p.link(1, "Output", 2, "In");
    p.link(2, "Out", 3, "Input");
    p
}

/// `modules/Scale.ron` beside the patch; returns its path.
fn write_scale_module(dir: &tempfile::TempDir) -> std::path::PathBuf {
    std::fs::create_dir(dir.path().join("modules")).expect("mkdir");
    let file = dir.path().join("modules/Scale.ron");
    format::save(&scale_module(), &file).expect("save");
    file
}

#[test]
fn a_subpatch_file_opens_in_place_and_its_edits_are_saved_to_it() {
    let dir = tempfile::tempdir().expect("tempdir");
    let file = write_scale_module(&dir);
    let p = uses_scale();
    let mut h = harness(&dir, &p);
    let top = dir.path().join("chain.ron");
    assert!(
        h.state().runtime().problems().is_empty(),
        "{:?}",
        h.state().runtime().problems()
    );
    assert!(
        h.state().pin_pos(NodeId(2), "In", true).is_some(),
        "its pins from the file"
    );

    // Double-click opens the file's inside in the patch's own canvas.
    let at = node_center(&h, NodeId(2));
    click(&mut h, at, 2);
    assert_eq!(
        h.state().path(),
        Some(top.as_path()),
        "the patch stays open"
    );
    assert_eq!(h.state().doc().scope(), ["Scale".to_owned()]);
    assert_eq!(h.state().instance(), [NodeId(2)]);
    assert_eq!(types(&h), ["Inlet", "Multiply (Value)", "Outlet"]);

    // Edit a value inside, in the inspector.
    let inner = node_center(&h, NodeId(2));
    click(&mut h, inner, 1);
    let editor = inspector_editor(&h, "Input 2");
    drag(&mut h, editor, editor + Vec2::new(60.0, 0.0));
    let factor = |h: &Harness<'_, EditorApp>| {
        h.state()
            .doc()
            .patch()
            .node(NodeId(2))
            .and_then(|n| n.values.get("Input 2").cloned())
    };
    let Some(Spread::Float(v)) = factor(&h) else {
        panic!("Input 2 was not set: {:?}", factor(&h));
    };
    assert!(
        v[0] > 1.0,
        "dragging right increased the default 1.0: {v:?}"
    );
    assert!(h.state().doc().is_dirty());
    assert!(
        h.state().runtime().problems().is_empty(),
        "the edited file runs"
    );

    // The breadcrumb goes back to the patch; undo opens the file again.
    h.get_by_label("⏶ chain").click();
    h.run();
    assert!(h.state().doc().scope().is_empty());
    assert_eq!(types(&h), ["LFO", "Probe", "Scale"]);
    keys(&mut h, Modifiers::COMMAND, Key::Z);
    assert_eq!(h.state().doc().scope(), ["Scale".to_owned()]);
    assert_eq!(factor(&h), None, "undone inside the file");
    keys(&mut h, Modifiers::COMMAND, Key::Y);
    assert_eq!(factor(&h), Some(Spread::Float(v.clone())));

    // Saving the patch writes the file; the patch itself still uses it by name.
    keys(&mut h, Modifiers::COMMAND, Key::S);
    assert!(!h.state().doc().is_dirty());
    let saved = format::load(&file).expect("module");
    assert_eq!(
        saved.node(NodeId(2)).and_then(|n| n.values.get("Input 2")),
        Some(&Spread::Float(v))
    );
    let parent = format::load(&top).expect("patch");
    assert!(parent.subpatches.is_empty(), "not copied into the patch");
    assert_eq!(parent, p);
}

/// Set a file's modification time a minute back, as it is when edits follow
/// a save (file times are coarse on some file systems).
fn age(path: &std::path::Path) {
    let old = std::time::SystemTime::now() - std::time::Duration::from_secs(60);
    std::fs::File::options()
        .write(true)
        .open(path)
        .and_then(|f| f.set_modified(old))
        .expect("touch");
}

#[test]
fn unsaved_edits_inside_a_subpatch_file_are_recovered_after_a_crash_unsaved() {
    let dir = tempfile::tempdir().expect("tempdir");
    let file = write_scale_module(&dir);
    let p = uses_scale();
    format::save(&p, &dir.path().join("chain.ron")).expect("save");
    let top = dir.path().join("chain.ron");
    age(&top);
    age(&file);
    let recovery = spreadlight_editor::files::recovery_path(Some(&top), dir.path());
    let modules = spreadlight_editor::files::module_recovery_path(&recovery);
    let edited = {
        let mut h = reopen(&dir);
        let at = node_center(&h, NodeId(2));
        click(&mut h, at, 2);
        assert_eq!(h.state().doc().scope(), ["Scale".to_owned()]);
        h.state_mut().doc_mut().set_value(
            NodeId(2),
            "Input 2",
            Some(Spread::Float(vec![3.0])),
            false,
        );
        h.run();
        assert!(modules.exists(), "the file's edit is autosaved");
        assert!(recovery.exists(), "and so is the patch");
        assert_eq!(
            format::load(&file).expect("module"),
            scale_module(),
            "the module file itself is untouched until saved"
        );
        h.state().doc().module_files()["Scale"].patch.clone()
        // Dropped unsaved: a crash, as far as the files know.
    };
    assert_ne!(edited, scale_module());

    let mut h = reopen(&dir);
    assert!(h.state().recovery_offered());
    assert_eq!(
        h.state().recovery_offered_modules(),
        std::slice::from_ref(&file)
    );
    assert!(
        h.state().doc().module_files().is_empty(),
        "nothing restored before the answer"
    );
    h.get_by_label("Restore").click();
    h.run();
    assert!(h.state().doc().is_dirty(), "restored edits are unsaved");
    assert_eq!(h.state().doc().module_files()["Scale"].patch, edited);
    assert_eq!(
        h.state().doc().runtime_patch().subpatches["Scale"],
        edited,
        "the restored edits run before they are saved"
    );
    assert_eq!(
        format::load(&file).expect("module"),
        scale_module(),
        "restoring does not write the module file"
    );
    assert!(
        h.state().runtime().problems().is_empty(),
        "{:?}",
        h.state().runtime().problems()
    );
    // Opening the node shows the file as edited.
    let at = node_center(&h, NodeId(2));
    click(&mut h, at, 2);
    assert_eq!(h.state().doc().patch(), &edited);

    keys(&mut h, Modifiers::COMMAND, Key::S);
    assert!(!h.state().doc().is_dirty());
    assert_eq!(format::load(&file).expect("module"), edited, "saved to it");
    assert_eq!(format::load(&top).expect("patch"), p);
    assert!(
        !recovery.exists() && !modules.exists(),
        "saving removes both"
    );
}

#[test]
fn discarding_the_recovery_drops_the_subpatch_files_edits_too() {
    let dir = tempfile::tempdir().expect("tempdir");
    let file = write_scale_module(&dir);
    format::save(&uses_scale(), &dir.path().join("chain.ron")).expect("save");
    let top = dir.path().join("chain.ron");
    age(&top);
    age(&file);
    let recovery = spreadlight_editor::files::recovery_path(Some(&top), dir.path());
    let modules = spreadlight_editor::files::module_recovery_path(&recovery);
    {
        let mut h = reopen(&dir);
        let at = node_center(&h, NodeId(2));
        click(&mut h, at, 2);
        h.state_mut().doc_mut().add_node("Probe", (0.0, 120.0));
        h.run();
        assert!(modules.exists());
    }
    let mut h = reopen(&dir);
    assert_eq!(
        h.state().recovery_offered_modules(),
        std::slice::from_ref(&file)
    );
    h.get_by_label("Discard").click();
    h.run();
    assert!(!recovery.exists() && !modules.exists(), "both autosaves go");
    assert!(!h.state().doc().is_dirty());
    assert_eq!(format::load(&file).expect("module"), scale_module());
    assert!(!reopen(&dir).state().recovery_offered());
}
