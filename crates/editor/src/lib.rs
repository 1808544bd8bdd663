//! Spreadlight's patch editor: eframe and egui-snarl over the shared renderer.
//!
//! The model ([`model::EditorDoc`]) is plain data with an undo history of
//! typed commands; the canvas ([`canvas`]) is a projection of it; the app
//! ([`app::EditorApp`]) ties them to the runtime, the viewports and the files.

pub mod app;
pub mod browser;
pub mod canvas;
pub mod canvas_units;
pub mod files;
pub mod gpu;
pub mod iobox;
pub mod model;
pub mod module_file;
pub mod module_scope;
pub mod monitors;
pub mod nodes;
pub mod organise;
pub mod previews;
pub mod recording;
pub mod shader_watch;
pub mod subpatch;
pub mod values;
pub mod viewport;
pub mod worker;
pub mod zoom;

pub use app::{EditorApp, EditorOptions, HelpLaunch, ShowWindowOptions};
pub use model::edits::Clip;
pub use model::links::LinkError;
pub use model::{Command, EditorDoc};
pub use worker::FrameWait;

use std::path::PathBuf;
use std::sync::{Arc, Mutex};

use thiserror::Error;

#[derive(Debug, Error)]
pub enum EditorError {
    #[error("cannot open the editor window: {0}")]
    Window(String),
    #[error("{0}")]
    Monitor(String),
}

/// Open the editor window and run until it closes.
pub fn run(options: EditorOptions) -> Result<(), EditorError> {
    let viewport = egui::ViewportBuilder::default()
        .with_inner_size([1600.0, 900.0])
        .with_title("Spreadlight");
    run_window(viewport, options)
}

/// How the show window opens.
#[derive(Clone, Debug, Default)]
pub struct ShowWindow {
    /// Its inner size in points (the Output renders at its pixel size); 1280x720 by default.
    pub size: Option<(u32, u32)>,
    /// Fullscreen on the monitor the window opens on.
    pub fullscreen: bool,
    /// The monitor to open on (as `spreadlight play --monitor` numbers them);
    /// without it, the `Monitor` pin of the patch's `Output` decides.
    pub monitor: Option<usize>,
    /// The window takes the Output texture's own pixel size and shows it 1:1.
    pub native: bool,
    /// Record what the window shows to this video file from the first frame
    /// (`spreadlight play --record`); Ctrl+R starts and stops one too.
    pub record: Option<PathBuf>,
    /// Step the clock by 1/fps each frame instead of by the wall clock, and
    /// wait for every patch frame: a deterministic run (`--fps`), recorded
    /// frame for frame and with exact video decoding.
    pub fps: Option<f64>,
}

/// Run a patch in a borderless show window alone (no editor) until it closes.
/// The window moves to its monitor on its first frame (`monitors.rs`).
pub fn play(options: EditorOptions, window: ShowWindow) -> Result<(), EditorError> {
    let (w, h) = window.size.unwrap_or((1280, 720));
    let viewport = egui::ViewportBuilder::default()
        .with_inner_size([w as f32, h as f32])
        .with_decorations(false)
        .with_fullscreen(window.fullscreen && window.monitor.is_none())
        .with_title("Spreadlight show");
    let native = native_options(viewport);
    let event_loop = winit::event_loop::EventLoop::<eframe::UserEvent>::with_user_event()
        .build()
        .map_err(|e| EditorError::Window(e.to_string()))?;
    let found = monitors::Found::default();
    let failure = Arc::new(Mutex::new(None));
    let (app_found, app_failure) = (found.clone(), failure.clone());
    let app = eframe::create_native(
        "Spreadlight",
        native,
        Box::new(move |cc| {
            let mut app = EditorApp::new(cc, options);
            app.set_show_mode(true);
            app.set_show_window(window, app_found, app_failure);
            Ok(Box::new(app))
        }),
        &event_loop,
    );
    let mut handler = monitors::Listing::new(app, found);
    event_loop
        .run_app(&mut handler)
        .map_err(|e| EditorError::Window(e.to_string()))?;
    match failure.lock().unwrap_or_else(|e| e.into_inner()).take() {
        Some(message) => Err(EditorError::Monitor(message)),
        None => Ok(()),
    }
}

fn native_options(viewport: egui::ViewportBuilder) -> eframe::NativeOptions {
    eframe::NativeOptions {
        viewport,
        renderer: eframe::Renderer::Wgpu,
        wgpu_options: egui_wgpu::WgpuConfiguration {
            wgpu_setup: gpu::wgpu_setup(false),
            ..Default::default()
        },
        ..Default::default()
    }
}

fn run_window(viewport: egui::ViewportBuilder, options: EditorOptions) -> Result<(), EditorError> {
    eframe::run_native(
        "Spreadlight",
        native_options(viewport),
        Box::new(move |cc| Ok(Box::new(EditorApp::new(cc, options)))),
    )
    .map_err(|e| EditorError::Window(e.to_string()))
}
