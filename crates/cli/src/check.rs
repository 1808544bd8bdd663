//! `spreadlight check`: load patches and print every problem.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::Context;
use spreadlight_graph::subpatch::Library;
use spreadlight_graph::{Network, Severity, format};

#[derive(clap::Args)]
pub struct Args {
    /// Patch files, or folders whose `.ron` files are all checked.
    #[arg(required = true)]
    paths: Vec<PathBuf>,
    /// Count warnings (e.g. unknown node types kept as placeholders) as errors.
    #[arg(long)]
    deny_warnings: bool,
    /// Pass a patch even though an unknown node type (misspelled, or a shader
    /// or subpatch file that is missing) feeds its Output or a Probe: as a
    /// warning, as the editor takes it. Without it such a patch is an error,
    /// as `render` would refuse it.
    #[arg(long)]
    pub allow_unknown: bool,
}

pub fn run(args: &Args) -> anyhow::Result<ExitCode> {
    let mut files = Vec::new();
    for path in &args.paths {
        files.extend(expand(path)?);
    }
    let (mut errors, mut warnings) = (0usize, 0usize);
    for file in &files {
        match format::load(file) {
            Err(e) => {
                println!("error: {e}");
                errors += 1;
            }
            Ok(patch) => {
                // Shader files beside the patch are node types; a broken one is an error.
                let (registry, shader_errors) = crate::session::registry_for(Some(file));
                for error in &shader_errors {
                    println!("{error}");
                }
                errors += shader_errors.len();
                // Subpatches are checked where they are used, with the files beside the patch.
                let library = Library::beside(file.parent().unwrap_or(Path::new("")));
                let network = Network::compile_with(&patch, &registry, &library);
                for problem in network.problems() {
                    let (severity, line) =
                        crate::session::headless_problem(problem, file, args.allow_unknown);
                    println!("{line}");
                    match severity {
                        Severity::Error => errors += 1,
                        Severity::Warning => warnings += 1,
                    }
                }
            }
        }
    }
    let failed = errors > 0 || (args.deny_warnings && warnings > 0);
    eprintln!(
        "checked {} patch(es): {errors} error(s), {warnings} warning(s)",
        files.len()
    );
    Ok(if failed {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    })
}

/// A file as itself; a folder as its `.ron` files, sorted so output is stable.
fn expand(path: &Path) -> anyhow::Result<Vec<PathBuf>> {
    if !path.is_dir() {
        return Ok(vec![path.to_owned()]);
    }
    let mut files = Vec::new();
    for entry in
        std::fs::read_dir(path).with_context(|| format!("cannot list {}", path.display()))?
    {
        let entry = entry.with_context(|| format!("cannot list {}", path.display()))?;
        let p = entry.path();
        if p.extension().is_some_and(|e| e == "ron") && p.is_file() {
            files.push(p);
        }
    }
    files.sort();
    if files.is_empty() {
        anyhow::bail!("{}: the folder holds no .ron patches", path.display());
    }
    Ok(files)
}
