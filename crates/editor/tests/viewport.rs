//! The viewports and the GPU timings, on the showcase patch: rendered by the
//! shared renderer on the device the harness's egui draws with.

use crate::common;

use std::path::PathBuf;

use egui::Vec2;
use egui::accesskit::Role;
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use spreadlight_editor::EditorApp;

fn showcase() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../patches/showcase.ron")
}

fn harness(dir: &tempfile::TempDir) -> Harness<'static, EditorApp> {
    let options = common::options(Some(showcase()), dir.path().to_owned());
    let mut h = common::editor(options, Vec2::new(1400.0, 800.0));
    h.run();
    h
}

/// How many distinct colours a region of the rendered window has: a blank
/// (or single-colour) viewport has one or two.
fn distinct_colours(image: &image::RgbaImage, rect: egui::Rect, ppp: f32) -> usize {
    let mut seen = std::collections::HashSet::new();
    let (x0, y0) = ((rect.min.x * ppp) as u32, (rect.min.y * ppp) as u32);
    let (x1, y1) = ((rect.max.x * ppp) as u32, (rect.max.y * ppp) as u32);
    for y in (y0..y1.min(image.height())).step_by(2) {
        for x in (x0..x1.min(image.width())).step_by(2) {
            let p = image.get_pixel(x, y);
            // Quantised, so dithering noise does not count as content.
            seen.insert((p[0] / 16, p[1] / 16, p[2] / 16));
        }
    }
    seen.len()
}

#[test]
fn the_viewport_shows_the_output_rendered_on_egui_s_device() {
    let dir = tempfile::tempdir().expect("tempdir");
    let mut h = harness(&dir);
    assert_eq!(h.state().gpu_error(), None);
    assert_eq!(h.state().viewport_error(0), None);
    let texture = h.state().viewport_texture(0).expect("a viewport texture");
    let rect = h.state().viewport_rect(0).expect("the viewport was drawn");
    let ppp = h.ctx.pixels_per_point();
    assert_eq!(
        (texture.width(), texture.height()),
        (
            (rect.width() * ppp).round() as u32,
            (rect.height() * ppp).round() as u32
        ),
        "rendered at the panel's size in pixels"
    );
    let image = h.render().expect("render the window");
    let colours = distinct_colours(&image, rect, ppp);
    assert!(
        colours > 20,
        "the lit scene has many colours, got {colours}"
    );
    image
        .save(dir.path().join("window.png"))
        .expect("the image can be written");
}

#[test]
fn a_second_viewport_shows_any_texture_pin() {
    let dir = tempfile::tempdir().expect("tempdir");
    let mut h = harness(&dir);
    h.get_by_role_and_label(Role::ComboBox, "Texture pin")
        .click();
    h.run();
    // Pins are listed as "Type #id.Pin"; the first light's diffuse term is near the top.
    h.get_by_label("CookTorrance #23.Diffuse").click();
    h.run();
    assert_eq!(h.state().viewport_error(1), None);
    let rect = h.state().viewport_rect(1).expect("second viewport drawn");
    let ppp = h.ctx.pixels_per_point();
    let image = h.render().expect("render");
    assert!(distinct_colours(&image, rect, ppp) > 20);
}

#[test]
fn timings_show_cpu_per_node_and_gpu_per_render_node() {
    let dir = tempfile::tempdir().expect("tempdir");
    let mut h = harness(&dir);
    assert!(
        h.query_by_label_contains("CPU ").is_none(),
        "hidden until asked"
    );
    h.get_by_label("⏱ Timings").click();
    h.run();
    let cpu = h.query_all_by_label_contains("CPU ").count();
    assert!(cpu > 10, "every node shows its CPU time, got {cpu}");
    let gpu = h.query_all_by_label_contains("GPU ").count();
    assert!(gpu >= 1, "render nodes show their GPU time");
}

#[test]
fn an_opened_patch_is_fitted_into_the_canvas_and_f_fits_again() {
    let dir = tempfile::tempdir().expect("tempdir");
    let mut h = harness(&dir);
    let inside = |h: &Harness<'_, EditorApp>| {
        let canvas = h.state().canvas_rect().expect("canvas drawn");
        let rects = h.state().node_screen_rects();
        assert_eq!(rects.len(), h.state().doc().patch().nodes.len());
        rects
            .iter()
            .filter(|(_, r)| !canvas.expand(1.0).contains_rect(*r))
            .count()
    };
    // Fitted readably: all of the showcase on screen, or as much as a readable zoom shows.
    let zoom = h.state().canvas_zoom(&h.ctx).expect("canvas drawn");
    let readable = spreadlight_editor::canvas::READABLE_ZOOM;
    assert!(zoom >= readable - 1e-4, "fitted at {zoom}");
    let fitted = inside(&h);
    assert!(
        fitted == 0 || (zoom - readable).abs() < 1e-4,
        "{fitted} nodes off screen at {zoom}"
    );
    // Zoom in on the canvas with the wheel, then F shows everything again.
    let canvas = h.state().canvas_rect().expect("canvas");
    h.hover_at(canvas.center());
    h.step();
    for _ in 0..5 {
        h.event(egui::Event::Zoom(1.5));
        h.step();
    }
    h.run();
    assert!(inside(&h) > 0, "zoomed in, some nodes are off screen");
    h.key_press(egui::Key::F);
    h.run();
    assert_eq!(inside(&h), fitted);
}

