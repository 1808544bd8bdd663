//! The canvas stays readable: fitting a big patch stops at a zoom where node
//! titles are still readable (a minimum on-screen text size, from the
//! layout) and pans to the patch's top left instead; the mouse wheel zooms
//! around the pointer rather than panning. At a small window size.

use crate::common;

use egui::{Event, Modifiers, MouseWheelUnit, Pos2, TouchPhase, Vec2};
use egui_kittest::Harness;
use spreadlight_editor::EditorApp;
use spreadlight_editor::canvas::READABLE_ZOOM;
use spreadlight_graph::{NodeDoc, Patch, format};

/// The smallest text, in points, a node title may have on screen after fitting.
const MIN_TEXT_POINTS: f32 = 9.0;

/// Rows of LFO -> Probe pairs, far wider and taller than the window.
fn wide_patch() -> Patch {
    let mut p = Patch::default();
    for k in 0..40u32 {
        let (x, y) = ((k % 8) as f32 * 300.0, (k / 8) as f32 * 200.0);
        p.add(NodeDoc::new(2 * k + 1, "LFO").at(x, y));
        p.add(NodeDoc::new(2 * k + 2, "Probe").at(x + 120.0, y));
        p.link(2 * k + 1, "Output", 2 * k + 2, "Input");
    }
    p
}

fn harness(dir: &tempfile::TempDir, patch: &Patch) -> Harness<'static, EditorApp> {
    harness_sized(dir, patch, Vec2::new(800.0, 500.0))
}

fn harness_sized(
    dir: &tempfile::TempDir,
    patch: &Patch,
    size: Vec2,
) -> Harness<'static, EditorApp> {
    let path = dir.path().join("wide.ron");
    format::save(patch, &path).expect("save");
    let options = common::options(Some(path), dir.path().join("config"));
    let mut h = common::editor_with(options, size, 60, |_| {});
    h.run();
    h
}

#[test]
fn fitting_a_big_patch_keeps_titles_readable_and_the_wheel_zooms_around_the_pointer() {
    let dir = tempfile::tempdir().expect("tempdir");
    let mut h = harness(&dir, &wide_patch());
    let zoom = h.state().canvas_zoom(&h.ctx).expect("canvas drawn");
    assert!(zoom >= READABLE_ZOOM - 1e-4, "fitted at {zoom}");
    let text = h.state().canvas_text_points(&h.ctx).expect("canvas drawn");
    assert!(
        text >= MIN_TEXT_POINTS,
        "titles are {text} points tall on screen"
    );
    // The patch starts at its top left: the first node is on screen.
    let canvas = h.state().canvas_rect().expect("canvas");
    let first = h
        .state()
        .node_screen_rects()
        .iter()
        .find(|(id, _)| id.0 == 1)
        .map(|(_, r)| *r);
    assert!(
        first.is_some_and(|r| canvas.intersects(r)),
        "{first:?} in {canvas:?}"
    );

    // The wheel zooms out around the pointer: the canvas point under it stays put.
    let pointer = canvas.center();
    let view_before = h.state().canvas_to_screen(&h.ctx, Pos2::ZERO);
    let under = {
        let zoom = h.state().canvas_zoom(&h.ctx).expect("zoom");
        Pos2::ZERO + (pointer - view_before) / zoom
    };
    h.hover_at(pointer);
    h.step();
    h.event(Event::MouseWheel {
        unit: MouseWheelUnit::Point,
        delta: Vec2::new(0.0, -120.0),
        phase: TouchPhase::Move,
        modifiers: Modifiers::NONE,
    });
    h.run();
    let after = h.state().canvas_zoom(&h.ctx).expect("zoom");
    assert!(
        after < zoom - 0.05,
        "the wheel zoomed out: {zoom} -> {after}"
    );
    let moved = h.state().canvas_to_screen(&h.ctx, under) - pointer;
    assert!(
        moved.length() < 2.0,
        "the point under the pointer moved by {moved:?}"
    );
}

/// The widest value editor a node row has (a vector's three drag values), in points.
const EDITOR_ALLOWANCE: f32 = 110.0;
/// Pins, the frame's margins and the gaps between a row's parts, in points.
const FRAME_ALLOWANCE: f32 = 40.0;

