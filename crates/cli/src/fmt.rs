//! `spreadlight fmt`: rewrite patches in the canonical layout that saving
//! produces (atomically), or with `--check` only report those that differ.

use std::path::PathBuf;
use std::process::ExitCode;

use spreadlight_graph::format;

#[derive(clap::Args)]
pub struct Args {
    /// Patch files to rewrite.
    #[arg(required = true)]
    paths: Vec<PathBuf>,
    /// Change nothing; exit 1 if any patch is not in canonical form.
    #[arg(long)]
    check: bool,
}

pub fn run(args: &Args) -> anyhow::Result<ExitCode> {
    let mut differ = 0;
    for path in &args.paths {
        let text = std::fs::read_to_string(path).map_err(|source| format::FormatError::Read {
            path: path.clone(),
            source,
        })?;
        let patch = format::from_str(&text, path)?;
        if format::to_string(&patch)? == text {
            continue;
        }
        differ += 1;
        if args.check {
            println!("{}: not in canonical form", path.display());
        } else {
            format::save(&patch, path)?;
            println!("{}: rewritten", path.display());
        }
    }
    Ok(if args.check && differ > 0 {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    })
}