/// The window's pixels at the centre of the first viewport, showing a patch
/// whose Output is a flat PNG of `grey` (sRGB-encoded, as files are).
fn viewport_centre_showing_a_flat_png(grey: u8) -> image::Rgba<u8> {
    use spreadlight_graph::{NodeDoc, Patch};
    let dir = tempfile::tempdir().expect("tempdir");
    image::RgbaImage::from_pixel(16, 16, image::Rgba([grey, grey, grey, 255]))
        .save(dir.path().join("grey.png"))
        .expect("png");
    let mut p = Patch::default();
    p.add(NodeDoc::new(1, "FileTexture").with("Filename", vec!["grey.png".to_owned()]));
    p.add(
        NodeDoc::new(2, "Output")
            .at(120.0, 0.0)
            .with("Write", vec![false]),
    );
    p.link(1, "Texture", 2, "Texture");
    viewport_centre(&p, &dir)
}

/// The window's pixels at the centre of the first viewport of the editor
/// on `patch`, saved in `dir`; the viewport must show it without an error.
fn viewport_centre(patch: &spreadlight_graph::Patch, dir: &tempfile::TempDir) -> image::Rgba<u8> {
    let path = dir.path().join("patch.ron");
    spreadlight_graph::format::save(patch, &path).expect("save");
    let options = common::options(Some(path), dir.path().join("config"));
    let mut h = common::editor(options, Vec2::new(1100.0, 700.0));
    h.run_steps(4);
    assert_eq!(h.state().viewport_error(0), None);
    let rect = h.state().viewport_rect(0).expect("the viewport was drawn");
    let ppp = h.ctx.pixels_per_point();
    let image = h.render().expect("render the window");
    let centre = rect.center() * ppp;
    *image.get_pixel(centre.x as u32, centre.y as u32)
}

/// A texture array (two image files as layers) shows its first layer: the
/// viewport's blit samples one 2D layer, where a default view of the array
/// was an array view the blit could not bind (a GPU validation error).
#[test]
fn a_texture_array_shows_its_first_layer() {
    use spreadlight_graph::{NodeDoc, Patch};
    let dir = tempfile::tempdir().expect("tempdir");
    for (name, grey) in [("dark.png", 40u8), ("light.png", 230)] {
        image::RgbaImage::from_pixel(16, 16, image::Rgba([grey, grey, grey, 255]))
            .save(dir.path().join(name))
            .expect("png");
    }
    let mut p = Patch::default();
    p.add(NodeDoc::new(1, "FileTexture (Array)").with(
        "Filenames",
        vec!["dark.png".to_owned(), "light.png".to_owned()],
    ));
    p.add(
        NodeDoc::new(2, "Output")
            .at(120.0, 0.0)
            .with("Write", vec![false]),
    );
    p.link(1, "Texture", 2, "Texture");
    let centre = viewport_centre(&p, &dir);
    for c in &centre.0[..3] {
        assert!(
            (i32::from(*c) - 40).abs() <= 3,
            "layer 0 shows as {centre:?}"
        );
    }
}

#[test]
fn a_texture_shows_in_the_viewport_as_its_file_has_it() {
    // The renderer holds linear values; the viewport must show them encoded
    // for the display, as a saved frame or another viewer would (it showed
    // linear 0.305, sRGB 150, as 78).
    for grey in [40u8, 150, 230] {
        let p = viewport_centre_showing_a_flat_png(grey);
        for c in &p.0[..3] {
            assert!(
                (i32::from(*c) - i32::from(grey)).abs() <= 3,
                "sRGB {grey} shows as {p:?}"
            );
        }
    }
}

/// A patch of a FileTexture (node 1) showing `file`, with its sRGB switch,
/// and, with `output`, an Output (node 2) it feeds.
fn file_texture_patch(file: &str, srgb: bool, output: bool) -> spreadlight_graph::Patch {
    use spreadlight_graph::{NodeDoc, Patch};
    let mut p = Patch::default();
    p.add(
        NodeDoc::new(1, "FileTexture")
            .with("Filename", vec![file.to_owned()])
            .with("sRGB", vec![srgb]),
    );
    if output {
        p.add(
            NodeDoc::new(2, "Output")
                .at(160.0, 0.0)
                .with("Write", vec![false]),
        );
        p.link(1, "Texture", 2, "Texture");
    }
    p
}

