//! `spreadlight nodes`: the node types this build knows, listed by category,
//! one documented in full (`--help NAME`), or all as markdown (`--markdown`,
//! what docs/nodes.md holds).

use std::process::ExitCode;

use clap::{CommandFactory, Parser};

#[derive(Parser, Debug, Default)]
#[command(disable_help_flag = true)]
pub struct Args {
    /// Document one node type: its category, help, and pins with types and defaults
    /// (`--help "GetSlice (Spreads)"`; any case, or a part of the name that only one type has).
    /// Without NAME, this help.
    #[arg(short = 'h', long = "help", value_name = "NAME", num_args = 0..=1)]
    help: Option<Option<String>>,
    /// Print every node type's documentation as markdown (docs/nodes.md).
    #[arg(long)]
    markdown: bool,
}

pub fn run(args: &Args) -> anyhow::Result<ExitCode> {
    // The built-in types, the shipped shader examples and the user's shader library.
    let (registry, errors) = crate::session::registry_for(None);
    for error in errors {
        eprintln!("{error}");
    }
    match &args.help {
        Some(None) => {
            Args::command().name("spreadlight nodes").print_help()?;
            return Ok(ExitCode::SUCCESS);
        }
        Some(Some(name)) => {
            return Ok(match spreadlight_nodes::docs::find(&registry, name) {
                Ok(def) => {
                    print!("{}", spreadlight_nodes::docs::help_text(def));
                    // The same table F1 in the editor opens help patches from.
                    match spreadlight_nodes::help::for_type(&def.name) {
                        Some(help) => {
                            println!("\nHelp patch: {}", help.path());
                            if let Some(file) = help.source_file() {
                                println!("  {}", file.display());
                            }
                            println!("  (F1 on the node in the editor opens it, read-only)");
                        }
                        None => println!("\nHelp patch: none yet"),
                    }
                    ExitCode::SUCCESS
                }
                Err(candidates) if candidates.is_empty() => {
                    eprintln!(
                        "error: no node type named `{name}` (`spreadlight nodes` lists them)"
                    );
                    ExitCode::from(1)
                }
                Err(candidates) => {
                    eprintln!(
                        "error: `{name}` names several node types: {}",
                        candidates.join(", ")
                    );
                    ExitCode::from(1)
                }
            });
        }
        None => {}
    }
    if args.markdown {
        // The documented set is the build's own, whatever the user's library holds.
        print!(
            "{}",
            spreadlight_nodes::docs::markdown(&spreadlight_nodes::registry())
        );
        return Ok(ExitCode::SUCCESS);
    }
    list(&registry);
    Ok(ExitCode::SUCCESS)
}

fn list(registry: &spreadlight_graph::Registry) {
    let mut defs: Vec<_> = registry.iter().collect();
    defs.sort_by(|a, b| (&a.category, &a.name).cmp(&(&b.category, &b.name)));
    let mut category = "";
    for def in defs {
        if def.category != category {
            category = &def.category;
            println!("{category}");
        }
        let pins = |pins: &[spreadlight_graph::PinDef]| {
            pins.iter()
                .map(|p| format!("{}: {}", p.name, p.ty))
                .collect::<Vec<_>>()
                .join(", ")
        };
        println!(
            "  {:<28} ({}) -> ({})",
            def.name,
            pins(&def.inputs),
            pins(&def.outputs)
        );
    }
}
