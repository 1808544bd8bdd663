//! Every file in `patches/bad/` is a kind of bad input. Each says, in its
//! first line (`// expect: ...`), what the report must contain; an empty file
//! must be reported as empty. Loading never panics, and the report names the
//! file, and the node and pin where there is one.

use spreadlight_graph::{Network, format};
use spreadlight_tests::{bad_patches, root};

/// What loading and checking `path` reports, one problem a line, as
/// `spreadlight check` prints it when run from the repository root.
fn report(path: &std::path::Path) -> String {
    let registry = spreadlight_nodes::registry();
    let text = std::fs::read_to_string(path).expect("readable");
    let path = path.strip_prefix(root()).expect("inside the repository");
    match format::from_str(&text, path) {
        Err(e) => format!("error: {e}"),
        Ok(patch) => {
            let network = Network::compile(&patch, &registry);
            assert!(
                !network.problems().is_empty(),
                "{}: no problem reported",
                path.display()
            );
            network
                .problems()
                .iter()
                .map(|p| p.located(path) + "\n")
                .collect()
        }
    }
}

fn expectation(path: &std::path::Path) -> String {
    let text = std::fs::read_to_string(path).expect("readable");
    match text
        .lines()
        .next()
        .and_then(|l| l.strip_prefix("// expect: "))
    {
        Some(expected) => expected.to_owned(),
        None => {
            assert!(
                text.trim().is_empty(),
                "{}: a bad patch needs a `// expect: ...` first line",
                path.display()
            );
            "the file is empty".to_owned()
        }
    }
}

#[test]
fn every_bad_patch_gets_its_clear_error() {
    let files = bad_patches();
    assert!(
        files.len() >= 15,
        "the issue asks for at least 15 kinds of bad input, found {}",
        files.len()
    );
    let mut failures = Vec::new();
    for path in &files {
        let expected = expectation(path);
        let got = report(path);
        if !got.contains(&expected) {
            failures.push(format!(
                "{}\n  expected: {expected}\n  got:      {got}",
                path.display()
            ));
        }
        let name = path
            .file_name()
            .and_then(|n| n.to_str())
            .expect("utf-8 name");
        assert!(
            got.contains(name),
            "{name}: the report does not name the file: {got}"
        );
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn loading_bad_patches_keeps_their_content_for_saving() {
    // Where a bad patch parses at all, nothing in it is dropped: saving and
    // reloading gives the same document, problems and all.
    for path in bad_patches() {
        let Ok(patch) = format::load(&path) else {
            continue;
        };
        let text = format::to_string(&patch).expect("encode");
        let again = format::from_str(&text, &path).expect("re-parse");
        // Compared as text: a NaN that was written must come back, and NaN != NaN.
        assert_eq!(
            format::to_string(&again).expect("encode"),
            text,
            "{}",
            path.display()
        );
    }
}

#[test]
fn no_truncation_or_corruption_of_a_patch_panics() {
    // Every prefix of a real patch, and every single-byte corruption of it,
    // loads to a patch or to an error: never a panic.
    let path = spreadlight_tests::root().join("patches/circle-of-transforms.ron");
    let text = std::fs::read_to_string(&path).expect("readable");
    let registry = spreadlight_nodes::registry();
    for end in (0..text.len()).filter(|&i| text.is_char_boundary(i)) {
        if let Ok(patch) = format::from_str(&text[..end], &path) {
            Network::compile(&patch, &registry);
        }
    }
    let bytes = text.as_bytes();
    for (i, junk) in (0..bytes.len())
        .step_by(7)
        .zip([b'"', b')', b'9', b'-', b'[', b'x', b'}'].iter().cycle())
    {
        let mut corrupted = bytes.to_vec();
        corrupted[i] = *junk;
        let Ok(corrupted) = String::from_utf8(corrupted) else {
            continue;
        };
        if let Ok(patch) = format::from_str(&corrupted, &path) {
            Network::compile(&patch, &registry);
        }
    }
}