/// The editor on `patch`, saved in `dir`, run until it settles.
fn editor_on(
    patch: &spreadlight_graph::Patch,
    dir: &tempfile::TempDir,
    size: Vec2,
) -> Harness<'static, EditorApp> {
    let path = dir.path().join("patch.ron");
    spreadlight_graph::format::save(patch, &path).expect("save");
    let options = common::options(Some(path), dir.path().join("config"));
    let mut h = common::editor(options, size);
    h.run_steps(6);
    h
}

fn thumb_key(node: u32) -> spreadlight_editor::previews::PreviewKey {
    spreadlight_editor::previews::PreviewKey {
        path: vec![spreadlight_graph::NodeId(node)],
        pin: "Texture".to_owned(),
        channel: None,
        large: false,
    }
}

/// The window's pixel at a fraction (`fx`, `fy`) across a rectangle in points.
fn pixel_in(image: &image::RgbaImage, rect: egui::Rect, ppp: f32, fx: f32, fy: f32) -> [u8; 3] {
    let p = rect.lerp_inside(Vec2::new(fx, fy)) * ppp;
    let c = image.get_pixel(p.x as u32, p.y as u32);
    [c[0], c[1], c[2]]
}

fn assert_grey(seen: [u8; 3], grey: u8, what: &str) {
    for c in seen {
        assert!(
            (i32::from(c) - i32::from(grey)).abs() <= 4,
            "{what}: expected grey {grey}, the window shows {seen:?}"
        );
    }
}

/// A two-tone PNG: the left half `left`, the right half `right` (sRGB bytes).
fn two_tone(dir: &tempfile::TempDir, left: u8, right: u8) {
    image::RgbaImage::from_fn(64, 36, |x, _| {
        let g = if x < 32 { left } else { right };
        image::Rgba([g, g, g, 255])
    })
    .save(dir.path().join("two.png"))
    .expect("png");
}

#[test]
fn a_thumbnail_shows_the_texture_it_previews_and_the_value_under_the_pointer() {
    let dir = tempfile::tempdir().expect("tempdir");
    two_tone(&dir, 40, 200);
    let p = file_texture_patch("two.png", true, true);
    let mut h = editor_on(&p, &dir, Vec2::new(1100.0, 700.0));
    assert!(h.state().thumbnails(), "thumbnails are on by default");
    let rect = h
        .state()
        .thumbnail_rect(&thumb_key(1))
        .expect("the FileTexture's thumbnail is drawn");
    let out = h
        .state()
        .preview(&thumb_key(1))
        .expect("the worker made it");
    assert_eq!(out.error, None);
    let (size, _) = out.source.expect("the texture's size and format");
    assert_eq!(size, (64, 36));
    let ppp = h.ctx.pixels_per_point();
    let image = h.render().expect("render the window");
    // Each half at its file's value, as the texture holds it.
    assert_grey(pixel_in(&image, rect, ppp, 0.25, 0.5), 40, "left half");
    assert_grey(pixel_in(&image, rect, ppp, 0.75, 0.5), 200, "right half");
    // Hovering it probes the texel under the pointer: linear, as shaders read it.
    h.event(egui::Event::PointerMoved(
        rect.lerp_inside(Vec2::new(0.8, 0.5)),
    ));
    h.run_steps(3);
    let (texel, value) = h
        .state()
        .preview(&thumb_key(1))
        .and_then(|o| o.value)
        .expect("a probed value");
    assert_eq!(texel, (51, 18));
    let linear = spreadlight_render::readback::srgb_to_linear(200.0 / 255.0);
    assert!(
        (value[0] - linear).abs() < 0.01,
        "{value:?} against {linear}"
    );
    // Ctrl+T takes every thumbnail away; nothing is asked for then.
    h.state_mut().set_thumbnails(false);
    h.run_steps(3);
    assert!(h.state().preview_requests().is_empty());
    assert!(h.state().thumbnail_rect(&thumb_key(1)).is_none());
}

