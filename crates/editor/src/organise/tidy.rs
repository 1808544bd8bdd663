//! Tidying a patch file, as `spreadlight fmt --layout` does: every node of
//! the patch and of its inline subpatches laid out ([`super::layout`]),
//! frames fitted again around the nodes they held, comments in a column
//! above the nodes. Sizes come from the editor's own measure, with the
//! subpatch types the patch uses known as the editor knows them.

use std::path::Path;

use spreadlight_graph::subpatch::{self, Library, MODULES_DIR};
use spreadlight_graph::{NodeId, Patch, Registry};

use super::{layout, measure};

/// The editor's node types plus the subpatch types `patch` (at `path`) can
/// use: its inline definitions and the modules beside it. The user library is
/// left out, so the result does not depend on the machine.
pub fn registry_for(path: &Path, patch: &Patch) -> Registry {
    let mut registry = crate::nodes::registry();
    let dir = path.parent().unwrap_or(Path::new("."));
    let mut dirs = vec![dir.join(MODULES_DIR)];
    if dir.file_name().is_some_and(|n| n == MODULES_DIR) {
        dirs.push(dir.to_path_buf());
    }
    let library = Library::new(dirs);
    let mut defs: Vec<(String, Patch, String)> = Vec::new();
    collect_inline(patch, &mut defs);
    for (name, entry) in library.entries() {
        if let Ok(def) = &entry.definition {
            defs.push((
                name.to_owned(),
                (**def).clone(),
                entry.path.display().to_string(),
            ));
        }
    }
    for (name, def, source) in defs {
        if registry
            .get(&name)
            .is_some_and(|d| !subpatch::is_subpatch_def(d))
        {
            continue;
        }
        let node_def = subpatch::node_def(&name, &def, &registry, &library, &source);
        registry.replace(node_def);
    }
    registry
}

fn collect_inline(patch: &Patch, out: &mut Vec<(String, Patch, String)>) {
    for (name, def) in &patch.subpatches {
        if !out.iter().any(|(n, ..)| n == name) {
            out.push((name.clone(), def.clone(), "inline".to_owned()));
        }
        collect_inline(def, out);
    }
}

/// Lay out `patch` and its inline subpatches in place.
pub fn tidy(patch: &mut Patch, registry: &Registry) {
    for sub in patch.subpatches.values_mut() {
        tidy(sub, registry);
    }
    let held: Vec<Vec<NodeId>> = patch
        .frames
        .iter()
        .map(|f| {
            patch
                .nodes
                .iter()
                .filter(|n| f.holds(n.pos))
                .map(|n| n.id)
                .collect()
        })
        .collect();
    for (id, pos) in layout::layout(patch, registry, &[], layout::Direction::LeftToRight) {
        if let Some(n) = patch.node_mut(id) {
            n.pos = pos;
        }
    }
    let mut frames = std::mem::take(&mut patch.frames);
    for (frame, ids) in frames.iter_mut().zip(held) {
        let mut lo = (f32::INFINITY, f32::INFINITY);
        let mut hi = (f32::NEG_INFINITY, f32::NEG_INFINITY);
        for n in ids
            .iter()
            .filter_map(|&id| patch.nodes.iter().find(|n| n.id == id))
        {
            let (w, h) = measure::node_size(n, registry, patch);
            lo = (lo.0.min(n.pos.0), lo.1.min(n.pos.1));
            hi = (hi.0.max(n.pos.0 + w), hi.1.max(n.pos.1 + h));
        }
        if lo.0.is_finite() {
            frame.pos = ((lo.0 - 8.0).round(), (lo.1 - 18.0).round());
            frame.size = ((hi.0 - lo.0 + 16.0).round(), (hi.1 - lo.1 + 26.0).round());
        }
    }
    patch.frames = frames;
    let places = layout::comments_above(patch);
    for (c, p) in patch.comments.iter_mut().zip(places) {
        c.pos = p;
    }
}

#[cfg(test)]
mod tests {
    use std::path::{Path, PathBuf};

    use spreadlight_graph::format;

    use super::*;
    use crate::organise::measure::overlapping_nodes;

    fn patch_files(dir: &Path, out: &mut Vec<PathBuf>) {
        let Ok(entries) = std::fs::read_dir(dir) else {
            return;
        };
        let mut entries: Vec<PathBuf> = entries.filter_map(|e| e.ok().map(|e| e.path())).collect();
        entries.sort();
        for path in entries {
            if path.is_dir() {
                patch_files(&path, out);
            } else if path.extension().is_some_and(|e| e == "ron") {
                out.push(path);
            }
        }
    }

    /// Every overlap in `patch` and its inline subpatches, named by where.
    fn overlaps_in(patch: &Patch, registry: &Registry, at: &str, found: &mut Vec<String>) {
        for (a, b) in overlapping_nodes(patch, registry) {
            found.push(format!("{at}: nodes {a} and {b} overlap"));
        }
        for (name, sub) in &patch.subpatches {
            overlaps_in(sub, registry, &format!("{at} > {name}"), found);
        }
    }

    /// The shipped patches open tidy: no two nodes overlap, by the measure
    /// the editor lays out and fits with; every example explains itself in
    /// a comment. Patches that do not parse (`patches/bad`) are skipped.
    #[test]
    fn no_two_nodes_overlap_in_any_shipped_patch_and_examples_are_commented() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../patches");
        let mut files = Vec::new();
        patch_files(&root, &mut files);
        let mut problems = Vec::new();
        let mut checked = 0;
        for path in &files {
            let Ok(patch) = format::load(path) else {
                continue;
            };
            checked += 1;
            let registry = registry_for(path, &patch);
            let name = path
                .strip_prefix(&root)
                .unwrap_or(path)
                .display()
                .to_string();
            overlaps_in(&patch, &registry, &name, &mut problems);
            // The bad patches show one mistake each; help patches are checked for overlap here and
            // for what they show by their own tests.
            let example = !name.starts_with("bad") && !name.starts_with("help");
            if example && patch.comments.is_empty() && !patch.nodes.is_empty() {
                problems.push(format!("{name}: no comment explains it"));
            }
        }
        assert!(
            checked > 25,
            "only {checked} patches found under {}",
            root.display()
        );
        assert!(problems.is_empty(), "{}", problems.join("\n"));
    }
}
