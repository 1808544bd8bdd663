//! Subpatches: a patch used as a node of another, as vvvv's modules are.
//!
//! A subpatch is an ordinary patch document whose IOBoxes (`Inlet`, `Outlet`)
//! become the pins of a node in its parent, named by their `Name` and typed by
//! what they are linked to inside ([`pins`]). It is defined inline in the
//! parent (`Patch::subpatches`, by type name) or by a file `NAME.ron` in the
//! folders of a [`Library`] (`modules/` beside the patch, then the user's
//! library); the node's type is the subpatch's name.
//!
//! Compiling flattens ([`flatten`]): every instance's inside is copied into
//! one flat network with ids of its own, so demand, caching, per-instance
//! state and statistics work node by node through subpatches, exactly as in a
//! patch without them. Problems inside a subpatch name the chain of subpatch
//! nodes they lie in (`Problem::within`). The documents are never changed: a
//! node whose subpatch file is missing stays an unknown-type placeholder with
//! its values and links; a recursive one is an error naming the chain.

mod flatten;
mod library;
mod pins;

pub use library::{LIBRARY_ENV, Library, LibraryEntry, MODULES_DIR, user_library_dir};
pub use pins::{INLET, OUTLET, ioboxes, is_iobox, pin_name, register};

use crate::diagnostics::ProblemKind;
use crate::document::{NodeId, Patch};
use crate::network::{CompileExtras, Network};
use crate::registry::{NodeDef, Registry};
use crate::value::PinType;

impl Network {
    /// Compile a patch whose subpatches are all inline (or absent); see
    /// [`Network::compile_with`] for subpatch files.
    pub fn compile(patch: &Patch, registry: &Registry) -> Network {
        Self::compile_with(patch, registry, &Library::default())
    }

    /// Compile a patch, expanding its subpatches (inline, or files from `library`).
    pub fn compile_with(patch: &Patch, registry: &Registry, library: &Library) -> Network {
        compile(patch, registry, library)
    }
}

/// Flatten and compile a patch; problems are placed in the documents they concern.
fn compile(patch: &Patch, registry: &Registry, library: &Library) -> Network {
    let mut flat = flatten::flatten(patch, registry, library);
    let typed = pins::type_ioboxes(&flat.patch, registry);
    flatten::short_circuit(&mut flat, &typed);
    let extras = CompileExtras {
        defs: pins::iobox_defs(&mut flat.patch, &typed),
        link_labels: &flat.link_labels,
        expanded: is_subpatch_def,
    };
    let mut network = Network::compile_flat(&flat.patch, registry, &extras);
    let located = |id: NodeId| flat.paths.get(&id).cloned().unwrap_or_else(|| vec![id]);
    let mut problems = flat.problems.clone();
    for mut problem in std::mem::take(network.problems_mut()) {
        if matches!(problem.kind, ProblemKind::UnknownNodeType { .. })
            && flat.explained.contains(&problem.node)
        {
            continue;
        }
        // The fed sink as the documents know it, not by its flat id.
        if let ProblemKind::UnknownNodeType {
            feeds: Some(sink), ..
        } = &mut problem.kind
            && let [flat_id] = sink.path[..]
        {
            sink.path = located(flat_id);
        }
        let fed = flat.fed_inlets.get(&problem.node);
        let path = match (fed, problem.pin.as_deref()) {
            // A parent's value or link on a subpatch pin: the parent's problem.
            (Some(fed), Some("Input")) => {
                problem.pin = Some(fed.pin.clone());
                problem.node_type = fed.node_type.clone();
                fed.path.clone()
            }
            _ => located(problem.node),
        };
        if let ProblemKind::Cycle { path: cycle, .. } = &mut problem.kind {
            // Each node of the cycle as its ancestor at the problem's depth.
            let depth = path.len() - 1;
            for id in cycle.iter_mut() {
                let p = located(*id);
                *id = p.get(depth).copied().unwrap_or(*p.last().unwrap_or(id));
            }
        }
        if let Some((last, within)) = path.split_last() {
            problem.node = *last;
            problem.within = within.to_vec();
        }
        problems.push(problem);
    }
    *network.problems_mut() = problems;
    network.set_paths(flat.paths, flat.instance_outputs);
    network
}

/// The pins a subpatch definition gives its node: one per `Inlet` and per
/// `Outlet`, in order, typed from their links inside.
pub fn pins_of(
    definition: &Patch,
    registry: &Registry,
    library: &Library,
) -> (Vec<SubpatchPin>, Vec<SubpatchPin>) {
    let flat = flatten::flatten(definition, registry, library);
    let typed = pins::type_ioboxes(&flat.patch, registry);
    let pin = |node: &crate::document::NodeDoc| {
        let (ty, default) = typed
            .get(&node.id)
            .cloned()
            .unwrap_or((PinType::Any, crate::Spread::Float(Vec::new())));
        SubpatchPin {
            name: pin_name(node),
            ty,
            default,
        }
    };
    let mut seen = std::collections::HashSet::new();
    let inputs = ioboxes(definition, INLET)
        .into_iter()
        .map(pin)
        .filter(|p| seen.insert(p.name.clone()))
        .collect();
    seen.clear();
    let outputs = ioboxes(definition, OUTLET)
        .into_iter()
        .map(pin)
        .filter(|p| seen.insert(p.name.clone()))
        .collect();
    (inputs, outputs)
}

/// The browser category of subpatch types.
pub const CATEGORY: &str = "Subpatches";

/// Whether a registry entry stands for a subpatch (made by [`node_def`]):
/// compiling expands those instead of running them.
pub fn is_subpatch_def(def: &NodeDef) -> bool {
    def.category == CATEGORY
}

/// A registry entry for a subpatch type, so hosts list and draw its nodes as
/// any other: its pins from [`pins_of`]. It never runs: compiling expands it.
pub fn node_def(
    name: &str,
    definition: &Patch,
    registry: &Registry,
    library: &Library,
    source: &str,
) -> NodeDef {
    let (inputs, outputs) = pins_of(definition, registry, library);
    let help = format!("A subpatch ({source}): double-click it to open it.");
    let mut def = NodeDef::new(name.to_owned(), CATEGORY, help);
    for pin in inputs {
        def = def.input_spread(pin.name, pin.ty, pin.default);
    }
    for pin in outputs {
        def = def.output_typed(pin.name, pin.ty);
    }
    def
}

/// A pin of a subpatch's node.
#[derive(Clone, Debug, PartialEq)]
pub struct SubpatchPin {
    pub name: String,
    pub ty: PinType,
    /// What an input pin holds when the parent neither links nor sets it.
    pub default: crate::Spread,
}