/// A thumbnail of a texture the patch's frame makes and reads anyway (the
/// first of two FXAA passes) watches it (`FrameGraph::watch`) instead of
/// requesting it: it shows the texture's pixels, with no low-rate note.
#[test]
fn a_thumbnail_of_a_texture_the_frame_makes_shows_it_without_a_request() {
    use spreadlight_graph::NodeDoc;
    let dir = tempfile::tempdir().expect("tempdir");
    // A source smaller than the viewport: image effects keep its size
    // (`FrameGraph::effect_size`), so the thumbnail shows it whole.
    image::RgbaImage::from_pixel(64, 36, image::Rgba([90, 90, 90, 255]))
        .save(dir.path().join("flat.png"))
        .expect("png");
    let mut p = file_texture_patch("flat.png", true, false);
    p.add(NodeDoc::new(2, "FXAA").at(160.0, 0.0));
    p.add(NodeDoc::new(3, "FXAA").at(320.0, 0.0));
    p.add(
        NodeDoc::new(4, "Output")
            .at(480.0, 0.0)
            .with("Write", vec![false]),
    );
    p.link(1, "Texture", 2, "Texture");
    p.link(2, "Texture", 3, "Texture");
    p.link(3, "Texture", 4, "Texture");
    let mut h = editor_on(&p, &dir, Vec2::new(1300.0, 700.0));
    h.run_steps(3);
    let rect = h
        .state()
        .thumbnail_rect(&thumb_key(2))
        .expect("the first FXAA's thumbnail is drawn");
    let out = h
        .state()
        .preview(&thumb_key(2))
        .expect("the worker made it");
    assert_eq!(out.error, None);
    assert_eq!(out.note, None, "the patch's frame makes and reads it");
    assert!(out.source.is_some());
    let ppp = h.ctx.pixels_per_point();
    let image = h.render().expect("render the window");
    assert_grey(pixel_in(&image, rect, ppp, 0.5, 0.5), 90, "watched texture");
    // Its far corner too: the whole source, not its corner in a black frame.
    assert_grey(pixel_in(&image, rect, ppp, 0.9, 0.9), 90, "its far corner");
}

/// Thumbnails ride the patch's own frame (issue 32: previews must not slow
/// the patch): each submission of the worker's waits at the submission gate
/// for a UI frame, and each wait asks for a repaint. So the thumbnails' and
/// the viewport's blits go in the frame's own submission: N patch frames
/// with K thumbnails refreshed in each make N submissions and publish N
/// frames (one wake of the UI each), as with no thumbnail at all; they made
/// 3N submissions when the blits were submitted apart.
#[test]
fn thumbnails_refreshed_with_a_patch_frame_go_in_its_one_submission() {
    use spreadlight_graph::{NodeDoc, NodeId, Spread};
    let dir = tempfile::tempdir().expect("tempdir");
    image::RgbaImage::from_pixel(64, 36, image::Rgba([90, 90, 90, 255]))
        .save(dir.path().join("flat.png"))
        .expect("png");
    // FileTexture -> Tonemap -> FXAA -> FXAA -> Output: four thumbnails,
    // three of which change with the Tonemap's exposure.
    let mut p = file_texture_patch("flat.png", true, false);
    p.add(NodeDoc::new(2, "Tonemap").at(160.0, 0.0));
    p.add(NodeDoc::new(3, "FXAA").at(320.0, 0.0));
    // Two rows, so that all fit the window at the readable zoom.
    p.add(NodeDoc::new(4, "FXAA").at(0.0, 240.0));
    p.add(
        NodeDoc::new(5, "Output")
            .at(160.0, 240.0)
            .with("Write", vec![false]),
    );
    p.link(1, "Texture", 2, "Texture");
    p.link(2, "Texture", 3, "Texture");
    p.link(3, "Texture", 4, "Texture");
    p.link(4, "Texture", 5, "Texture");
    let mut h = editor_on(&p, &dir, Vec2::new(1300.0, 800.0));
    for node in 1..=4 {
        assert!(
            h.state().thumbnail_rect(&thumb_key(node)).is_some(),
            "node {node}'s thumbnail is on screen"
        );
    }
    let (before, evaluated) = (h.state().worker_counts(), h.state().evaluations());
    let frames = 4u64;
    for k in 0..frames {
        // An edit: one patch frame (the editor is paused, each UI frame
        // waits for it), every changed thumbnail refreshed.
        let exposure = Spread::Float(vec![2.0 + k as f32 * 0.5]);
        h.state_mut()
            .doc_mut()
            .set_value(NodeId(2), "Exposure", Some(exposure), false);
        h.step();
    }
    let after = h.state().worker_counts();
    assert_eq!(h.state().evaluations() - evaluated, frames, "patch frames");
    assert_eq!(
        after.thumbnails_scaled - before.thumbnails_scaled,
        3 * frames,
        "the Tonemap's and both FXAAs' thumbnails refreshed in every frame \
         (the FileTexture's did not change)"
    );
    assert_eq!(
        after.gate.submissions - before.gate.submissions,
        frames,
        "one submission a patch frame, its thumbnails' and viewport's blits in it"
    );
    assert_eq!(
        after.published - before.published,
        frames,
        "one frame published (one wake of the UI) a patch frame"
    );
    // The right pixels: the tonemapped grey in the Tonemap's thumbnail, the
    // same through both (flat-image) FXAAs and in the viewport.
    for node in 1..=4 {
        let out = h.state().preview(&thumb_key(node)).expect("made");
        assert_eq!(out.error, None, "node {node}");
    }
    let ppp = h.ctx.pixels_per_point();
    let image = h.render().expect("render the window");
    let at = |rect: egui::Rect| pixel_in(&image, rect, ppp, 0.5, 0.5);
    let thumb = |node| h.state().thumbnail_rect(&thumb_key(node)).expect("drawn");
    let source = at(thumb(1));
    assert_grey(source, 90, "the FileTexture's thumbnail");
    let tonemapped = at(thumb(2));
    assert!(
        tonemapped[0] > source[0] + 30,
        "exposure 3.5 brightens: {tonemapped:?} against {source:?}"
    );
    for (rect, what) in [
        (thumb(3), "the first FXAA's thumbnail"),
        (thumb(4), "the second FXAA's thumbnail"),
        (
            h.state().viewport_rect(0).expect("the viewport was drawn"),
            "the viewport",
        ),
    ] {
        assert_grey(at(rect), tonemapped[0], what);
    }
}

