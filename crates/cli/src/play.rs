//! `spreadlight play`: run a patch in a borderless show window, no editor.

use std::path::PathBuf;
use std::process::ExitCode;

use spreadlight_editor::app::Automation;
use spreadlight_editor::{EditorOptions, ShowWindow};

#[derive(clap::Args)]
pub struct Args {
    /// The patch to play; the window shows its `Output`.
    patch: PathBuf,
    /// The window's size, WIDTHxHEIGHT (1280x720 by default); the Output renders at its pixel size.
    #[arg(long, value_parser = crate::session::parse_size)]
    size: Option<(u32, u32)>,
    /// Fill the monitor the window opens on.
    #[arg(long)]
    fullscreen: bool,
    /// Open on this monitor (0, 1, ... as the window system lists them); by
    /// default the `Monitor` pin of the patch's Output decides.
    #[arg(long, value_name = "N")]
    monitor: Option<usize>,
    /// Size the window to the Output texture's own pixel size and show it
    /// 1:1 (a texture that follows the window's size keeps the window's).
    #[arg(long)]
    native: bool,
    /// Run this many frames, print the frame times as JSON, and quit (as `edit` does).
    #[arg(long, value_name = "FRAMES")]
    measure_frames: Option<u32>,
    /// After the frames, write a screenshot of the window (PNG) here and quit.
    #[arg(long, value_name = "PNG")]
    screenshot: Option<PathBuf>,
    /// Record what the window shows to this video file (.mp4, .mkv, .mov)
    /// from the first frame until the window closes; Ctrl+R stops and starts
    /// recording too. The sound of the patch's AudioFile is muxed in.
    #[arg(long, value_name = "VIDEO")]
    record: Option<PathBuf>,
    /// Step the clock by 1/FPS each frame instead of following the wall clock,
    /// waiting for every patch frame: deterministic, and recorded frame for frame.
    #[arg(long, value_name = "FPS", value_parser = positive_fps)]
    fps: Option<f64>,
}

fn positive_fps(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(fps) if fps.is_finite() && fps > 0.0 && fps <= 1000.0 => Ok(fps),
        _ => Err(format!("`{s}` is not a frame rate from above 0 to 1000")),
    }
}

pub fn run(args: &Args) -> anyhow::Result<ExitCode> {
    anyhow::ensure!(
        args.patch.is_file(),
        "{}: no such patch file",
        args.patch.display()
    );
    let mut options = EditorOptions::new(Some(args.patch.clone()));
    if args.measure_frames.is_some() || args.screenshot.is_some() {
        options.automation = Some(Automation {
            frames: args.measure_frames.unwrap_or(30),
            screenshot: args.screenshot.clone(),
        });
    }
    if args.fps.is_some() {
        options.frame_wait = spreadlight_editor::FrameWait::Always;
    }
    let window = ShowWindow {
        size: args.size,
        fullscreen: args.fullscreen,
        monitor: args.monitor,
        native: args.native,
        record: args.record.clone(),
        fps: args.fps,
    };
    spreadlight_editor::play(options, window)?;
    Ok(ExitCode::SUCCESS)
}
