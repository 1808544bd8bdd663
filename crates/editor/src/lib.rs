//! Spreadlight's patch editor: eframe and egui-snarl over the shared renderer.
//!
//! The model ([`model::EditorDoc`]) is plain data with an undo history of
//! typed commands; the canvas ([`canvas`]) is a projection of it; the app
//! ([`app::EditorApp`]) ties them to the runtime, the viewports and the files.

pub mod app;
pub mod browser;
pub mod canvas;
pub mod files;
pub mod gpu;
pub mod iobox;
pub mod model;
pub mod nodes;
pub mod shader_watch;
pub mod subpatch;
pub mod values;
pub mod viewport;
pub mod zoom;

pub use app::{EditorApp, EditorOptions};
pub use model::{Clip, Command, EditorDoc, LinkError};

use thiserror::Error;

#[derive(Debug, Error)]
pub enum EditorError {
    #[error("cannot open the editor window: {0}")]
    Window(String),
}

/// Open the editor window and run until it closes.
pub fn run(options: EditorOptions) -> Result<(), EditorError> {
    let viewport = egui::ViewportBuilder::default()
        .with_inner_size([1600.0, 900.0])
        .with_title("Spreadlight");
    run_window(viewport, options, false)
}

/// How the show window opens.
#[derive(Clone, Copy, Debug, Default)]
pub struct ShowWindow {
    /// Its inner size in points (the Output renders at its pixel size); 1280x720 by default.
    pub size: Option<(u32, u32)>,
    /// Fullscreen on the monitor the window opens on.
    pub fullscreen: bool,
}

/// Run a patch in a borderless show window alone (no editor) until it closes.
pub fn play(options: EditorOptions, window: ShowWindow) -> Result<(), EditorError> {
    let (w, h) = window.size.unwrap_or((1280, 720));
    let viewport = egui::ViewportBuilder::default()
        .with_inner_size([w as f32, h as f32])
        .with_decorations(false)
        .with_fullscreen(window.fullscreen)
        .with_title("Spreadlight show");
    run_window(viewport, options, true)
}

fn run_window(
    viewport: egui::ViewportBuilder,
    options: EditorOptions,
    show: bool,
) -> Result<(), EditorError> {
    let native = eframe::NativeOptions {
        viewport,
        renderer: eframe::Renderer::Wgpu,
        wgpu_options: egui_wgpu::WgpuConfiguration {
            wgpu_setup: gpu::wgpu_setup(false),
            ..Default::default()
        },
        ..Default::default()
    };
    eframe::run_native(
        "Spreadlight",
        native,
        Box::new(move |cc| {
            let mut app = EditorApp::new(cc, options);
            app.set_show_mode(show);
            Ok(Box::new(app))
        }),
    )
    .map_err(|e| EditorError::Window(e.to_string()))
}
