//! The editor under kittest, as the editor's tests build it: on the device
//! egui draws with, paused (a paused patch settles, so `run` returns; tests
//! that need time step it), each frame showing the patch as of that frame.
//! Each test file uses a part of this, hence the allow.
#![allow(dead_code)]

use std::path::PathBuf;

use egui::Vec2;
use egui_kittest::Harness;
use spreadlight_editor::{EditorApp, EditorOptions, FrameWait};

/// Options for `path` (None: an empty patch) with settings under
/// `config_dir`: no autosave, no automation. Each frame shows the patch as
/// of that frame (deterministic); the patch still runs on its worker thread.
pub fn options(path: Option<PathBuf>, config_dir: PathBuf) -> EditorOptions {
    EditorOptions {
        path,
        config_dir,
        autosave_secs: 0.0,
        automation: None,
        frame_wait: FrameWait::Always,
        read_only: false,
        min_zoom: spreadlight_editor::canvas::READABLE_ZOOM,
        paused: false,
    }
}

/// The editor in a `size` window, paused, before its first frame.
pub fn editor(options: EditorOptions, size: Vec2) -> Harness<'static, EditorApp> {
    editor_with(options, size, 40, |_| {})
}

/// `key` pressed (or let go), with no modifiers; no frame run.
pub fn key_event(h: &mut Harness<'_, EditorApp>, key: egui::Key, pressed: bool) {
    h.event(egui::Event::Key {
        key,
        physical_key: None,
        pressed,
        repeat: false,
        modifiers: egui::Modifiers::NONE,
    });
}

/// [`editor`] with `max_steps` for `run` and `setup` applied to the app.
pub fn editor_with(
    options: EditorOptions,
    size: Vec2,
    max_steps: u64,
    setup: impl FnOnce(&mut EditorApp) + 'static,
) -> Harness<'static, EditorApp> {
    Harness::builder()
        .with_size(size)
        .with_max_steps(max_steps)
        .wgpu_setup(spreadlight_editor::gpu::wgpu_setup(true))
        .build_eframe(move |cc| {
            let mut app = EditorApp::new(cc, options);
            app.set_playing(false);
            setup(&mut app);
            app
        })
}
