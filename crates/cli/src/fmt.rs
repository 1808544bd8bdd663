//! `spreadlight fmt`: rewrite patches in the canonical layout that saving
//! produces (atomically), or with `--check` only report those that differ.
//! With `--layout`, the nodes are laid out as the editor's layout key does
//! (and comments stacked above them) before writing.

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
    /// Lay the nodes out (layered, left to right in data-flow order, no
    /// overlaps), fit frames to their nodes and stack comments above them.
    #[arg(long)]
    layout: bool,
}

pub fn run(args: &Args) -> anyhow::Result<ExitCode> {
    let mut differ = 0;
    for path in &args.paths {
        let text = std::fs::read_to_string(path).map_err(|source| format::FormatError::Read {
            path: path.clone(),
            source,
        })?;
        let mut patch = format::from_str(&text, path)?;
        if args.layout {
            let registry = spreadlight_editor::organise::tidy::registry_for(path, &patch);
            spreadlight_editor::organise::tidy::tidy(&mut patch, &registry);
        }
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
