//! Scopes over subpatch files opened in place: the opened files by type
//! name, and the walk from the top document along a scope (a chain of
//! definition names, inline definitions first, as in the runtime) to the
//! document it names. Apart from `module_file.rs` (which opens and saves
//! them as part of the editor's document) so the document model uses these
//! without the two depending on each other.

use std::collections::BTreeMap;
use std::path::PathBuf;

use spreadlight_graph::Patch;

/// A subpatch file read into the document.
#[derive(Clone, Debug, PartialEq)]
pub struct ModuleFile {
    pub path: PathBuf,
    /// As edited.
    pub patch: Patch,
    /// As last read or written: saving writes the file only when they differ.
    pub saved: Patch,
}

/// The opened subpatch files, by type name.
pub type Modules = BTreeMap<String, ModuleFile>;

/// Walk `scope` from `top`: the index of the last step that enters a file
/// (the walk restarts there) and how many steps still lead somewhere.
fn walk(top: &Patch, files: &Modules, scope: &[String]) -> (Option<usize>, usize) {
    let mut doc = top;
    let mut last_file = None;
    for (k, name) in scope.iter().enumerate() {
        if let Some(inner) = doc.subpatches.get(name) {
            doc = inner;
        } else if let Some(file) = files.get(name) {
            doc = &file.patch;
            last_file = Some(k);
        } else {
            return (last_file, k);
        }
    }
    (last_file, scope.len())
}

/// The document at `scope`, or the deepest one that still exists on the way.
pub fn doc_at<'p>(top: &'p Patch, files: &'p Modules, scope: &[String]) -> &'p Patch {
    let (start, depth) = walk(top, files, scope);
    let (mut doc, rest) = match start {
        Some(k) => (&files[&scope[k]].patch, &scope[k + 1..depth]),
        None => (top, &scope[..depth]),
    };
    for name in rest {
        doc = &doc.subpatches[name];
    }
    doc
}

pub fn doc_at_mut<'p>(
    top: &'p mut Patch,
    files: &'p mut Modules,
    scope: &[String],
) -> &'p mut Patch {
    let (start, depth) = walk(top, files, scope);
    let (mut doc, rest) = match start {
        Some(k) => (
            &mut files.get_mut(&scope[k]).expect("walked").patch,
            &scope[k + 1..depth],
        ),
        None => (top, &scope[..depth]),
    };
    for name in rest {
        doc = doc.subpatches.get_mut(name).expect("walked");
    }
    doc
}

/// How many names of `scope` still lead to a document, from the top.
pub fn existing_depth(top: &Patch, files: &Modules, scope: &[String]) -> usize {
    walk(top, files, scope).1
}
