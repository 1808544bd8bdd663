//! The viewports and the GPU timings, on the showcase patch: rendered by the
//! shared renderer on the device the harness's egui draws with.

mod common;

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