/// Nodes are as narrow as their title and pins need, as vvvv's: at real
/// size, no node is wider than its title, or its widest input name with a
/// value editor beside its widest output name, plus the frame. Measured from
/// the layout: text widths from egui's fonts, node widths as drawn.
#[test]
fn nodes_are_as_narrow_as_their_title_and_pins_need() {
    let dir = tempfile::tempdir().expect("tempdir");
    let mut p = Patch::default();
    for (k, name) in [
        "DeferredBase",
        "Transform (Transform 3d)",
        "LFO",
        "Probe",
        "MRE",
        "FileTexture",
        "SSAO",
        "Torus",
    ]
    .iter()
    .enumerate()
    {
        let k = k as u32;
        p.add(NodeDoc::new(k + 1, name).at((k % 4) as f32 * 130.0, (k / 4) as f32 * 120.0));
    }
    let mut h = harness_sized(&dir, &p, Vec2::new(1800.0, 1100.0));
    h.run();
    let zoom = h.state().canvas_zoom(&h.ctx).expect("canvas drawn");
    let font = h
        .ctx
        .global_style()
        .text_styles
        .get(&egui::TextStyle::Body)
        .cloned()
        .expect("body font");
    let width_of = |text: &str| {
        h.ctx.fonts_mut(|f| {
            f.layout_no_wrap(text.to_owned(), font.clone(), egui::Color32::WHITE)
                .size()
                .x
        })
    };
    let rects = h.state().node_screen_rects().to_vec();
    assert_eq!(rects.len(), p.nodes.len(), "every node drawn");
    for (id, rect) in rects {
        let node = p.node(id).expect("node");
        let def = h
            .state()
            .registry()
            .get(&node.type_name)
            .expect("type")
            .clone();
        let widest = |names: Vec<&str>| names.into_iter().map(&width_of).fold(0.0, f32::max);
        let inputs = widest(def.inputs.iter().map(|p| &*p.name).collect());
        let outputs = widest(def.outputs.iter().map(|p| &*p.name).collect());
        // The title is drawn strong; allow a tenth more for it.
        let title = width_of(&node.type_name) * 1.1;
        // A texture output's thumbnail sits between the inputs and the outputs.
        let thumbnail = if def
            .outputs
            .iter()
            .any(|p| spreadlight_editor::previews::has_thumbnail(p.ty))
        {
            spreadlight_editor::previews::THUMB_POINTS + 8.0
        } else {
            0.0
        };
        let need = title.max(inputs + EDITOR_ALLOWANCE + thumbnail + outputs) + FRAME_ALLOWANCE;
        let width = rect.width() / zoom;
        assert!(
            width <= need,
            "{} is {width:.0} points wide; its title and pins need {need:.0}",
            node.type_name
        );
    }
}

/// `pairs` LFO -> Probe pairs, eight to a row, as `wide_patch` lays them out.
fn pairs(pairs: u32) -> Patch {
    let mut p = Patch::default();
    for k in 0..pairs {
        let (x, y) = ((k % 8) as f32 * 300.0, (k / 8) as f32 * 200.0);
        p.add(NodeDoc::new(2 * k + 1, "LFO").at(x, y));
        p.add(NodeDoc::new(2 * k + 2, "Probe").at(x + 120.0, y));
        p.link(2 * k + 1, "Output", 2 * k + 2, "Input");
    }
    p
}

/// Big patches stay fluid: the canvas lays out (titles, pins, values) only
/// the nodes near its view, so eight times the nodes off screen cost
/// nothing more, and a wire from a node on screen to one far off it is still
/// drawn, its far end where that node's pin is.
#[test]
fn only_the_nodes_near_the_view_are_laid_out_and_wires_still_lead_off_screen() {
    let dir = tempfile::tempdir().expect("tempdir");
    let mut counts = Vec::new();
    for n in [40, 320] {
        let mut h = harness(&dir, &pairs(n));
        h.run_steps(2);
        let laid_out = h.state().nodes_laid_out();
        assert!(
            laid_out > 0 && laid_out < 2 * n as usize,
            "{laid_out} of {} nodes laid out",
            2 * n
        );
        counts.push(laid_out);
    }
    assert_eq!(counts[0], counts[1], "flat in the nodes off screen");

    let mut p = pairs(4);
    p.add(NodeDoc::new(100, "Probe").at(3000.0, 0.0));
    p.link(1, "Output", 100, "Input");
    let mut h = harness(&dir, &p);
    h.run_steps(2);
    let canvas = h.state().canvas_rect().expect("canvas");
    assert!(
        h.state().nodes_laid_out() < 9,
        "the far node is not laid out: {} of 9",
        h.state().nodes_laid_out()
    );
    let far_node = h
        .state()
        .node_screen_rects()
        .iter()
        .find(|(id, _)| id.0 == 100)
        .map(|(_, r)| *r)
        .expect("every node has its rectangle, drawn or not");
    assert!(far_node.min.x > canvas.max.x, "{far_node:?}");
    let near = h
        .state()
        .pin_pos(spreadlight_graph::NodeId(1), "Output", false)
        .expect("the near end is drawn");
    let far = h
        .state()
        .pin_pos(spreadlight_graph::NodeId(100), "Input", true)
        .expect("the wire's far end is recorded");
    assert!(canvas.contains(near), "{near:?} in {canvas:?}");
    assert!(
        far.x > canvas.max.x + 1000.0,
        "{far:?} far right of {canvas:?}"
    );
}
