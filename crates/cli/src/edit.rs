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
    /// The smallest zoom fitting the view may go to (0.1 to 1; 0.75, where titles stay
    /// readable, by default). Lower shows a bigger patch whole, e.g. every thumbnail of
    /// `patches/post.ron` for a `--measure-frames` run.
    #[arg(long, value_name = "ZOOM", value_parser = parse_zoom)]
    min_zoom: Option<f32>,
    /// Open with time stopped (▶ Play starts it): the patch evaluates on edits and Step only.
    /// With `--measure-frames`, the UI's own cost without the patch running beside it.
    #[arg(long)]
    paused: bool,
}

fn parse_zoom(text: &str) -> Result<f32, String> {
    let zoom: f32 = text
        .parse()
        .map_err(|e| format!("`{text}` is not a number: {e}"))?;
    if (0.1..=1.0).contains(&zoom) {
        Ok(zoom)
    } else {
        Err(format!(
            "{zoom} is outside the canvas's zoom range, 0.1 to 1"
        ))
    }
}

pub fn run(args: &Args) -> anyhow::Result<ExitCode> {
    let mut options = EditorOptions::new(args.patch.clone());
    options.read_only = args.read_only;
    options.paused = args.paused;
    if let Some(zoom) = args.min_zoom {
        options.min_zoom = zoom;
    }
    if args.measure_frames.is_some() || args.screenshot.is_some() {
        options.automation = Some(Automation {
            frames: args.measure_frames.unwrap_or(30),
            screenshot: args.screenshot.clone(),
        });
    }
    spreadlight_editor::run(options)?;
    Ok(ExitCode::SUCCESS)
}