#[test]
fn a_preview_of_an_unsunk_branch_evaluates_it_and_render_still_does_not() {
    use spreadlight_graph::stats::NodeRun;
    let dir = tempfile::tempdir().expect("tempdir");
    two_tone(&dir, 90, 90);
    // The FileTexture feeds nothing: no sink needs it.
    let p = file_texture_patch("two.png", true, false);
    let mut h = editor_on(&p, &dir, Vec2::new(1100.0, 700.0));
    let node = spreadlight_graph::NodeId(1);
    assert_eq!(
        h.state().runtime().stats().node(node).map(|n| n.run),
        Some(NodeRun::Evaluated),
        "its thumbnail demanded it"
    );
    let rect = h.state().thumbnail_rect(&thumb_key(1)).expect("drawn");
    assert_eq!(
        h.state()
            .preview(&thumb_key(1))
            .and_then(|o| o.error.clone()),
        None
    );
    let ppp = h.ctx.pixels_per_point();
    let image = h.render().expect("render the window");
    assert_grey(
        pixel_in(&image, rect, ppp, 0.5, 0.5),
        90,
        "the unsunk texture",
    );
    // `render` evaluates with the patch's own demand: the branch stays skipped.
    let mut runtime = spreadlight_graph::Runtime::new(spreadlight_editor::nodes::registry());
    runtime.provide(std::sync::Arc::new(spreadlight_graph::PatchDir(
        dir.path().to_owned(),
    )));
    runtime.load(&p);
    let stats = runtime.evaluate(spreadlight_graph::FrameClock::default());
    assert_eq!(stats.node(node).map(|n| n.run), Some(NodeRun::Skipped));
}

#[test]
fn a_linear_texture_shows_at_its_true_value() {
    // Data (sRGB off: a normal map, a mask) shows as stored, 128 as 128, as
    // image viewers show it; it showed sRGB-encoded, 128 as 188.
    for grey in [64u8, 128, 200] {
        let dir = tempfile::tempdir().expect("tempdir");
        two_tone(&dir, grey, grey);
        let p = file_texture_patch("two.png", false, true);
        let mut h = editor_on(&p, &dir, Vec2::new(1100.0, 700.0));
        assert_eq!(h.state().viewport_error(0), None);
        let view = h.state().viewport_rect(0).expect("the viewport was drawn");
        let thumb = h.state().thumbnail_rect(&thumb_key(1)).expect("drawn");
        let ppp = h.ctx.pixels_per_point();
        let image = h.render().expect("render the window");
        assert_grey(pixel_in(&image, view, ppp, 0.5, 0.5), grey, "viewport");
        assert_grey(pixel_in(&image, thumb, ppp, 0.5, 0.5), grey, "thumbnail");
    }
    // A float file holds linear light: 0.5 shows sRGB-encoded (188), not cut
    // to 8 bits and taken as encoded (0.5 showed as 128, darker than it is).
    let dir = tempfile::tempdir().expect("tempdir");
    image::Rgb32FImage::from_pixel(16, 16, image::Rgb([0.5, 0.5, 0.5]))
        .save(dir.path().join("half.hdr"))
        .expect("hdr");
    let p = file_texture_patch("half.hdr", true, true);
    let mut h = editor_on(&p, &dir, Vec2::new(1100.0, 700.0));
    assert_eq!(h.state().viewport_error(0), None);
    let view = h.state().viewport_rect(0).expect("drawn");
    let ppp = h.ctx.pixels_per_point();
    let image = h.render().expect("render the window");
    assert_grey(pixel_in(&image, view, ppp, 0.5, 0.5), 188, "linear 0.5");
}

