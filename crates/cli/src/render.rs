//! `spreadlight render`: render a patch headless to an image.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{Context, bail};
use spreadlight_render::image_io::write_image;

use crate::session::{Session, parse_size};

#[derive(clap::Args)]
pub struct Args {
    /// The patch to render; it needs an `Output` node.
    patch: PathBuf,
    /// The image to write: PNG, or EXR (32-bit float) when it ends in .exr. `{frame}` in the name writes every frame.
    #[arg(short, long)]
    output: PathBuf,
    /// Output size.
    #[arg(long, default_value = "640x360", value_parser = parse_size)]
    size: (u32, u32),
    /// How many frames to evaluate (the last is written).
    #[arg(long, default_value_t = 1, conflicts_with = "frame")]
    frames: u64,
    /// Render exactly frame K (frames 0..K are evaluated first, so time-dependent patches are deterministic).
    #[arg(long)]
    frame: Option<u64>,
    /// Frames per second of the clock.
    #[arg(long, default_value_t = 60.0)]
    fps: f64,
    /// Which `Output` node to write, by its Name (the only one, when there is one).
    #[arg(long = "output-name")]
    output_name: Option<String>,
}

pub fn run(args: &Args) -> anyhow::Result<ExitCode> {
    if !(args.fps.is_finite() && args.fps > 0.0) {
        bail!("--fps must be a positive number");
    }
    let mut session = Session::open(&args.patch, true, Some(args.size))?;
    let renderer = session.renderer.clone().context("no renderer")?;
    eprintln!(
        "rendering {} at {}x{} on {}",
        args.patch.display(),
        args.size.0,
        args.size.1,
        renderer.gpu.adapter_name()
    );
    let last = args.frame.unwrap_or(args.frames.max(1) - 1);
    let per_frame = args.output.to_string_lossy().contains("{frame}");
    let mut reported = BTreeSet::new();
    let mut failed = session.load_errors;
    for frame in 0..=last {
        failed |= session.step(frame, args.fps, &args.patch, &mut reported);
        if last >= 10 && frame % 10 == 0 {
            eprintln!("frame {frame}/{last}");
        }
        if per_frame || frame == last {
            let path = PathBuf::from(
                args.output
                    .to_string_lossy()
                    .replace("{frame}", &format!("{frame:05}")),
            );
            write_output(&session, args.output_name.as_deref(), &path)?;
        }
    }
    if let Some(ms) = renderer.last_report().gpu_ms {
        eprintln!(
            "last frame: {ms:.3} ms GPU on {}",
            renderer.gpu.adapter_name()
        );
    }
    Ok(if failed {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    })
}

fn write_output(session: &Session, name: Option<&str>, path: &Path) -> anyhow::Result<()> {
    let names = session.images.names();
    let name = match (name, names.as_slice()) {
        (Some(n), _) => n.to_owned(),
        (None, [only]) => only.clone(),
        (None, []) => bail!(
            "the patch rendered nothing: it needs an `Output` node fed by a texture (see the errors above)"
        ),
        (None, many) => bail!(
            "the patch has several outputs ({}); pick one with --output-name",
            many.join(", ")
        ),
    };
    let (image, encoding) = session.images.get(&name).with_context(|| {
        format!(
            "no Output node named `{name}` rendered (outputs: {})",
            names.join(", ")
        )
    })?;
    write_image(&image, path, encoding)?;
    eprintln!("wrote {}", path.display());
    Ok(())
}
