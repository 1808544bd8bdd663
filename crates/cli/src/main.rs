//! `spreadlight`: the command-line edge of Spreadlight. It loads patches,
//! reports their problems with file and node, and evaluates them headless.
//! Exit codes: 0 clean, 1 the patch has errors (for `render`: some frames
//! failed), 2 usage errors (clap's own; for `render`: any bad input).

mod accuracy;
mod bench;
mod check;
mod cold_start;
mod edit;
mod eval;
mod fmt;
mod node_cpu;
mod nodes;
mod orbit;
mod pin_arg;
mod play;
mod sequence;
mod session;
mod stats;
mod view;

use std::process::ExitCode;

/// A frame allocates and frees many small blocks (recipes, maps, wgpu's
/// command encoding); with glibc's allocator malloc and free were a sixth of
/// a frame's CPU on the main thread (docs/benchmarks.md, "Session 10: CPU").
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

use clap::{Parser, Subcommand};

#[derive(Parser)]
#[command(
    name = "spreadlight",
    version,
    about = "Spreadlight: node-based real-time deferred rendering"
)]
struct Cli {
    /// Without a command, the editor opens on an empty patch.
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Subcommand)]
enum Command {
    /// Open the patch editor (a window), on PATCH or on an empty patch.
    Edit(edit::Args),
    /// Load and validate patches; print every problem with its file, node and pin.
    Check(check::Args),
    /// Evaluate a patch headless for a number of frames and print what its probes recorded.
    Eval(eval::Args),
    /// Render a patch headless: one image, a frame sequence (PNG/EXR, resumable, in chunks) or a video.
    Render(sequence::Args),
    /// Render a glTF file lit (sun, shadow, sky light), a camera framing it; or one G-buffer channel.
    View(view::Args),
    /// Print a frame's statistics: runtime counts, passes executed and culled, compiles, draws, GPU times.
    Stats(stats::Args),
    /// Time a patch's frames on the GPU (timestamp queries; medians; the adapter named).
    Bench(bench::Args),
    /// What accuracy costs: GPU time against error versus a CPU reference, per quality setting.
    Accuracy(accuracy::Args),
    /// Rewrite patches in the canonical layout (what saving writes).
    Fmt(fmt::Args),
    /// List the node types this build knows, by category (`--help NAME` documents one).
    Nodes(nodes::Args),
    /// Run a patch in a borderless show window alone (no editor): its Output at the window's size.
    Play(play::Args),
}

fn main() -> ExitCode {
    cold_start::mark_process_start();
    // SAFETY: no other thread runs yet (nothing before this line starts
    // one); it may set the driver's environment.
    #[allow(unsafe_code)]
    unsafe {
        spreadlight_render::pipeline_cache::prefer_kept_pipelines();
    }
    let cli = Cli::parse();
    let result = match cli.command {
        None => edit::run(&edit::Args::default()),
        Some(Command::Edit(args)) => edit::run(&args),
        Some(command) => run_command(command),
    };
    match result {
        Ok(code) => code,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::from(1)
        }
    }
}

fn run_command(command: Command) -> anyhow::Result<ExitCode> {
    match command {
        Command::Edit(args) => edit::run(&args),
        Command::Check(args) => check::run(&args),
        Command::Eval(args) => eval::run(&args),
        Command::Fmt(args) => fmt::run(&args),
        Command::Render(args) => sequence::run(&args),
        Command::View(args) => view::run(&args),
        Command::Stats(args) => stats::run(&args),
        Command::Bench(args) => bench::run(&args),
        Command::Accuracy(args) => accuracy::run(&args),
        Command::Nodes(args) => nodes::run(&args),
        Command::Play(args) => play::run(&args),
    }
}