#[test]
fn off_screen_thumbnails_are_not_requested() {
    let dir = tempfile::tempdir().expect("tempdir");
    two_tone(&dir, 90, 90);
    let mut p = file_texture_patch("two.png", true, false);
    // Far beyond the window at the readable zoom the patch opens at.
    p.add(
        spreadlight_graph::NodeDoc::new(3, "FileTexture")
            .at(3000.0, 3000.0)
            .with("Filename", vec!["two.png".to_owned()]),
    );
    let h = editor_on(&p, &dir, Vec2::new(900.0, 600.0));
    let asked: Vec<_> = h
        .state()
        .preview_requests()
        .iter()
        .map(|r| r.key.path.clone())
        .collect();
    assert!(
        asked.contains(&vec![spreadlight_graph::NodeId(1)]),
        "{asked:?}"
    );
    assert!(
        !asked.contains(&vec![spreadlight_graph::NodeId(3)]),
        "an off-screen node asks for nothing: {asked:?}"
    );
    assert!(h.state().thumbnail_rect(&thumb_key(3)).is_none());
    assert!(
        h.state().preview(&thumb_key(3)).is_none(),
        "nor does the worker make it"
    );
}

#[test]
fn a_g_buffer_output_shows_a_channel_as_its_thumbnail() {
    use spreadlight_editor::previews::{ChannelName, PreviewKey};
    let dir = tempfile::tempdir().expect("tempdir");
    let mut h = harness(&dir);
    // The tidied showcase opens fitted to its bounds, where the MRE may lie
    // outside the canvas: bring it beside a node that is on screen.
    let mre = spreadlight_graph::NodeId(15);
    let canvas = h.state().canvas_rect().expect("a canvas");
    let beside = h
        .state()
        .node_screen_rects()
        .iter()
        .find(|(id, r)| *id != mre && canvas.contains_rect(*r))
        .map(|(id, _)| *id)
        .expect("a node on screen");
    let at = h.state().doc().node(beside).expect("on screen").pos;
    let from = h.state().doc().node(mre).expect("the MRE").pos;
    h.state_mut().doc_mut().execute(
        "move",
        spreadlight_editor::model::Command::Move {
            moves: vec![(mre, from, (at.0 + 20.0, at.1 + 20.0))],
        },
    );
    // Not an edit to keep: no autosave beside the shipped patch.
    h.state_mut().doc_mut().mark_saved();
    h.run();
    // The showcase's MRE (node 15): its G-buffer's albedo, at the viewport's size.
    let key = PreviewKey {
        path: vec![spreadlight_graph::NodeId(15)],
        pin: "G-Buffer".to_owned(),
        channel: Some(ChannelName(0)),
        large: false,
    };
    let rect = h
        .state()
        .thumbnail_rect(&key)
        .expect("the MRE's thumbnail is drawn");
    let out = h.state().preview(&key).expect("the worker made it");
    assert_eq!(out.error, None);
    let (size, _) = out.source.expect("its size");
    assert_eq!(
        Some(size),
        h.state().viewport_pixels(0),
        "rendered in the viewport's frame"
    );
    let image = h.render().expect("render the window");
    assert!(
        distinct_colours(&image, rect, h.ctx.pixels_per_point()) > 2,
        "the albedo of the scene, not a blank"
    );
    // `SPREADLIGHT_DOC_PICTURES=1` refreshes docs/editor.md's picture of previews.
    if std::env::var_os("SPREADLIGHT_DOC_PICTURES").is_some() {
        let docs = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../docs/editor-previews.png");
        image.save(docs).expect("write docs/editor-previews.png");
    }
}

/// Hover the output pin `pin` of node `node` (its name, where snarl draws it) until its popup shows.
fn hover_output(h: &mut Harness<'static, EditorApp>, node: u32, pin: &str) {
    let dot = h
        .state()
        .pin_pos(spreadlight_graph::NodeId(node), pin, false)
        .expect("the pin is drawn");
    // The name is left of the pin's dot, on its row.
    let at = h
        .get_all_by_label(pin)
        .map(|l| {
            let r = l.rect();
            let a = h.state().canvas_to_screen(&h.ctx, r.min);
            let b = h.state().canvas_to_screen(&h.ctx, r.max);
            egui::Rect::from_min_max(a, b).center()
        })
        .min_by(|a, b| a.distance(dot).total_cmp(&b.distance(dot)))
        .expect("the pin's name");
    h.hover_at(at);
    h.run_steps(6);
}

