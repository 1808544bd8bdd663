//! `spreadlight edit`: the patch editor window.

use std::path::PathBuf;
use std::process::ExitCode;

use spreadlight_editor::EditorOptions;
use spreadlight_editor::app::Automation;

#[derive(clap::Args, Default)]
pub struct Args {
    /// The patch to open; an empty patch without one.
    patch: Option<PathBuf>,
    /// Run this many frames (repainting continuously), print the UI frame times as JSON, and quit.
    #[arg(long, value_name = "FRAMES")]
    measure_frames: Option<u32>,
    /// After the frames, write a screenshot of the window (PNG) here and quit; prints where the viewport is.
    #[arg(long, value_name = "PNG")]
    screenshot: Option<PathBuf>,
    /// Open the patch read-only (as F1 opens a help patch): every edit is undone at once.
    #[arg(long)]
    read_only: bool,
}

pub fn run(args: &Args) -> anyhow::Result<ExitCode> {
    let mut options = EditorOptions::new(args.patch.clone());
    options.read_only = args.read_only;
    if args.measure_frames.is_some() || args.screenshot.is_some() {
        options.automation = Some(Automation {
            frames: args.measure_frames.unwrap_or(30),
            screenshot: args.screenshot.clone(),
        });
    }
    spreadlight_editor::run(options)?;
    Ok(ExitCode::SUCCESS)
}
