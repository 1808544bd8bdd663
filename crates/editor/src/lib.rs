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
pub mod subpatch;
pub mod values;
pub mod viewport;

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
    let native = eframe::NativeOptions {
        viewport: egui::ViewportBuilder::default()
            .with_inner_size([1600.0, 900.0])
            .with_title("Spreadlight"),
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
        Box::new(move |cc| Ok(Box::new(EditorApp::new(cc, options)))),
    )
    .map_err(|e| EditorError::Window(e.to_string()))
}