#[test]
fn hovering_a_texture_or_mesh_pin_shows_its_large_preview() {
    use spreadlight_editor::previews::{MeshCounts, PreviewKey};
    let dir = tempfile::tempdir().expect("tempdir");
    two_tone(&dir, 40, 200);
    let mut p = file_texture_patch("two.png", true, false);
    p.add(spreadlight_graph::NodeDoc::new(3, "Box").at(160.0, 0.0));
    let mut h = editor_on(&p, &dir, Vec2::new(1100.0, 700.0));
    let large = |node: u32, pin: &str| PreviewKey {
        path: vec![spreadlight_graph::NodeId(node)],
        pin: pin.to_owned(),
        channel: None,
        large: true,
    };

    // A texture pin: the large preview shows the texture's pixels, its size, and the centre texel.
    hover_output(&mut h, 1, "Texture");
    let rect = h
        .state()
        .thumbnail_rect(&large(1, "Texture"))
        .expect("the large preview is drawn in the pin's popup");
    assert!(rect.width() > 200.0, "large: {rect:?}");
    let out = h
        .state()
        .preview(&large(1, "Texture"))
        .expect("the worker made it");
    assert_eq!(out.error, None);
    assert_eq!(out.source.map(|s| s.0), Some((64, 36)));
    let (texel, value) = out.value.expect("the centre texel");
    assert_eq!(texel, (32, 18));
    let linear = spreadlight_render::readback::srgb_to_linear(200.0 / 255.0);
    assert!((value[0] - linear).abs() < 0.01, "{value:?}");
    assert!(h.query_by_label_contains("64 × 36").is_some());
    let ppp = h.ctx.pixels_per_point();
    let image = h.render().expect("render the window");
    assert_grey(
        pixel_in(&image, rect, ppp, 0.25, 0.5),
        40,
        "large, left half",
    );
    assert_grey(
        pixel_in(&image, rect, ppp, 0.75, 0.5),
        200,
        "large, right half",
    );

    // A mesh pin: a turntable of the mesh, with its counts (a box: 6 faces of 4 vertices, 2 triangles).
    hover_output(&mut h, 3, "Mesh");
    let out = h
        .state()
        .preview(&large(3, "Mesh"))
        .expect("the worker made the turntable");
    assert_eq!(out.error, None);
    assert_eq!(
        out.mesh,
        Some(MeshCounts {
            meshes: 1,
            vertices: 24,
            triangles: 12
        })
    );
    assert!(
        h.query_by_label_contains("1 mesh · 24 vertices · 12 triangles")
            .is_some()
    );
    let rect = h
        .state()
        .thumbnail_rect(&large(3, "Mesh"))
        .expect("the turntable is drawn");
    let image = h.render().expect("render the window");
    assert!(
        distinct_colours(&image, rect, ppp) > 2,
        "the box's normals, not a blank"
    );
}

/// The thumbnails' schedule (previews/schedule.rs): what a frame of a playing
/// patch refreshes, so that previews do not slow the patch.
mod thumbnail_schedule {
    use spreadlight_editor::previews::PreviewKey;
    use spreadlight_editor::previews::schedule::{BASE_EVERY, BUDGET_SHARE, Candidate, Scheduler};
    use spreadlight_graph::NodeId;

    fn key(node: u32) -> PreviewKey {
        PreviewKey {
            path: vec![NodeId(node)],
            pin: "Output".to_owned(),
            channel: None,
            large: false,
        }
    }

    /// Thumbnails of nodes 1..=n, each showing source `version`.
    fn thumbs(n: u32, version: u32) -> Vec<Candidate<u32>> {
        (1..=n)
            .map(|k| Candidate {
                key: key(k),
                source: Some(version),
                live: false,
            })
            .collect()
    }

    /// Pick, mark the picked as refreshed, measure `base + cost * n` ms.
    fn frame(s: &mut Scheduler<u32>, c: &[Candidate<u32>], base: f64, cost: f64) -> Vec<bool> {
        let picked = s.pick(c, true);
        let mut n = 0;
        for (c, p) in c.iter().zip(&picked) {
            if *p {
                s.refreshed(&c.key, c.source);
                n += usize::from(!c.live);
            }
        }
        s.measured(base + cost * n as f64, n);
        picked
    }

    /// A scheduler that measured a 100 ms frame and 1 ms thumbnails.
    fn measured(base: f64, cost: f64) -> Scheduler<u32> {
        let mut s = Scheduler::default();
        s.measured(base, 0);
        for _ in 0..200 {
            s.measured(base + cost, 1);
        }
        s.measured(base, 0);
        s
    }

