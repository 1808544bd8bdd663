//! The show window opened from the editor (F11 or the toolbar): the Output's
//! texture in a window of its own, filled or at its native pixel size, and
//! the window the patch's input nodes read while it is open. The harness has
//! no native windows, so egui draws the show window as an egui window in the
//! editor's (egui's embedded viewport); the real window is tested under Xvfb
//! in crates/cli/tests/editor_window.rs.

use crate::common;

use egui::{Key, Vec2};
use egui_kittest::Harness;
use spreadlight_editor::{EditorApp, ShowWindowOptions};
use spreadlight_graph::{NodeDoc, NodeId, Patch, Spread, format};

/// The texture's own size, unlike any window's.
const NATIVE: (u32, u32) = (48, 32);

fn harness(dir: &tempfile::TempDir) -> Harness<'static, EditorApp> {
    let png = dir.path().join("small.png");
    image::RgbaImage::from_fn(NATIVE.0, NATIVE.1, |x, y| {
        image::Rgba([(x * 5) as u8, (y * 7) as u8, 128, 255])
    })
    .save(&png)
    .expect("png");
    let mut p = Patch::default();
    p.add(NodeDoc::new(1, "FileTexture").with("Filename", vec!["small.png".to_owned()]));
    p.add(
        NodeDoc::new(2, "Output")
            .at(120.0, 0.0)
            .with("Write", vec![false]),
    );
    p.link(1, "Texture", 2, "Texture");
    p.add(NodeDoc::new(3, "WindowSize (Window)").at(0.0, 80.0));
    p.add(
        NodeDoc::new(4, "Probe")
            .at(120.0, 80.0)
            .with("Name", vec!["w".to_owned()]),
    );
    p.link(3, "Width", 4, "Input");
    let path = dir.path().join("show.ron");
    format::save(&p, &path).expect("save");
    let options = common::options(Some(path), dir.path().join("config"));
    let mut h = common::editor(options, Vec2::new(1100.0, 700.0));
    h.run_steps(4);
    h
}

fn width(h: &Harness<'_, EditorApp>) -> Spread {
    h.state()
        .runtime()
        .output(NodeId(3), "Width")
        .map(|s| (**s).clone())
        .expect("WindowSize was evaluated")
}

fn press(h: &mut Harness<'_, EditorApp>, key: Key) {
    for pressed in [true, false] {
        common::key_event(h, key, pressed);
    }
    h.run_steps(4);
}

#[test]
fn f11_opens_the_show_window_on_the_output_and_esc_closes_it() {
    let dir = tempfile::tempdir().expect("tempdir");
    let mut h = harness(&dir);
    assert_eq!(h.state().show_window(), None);
    let (editor_w, _) = h.state().viewport_pixels(0).expect("the first viewport");
    assert_eq!(width(&h), Spread::Int(vec![i64::from(editor_w)]));

    press(&mut h, Key::F11);
    let options = h.state().show_window().expect("F11 opened the show window");
    assert!(!options.native && !options.fullscreen, "{options:?}");
    assert_eq!(h.state().viewport_error(2), None);
    let texture = h
        .state()
        .viewport_texture(2)
        .expect("the show window's texture");
    assert_eq!((texture.width(), texture.height()), NATIVE);
    // Filled: the image covers the window, whatever the texture's size.
    let (w, hh) = h.state().show_window_pixels().expect("its size");
    assert_ne!(w, editor_w, "the show window is not the editor's viewport");
    let rect = h.state().show_window_image_rect().expect("drawn");
    let ppp = h.ctx.pixels_per_point();
    assert!(
        (rect.width() * ppp - w as f32).abs() <= 1.0,
        "{rect:?} vs {w}"
    );
    assert!(
        (rect.height() * ppp - hh as f32).abs() <= 1.0,
        "{rect:?} vs {hh}"
    );
    // The patch's WindowSize reads the show window while it is open.
    assert_eq!(width(&h), Spread::Int(vec![i64::from(w)]));

    press(&mut h, Key::Escape);
    assert_eq!(h.state().show_window(), None, "Esc closed it");
    assert_eq!(h.state().show_window_pixels(), None);
    assert_eq!(width(&h), Spread::Int(vec![i64::from(editor_w)]));
}

#[test]
fn at_native_size_the_show_window_draws_the_texture_one_to_one() {
    let dir = tempfile::tempdir().expect("tempdir");
    let mut h = harness(&dir);
    h.state_mut().open_show_window(ShowWindowOptions {
        fullscreen: false,
        native: true,
    });
    h.run_steps(4);
    let rect = h.state().show_window_image_rect().expect("drawn");
    let ppp = h.ctx.pixels_per_point();
    assert_eq!(
        (
            (rect.width() * ppp).round() as u32,
            (rect.height() * ppp).round() as u32
        ),
        NATIVE,
        "one texture pixel per window pixel"
    );
    h.state_mut().close_show_window();
    h.run_steps(2);
    assert_eq!(h.state().show_window_image_rect(), None);
}
