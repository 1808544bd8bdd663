//! Docs that cannot go stale: what docs/architecture.md says about the
//! repository's files and crates, and the files docs/testing.md names, are
//! checked against the repository.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("tests/ has a parent")
        .to_path_buf()
}

fn architecture() -> String {
    std::fs::read_to_string(root().join("docs/architecture.md")).expect("docs/architecture.md")
}

/// Every file under `dir`, as a path relative to the root with `/`.
fn files(dir: &Path, root: &Path, out: &mut Vec<String>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for entry in entries.flatten() {
        let path = entry.path();
        let name = entry.file_name();
        if name == "target" || name == ".git" {
            continue;
        }
        if path.is_dir() {
            files(&path, root, out);
        } else if let Ok(rel) = path.strip_prefix(root) {
            out.push(rel.to_string_lossy().replace('\\', "/"));
        }
    }
}

/// `shaders/lib/{brdf,lights}.wgsl` as the two names it stands for.
fn expand_braces(name: &str) -> Vec<String> {
    match (name.find('{'), name.find('}')) {
        (Some(open), Some(close)) if open < close => name[open + 1..close]
            .split(',')
            .map(|part| format!("{}{part}{}", &name[..open], &name[close + 1..]))
            .collect(),
        _ => vec![name.to_owned()],
    }
}

/// The files `doc` names in backticks (`frame_graph/merge.rs`,
/// `shaders/lib/brdf.wgsl`, `docs/post.md`) that the repository lacks: a
/// name counts as present when it is the end of some file's path.
fn missing_files(doc: &str) -> Vec<String> {
    let root = root();
    let mut all = Vec::new();
    files(&root, &root, &mut all);
    let mut missing = Vec::new();
    for quoted in doc.split('`').skip(1).step_by(2) {
        let is_file = [".rs", ".wgsl", ".md", ".ron"]
            .iter()
            .any(|ext| quoted.ends_with(ext))
            && !quoted.contains(' ')
            && !quoted.starts_with('.');
        if !is_file {
            continue;
        }
        for name in expand_braces(quoted) {
            if !all
                .iter()
                .any(|f| *f == name || f.ends_with(&format!("/{name}")))
            {
                missing.push(name);
            }
        }
    }
    missing
}

/// Every file the architecture names in backticks is a file of the repository.
#[test]
fn the_architecture_names_only_files_that_exist() {
    let missing = missing_files(&architecture());
    assert!(
        missing.is_empty(),
        "docs/architecture.md names files the repository does not have: {missing:?}"
    );
}

/// Every test file docs/testing.md names is there: a test moved or merged
/// into another file takes the doc with it.
#[test]
fn the_testing_guide_names_only_files_that_exist() {
    let doc = std::fs::read_to_string(root().join("docs/testing.md")).expect("docs/testing.md");
    let missing = missing_files(&doc);
    assert!(
        missing.is_empty(),
        "docs/testing.md names files the repository does not have: {missing:?}"
    );
}

/// The crate diagram's arrows are the crates' dependencies: each arrow is a
/// dependency in the manifest, and each dependency is a path of arrows.
#[test]
fn the_crate_diagram_matches_the_manifests() {
    let doc = architecture();
    let section = doc
        .split("## The crates and the arrow")
        .nth(1)
        .expect("the crate section");
    let diagram = section
        .split("```")
        .nth(1)
        .expect("the diagram's code block");
    let mut arrows: BTreeSet<(String, String)> = BTreeSet::new();
    for line in diagram.lines() {
        let names: Vec<&str> = line
            .split('►')
            .map(|part| part.trim_matches(|c: char| !c.is_alphanumeric()))
            .filter(|n| !n.is_empty())
            .collect();
        for pair in names.windows(2) {
            arrows.insert((pair[0].to_owned(), pair[1].to_owned()));
        }
    }
    // Every crate under crates/: a new one must be drawn.
    let mut crates: Vec<String> = std::fs::read_dir(root().join("crates"))
        .expect("crates/")
        .filter_map(|e| e.ok())
        .filter(|e| e.path().join("Cargo.toml").is_file())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    crates.sort();
    let mut deps: BTreeMap<&str, BTreeSet<String>> = BTreeMap::new();
    for krate in &crates {
        let manifest = std::fs::read_to_string(root().join(format!("crates/{krate}/Cargo.toml")))
            .expect("manifest");
        let dependencies = manifest
            .split("[dependencies]")
            .nth(1)
            .and_then(|d| d.split("\n[").next())
            .unwrap_or_default();
        let used = crates
            .iter()
            .filter(|other| dependencies.contains(&format!("spreadlight-{other}")))
            .map(|other| (*other).to_owned())
            .collect();
        deps.insert(krate.as_str(), used);
    }
    for (from, to) in &arrows {
        assert!(
            deps.get(to.as_str()).is_some_and(|d| d.contains(from)),
            "the diagram draws {from} -> {to}, but crates/{to} does not depend on spreadlight-{from}"
        );
    }
    let reaches = |from: &str, to: &str| {
        let mut stack = vec![from.to_owned()];
        let mut seen = BTreeSet::new();
        while let Some(at) = stack.pop() {
            if at == to {
                return true;
            }
            if seen.insert(at.clone()) {
                stack.extend(
                    arrows
                        .iter()
                        .filter(|(a, _)| *a == at)
                        .map(|(_, b)| b.clone()),
                );
            }
        }
        false
    };
    for (krate, used) in &deps {
        for dep in used {
            assert!(
                reaches(dep, krate),
                "crates/{krate} depends on spreadlight-{dep}, which the diagram does not reach it from"
            );
        }
    }
}