    #[test]
    fn the_thumbnails_refreshed_stay_within_the_budget_and_take_turns() {
        // 100 ms frames, 1 ms a thumbnail: 3 ms of budget, three a frame.
        let mut s = measured(100.0, 1.0);
        let first = frame(&mut s, &thumbs(12, 1000), 100.0, 1.0);
        assert!(
            first.iter().all(|p| *p),
            "a thumbnail coming on screen shows at once"
        );
        let mut counts = [0u32; 12];
        let mut refreshed = 0;
        let frames = 40u32;
        for f in 0..frames {
            // A playing patch: every source changes every frame.
            let c = thumbs(12, f);
            let picked = frame(&mut s, &c, 100.0, 1.0);
            for (k, p) in picked.iter().enumerate() {
                counts[k] += u32::from(*p);
                refreshed += usize::from(*p);
            }
        }
        let spent = refreshed as f64; // 1 ms each
        let allowed = BUDGET_SHARE * 100.0 * f64::from(frames);
        assert!(
            spent <= allowed + 1.0,
            "{spent} ms of thumbnails against {allowed} allowed"
        );
        assert!(
            spent >= allowed * 0.9,
            "the budget is used: {spent} of {allowed} ms"
        );
        // Round-robin: each thumbnail gets its turn, none twice before another's once.
        let (min, max) = (counts.iter().min(), counts.iter().max());
        assert!(max.zip(min).is_some_and(|(a, b)| a - b <= 1), "{counts:?}");
        assert_eq!(s.pending(), 12 - 3, "the rest wait for their turn");
    }

    #[test]
    fn on_a_fast_machine_every_thumbnail_refreshes_every_frame() {
        // 16 ms frames, 0.01 ms a thumbnail: 0.48 ms of budget holds all 20.
        let mut s = measured(16.0, 0.01);
        for f in 0..(BASE_EVERY as u32 - 2) {
            let picked = frame(&mut s, &thumbs(20, f), 16.0, 0.01);
            assert!(picked.iter().all(|p| *p), "frame {f}: {picked:?}");
        }
    }

    #[test]
    fn an_unchanged_source_is_skipped() {
        let mut s = measured(100.0, 0.01);
        let first = frame(&mut s, &thumbs(4, 7), 100.0, 0.01);
        assert!(first.iter().all(|p| *p), "first shown: {first:?}");
        // The same sources again: nothing to do, whatever the budget.
        let again = frame(&mut s, &thumbs(4, 7), 100.0, 0.01);
        assert_eq!(again, vec![false; 4]);
        assert_eq!(s.pending(), 0);
        // Paused (no budget) too.
        assert_eq!(s.pick(&thumbs(4, 7), false), vec![false; 4]);
        // One source changes: that one alone.
        let mut c = thumbs(4, 7);
        c[2].source = Some(8);
        assert_eq!(
            frame(&mut s, &c, 100.0, 0.01),
            vec![false, false, true, false]
        );
        // An unknown source is never taken as unchanged.
        let mut c = thumbs(4, 7);
        c[2].source = Some(8);
        c[1].source = None;
        assert_eq!(
            frame(&mut s, &c, 100.0, 0.01),
            vec![false, true, false, false]
        );
    }

    #[test]
    fn the_hovered_preview_is_refreshed_every_frame_whatever_the_budget() {
        // 10 ms a thumbnail against 3 ms of budget a frame.
        let mut s = measured(100.0, 10.0);
        let mut c = thumbs(6, 0);
        c.push(Candidate {
            key: PreviewKey {
                large: true,
                ..key(1)
            },
            source: Some(0),
            live: true,
        });
        for f in 0..30 {
            for t in &mut c {
                t.source = Some(f);
            }
            let picked = frame(&mut s, &c, 100.0, 10.0);
            assert!(picked[6], "frame {f}: the hovered preview is live");
            // Unchanged, it is still live (its texel under the pointer is read from it).
            let again = s.pick(&c, true);
            assert!(again[6]);
        }
    }

    #[test]
    fn a_paused_patch_refreshes_every_changed_thumbnail_at_once() {
        let mut s = measured(100.0, 10.0);
        frame(&mut s, &thumbs(8, 0), 100.0, 10.0);
        let picked = s.pick(&thumbs(8, 1), false);
        assert!(picked.iter().all(|p| *p));
        assert_eq!(s.pending(), 0);
    }

    #[test]
    fn the_patch_frame_is_measured_alone_now_and_then() {
        // A fast machine refreshes all every frame, but not for ever without a base frame.
        let mut s = measured(16.0, 0.01);
        let mut bare = 0;
        for f in 0..(3 * BASE_EVERY as u32) {
            let picked = frame(&mut s, &thumbs(5, f), 16.0, 0.01);
            bare += u32::from(picked.iter().all(|p| !p));
        }
        assert!((2..=4).contains(&bare), "{bare} frames without thumbnails");
        let m = s.measurements();
        assert!(m.base_ms.is_some_and(|b| (b - 16.0).abs() < 1e-6), "{m:?}");
        assert!(m.thumb_ms.is_some_and(|c| (c - 0.01).abs() < 1e-6), "{m:?}");
    }
}
