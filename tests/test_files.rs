//! No test file is skipped silently. The crates' integration tests are one
//! binary per crate (`autotests = false` and one `[[test]]` whose root
//! declares every file as a module: linking a binary per file cost CI
//! minutes, docs/testing.md), so a new file under a `tests/` folder compiles
//! only once some binary's root names it with `mod`. This walks every
//! package's test roots, follows their `mod` declarations as rustc would, and
//! fails naming each `.rs` file under a tests folder that none reaches.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("tests/ has a parent")
        .to_path_buf()
}

/// A package directory and the folder whose `.rs` files must all be compiled:
/// `crates/X/tests`, and for the workspace tests package (`tests/`) the
/// package folder itself.
fn test_folders(root: &Path) -> Vec<(PathBuf, PathBuf)> {
    let mut out = vec![(root.join("tests"), root.join("tests"))];
    let crates = std::fs::read_dir(root.join("crates")).expect("crates/ lists");
    for entry in crates.flatten() {
        let package = entry.path();
        if package.join("Cargo.toml").is_file() && package.join("tests").is_dir() {
            out.push((package.clone(), package.join("tests")));
        }
    }
    out.sort();
    out
}

/// Every `.rs` file under `dir`, at any depth.
fn rust_files(dir: &Path, out: &mut BTreeSet<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for entry in entries.flatten() {
        let path = entry.path();
        let name = entry.file_name();
        if name == "target" {
            continue;
        }
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.insert(path);
        }
    }
}

/// The crate roots a package's manifest gives: every target's `path = ...`,
/// and with cargo's auto-discovery of tests left on (no `autotests = false`),
/// every `tests/*.rs` and `tests/*/main.rs` too.
fn target_roots(package: &Path) -> Vec<PathBuf> {
    let manifest = std::fs::read_to_string(package.join("Cargo.toml"))
        .unwrap_or_else(|e| panic!("{}: {e}", package.join("Cargo.toml").display()));
    let mut roots = Vec::new();
    let mut autotests = true;
    let mut in_target = false;
    for line in manifest.lines().map(str::trim) {
        if line.starts_with('[') {
            in_target = matches!(
                line,
                "[lib]" | "[[bin]]" | "[[test]]" | "[[bench]]" | "[[example]]"
            );
            continue;
        }
        let Some((key, value)) = line.split_once('=') else {
            continue;
        };
        let (key, value) = (key.trim(), value.trim().trim_matches('"'));
        if key == "autotests" && value == "false" {
            autotests = false;
        } else if in_target && key == "path" {
            roots.push(package.join(value));
        }
    }
    if autotests && let Ok(entries) = std::fs::read_dir(package.join("tests")) {
        for entry in entries.flatten() {
            let path = entry.path();
            if path.extension().is_some_and(|e| e == "rs") {
                roots.push(path);
            } else if path.join("main.rs").is_file() {
                roots.push(path.join("main.rs"));
            }
        }
    }
    roots
}

/// The files a source file's `mod NAME;` lines load, resolved as rustc does:
/// `#[path = "..."]` relative to the file's folder; otherwise `NAME.rs` or
/// `NAME/mod.rs` beside a crate root or `mod.rs`, and under `stem/` beside
/// any other file. (Inline `mod x { mod y; }` is not followed: a file reached
/// only that way is reported, loudly, rather than missed.)
fn declared_modules(file: &Path, is_root: bool) -> Vec<PathBuf> {
    let Ok(text) = std::fs::read_to_string(file) else {
        return Vec::new();
    };
    let folder = file.parent().unwrap_or(Path::new("."));
    let owns_folder = is_root || file.file_name().is_some_and(|n| n == "mod.rs");
    let base = if owns_folder {
        folder.to_path_buf()
    } else {
        folder.join(file.file_stem().unwrap_or_default())
    };
    let mut out = Vec::new();
    let mut path_attribute: Option<String> = None;
    for line in text.lines().map(str::trim) {
        if line.starts_with("//") || line.is_empty() {
            continue;
        }
        if let Some(rest) = line.strip_prefix("#[path") {
            path_attribute = rest
                .split('"')
                .nth(1)
                .map(str::to_string)
                .filter(|_| rest.trim_start().starts_with('='));
            continue;
        }
        if line.starts_with("#[") {
            continue;
        }
        let declaration = line
            .strip_prefix("pub(crate) ")
            .or_else(|| line.strip_prefix("pub "))
            .unwrap_or(line);
        if let Some(name) = declaration
            .strip_prefix("mod ")
            .and_then(|rest| rest.strip_suffix(';'))
        {
            let name = name.trim();
            match path_attribute.take() {
                Some(path) => out.push(folder.join(path)),
                None => {
                    let flat = base.join(format!("{name}.rs"));
                    if flat.is_file() {
                        out.push(flat);
                    } else {
                        out.push(base.join(name).join("mod.rs"));
                    }
                }
            }
        }
        path_attribute = None;
    }
    out
}

/// Lexically normalised (`a/b/../c` is `a/c`), so a file reached through a
/// `#[path = "../.."]` compares equal to the same file found on disk.
fn normalise(path: &Path) -> PathBuf {
    let mut out = PathBuf::new();
    for part in path.components() {
        match part {
            std::path::Component::ParentDir => {
                out.pop();
            }
            std::path::Component::CurDir => {}
            other => out.push(other),
        }
    }
    out
}

#[test]
fn every_file_under_a_tests_folder_is_compiled_by_a_test_binary() {
    let root = root();
    let mut on_disk = BTreeSet::new();
    let mut compiled = BTreeSet::new();
    let mut roots_by_package = Vec::new();
    for (package, folder) in test_folders(&root) {
        rust_files(&folder, &mut on_disk);
        let roots = target_roots(&package);
        let mut stack: Vec<(PathBuf, bool)> = roots.iter().map(|r| (r.clone(), true)).collect();
        while let Some((file, is_root)) = stack.pop() {
            let file = normalise(&file);
            if !compiled.insert(file.clone()) {
                continue;
            }
            stack.extend(
                declared_modules(&file, is_root)
                    .into_iter()
                    .map(|m| (m, false)),
            );
        }
        roots_by_package.push((folder, roots));
    }
    let skipped: Vec<String> = on_disk
        .iter()
        .filter(|f| !compiled.contains(&normalise(f)))
        .map(|f| {
            let f = normalise(f);
            let binaries = roots_by_package
                .iter()
                .find(|(folder, _)| f.starts_with(normalise(folder)))
                .map(|(_, roots)| {
                    roots
                        .iter()
                        .map(|r| {
                            normalise(r)
                                .strip_prefix(&root)
                                .unwrap_or(r)
                                .display()
                                .to_string()
                        })
                        .collect::<Vec<_>>()
                        .join(", ")
                })
                .unwrap_or_default();
            format!(
                "{} (no test binary compiles it: declare it with `mod` in one of {binaries})",
                f.strip_prefix(&root).unwrap_or(&f).display()
            )
        })
        .collect();
    assert!(
        skipped.is_empty(),
        "test files no binary compiles, so their tests never run:\n  {}",
        skipped.join("\n  ")
    );
    // The walk itself must have found the files, or an empty tree would pass.
    let reached = on_disk
        .iter()
        .filter(|f| compiled.contains(&normalise(f)))
        .count();
    assert!(
        reached > 50,
        "only {reached} test files reached from the manifests: the walk is broken"
    );
}
