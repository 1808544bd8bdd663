//! The text naga_oil reads, made smaller first. naga_oil's preprocessor
//! (several regular expressions on every line), its identifier
//! substitution and naga's lexer go over an entry shader once for each
//! permutation composed: its comments, its blank lines and the code of
//! every switch the permutation leaves off. The light loop and the
//! transparency shader are 1,035 and 1,444 lines, a third of their text
//! comments, and the exhaustive permutation test composes 21,000
//! permutations of the two (a cold start a few dozen). Composing the
//! decided text took 8.7 and 9.5 ms a permutation against 11.5 and 20.6 as
//! written (a debug build of the tests, naga_oil optimized).
//!
//! [`without_comments`] keeps every line where it was (an error's line and
//! column still point into the file); [`decide`] drops lines, so the
//! composer composes the file as written again when the decided text
//! fails, for naga_oil's error to name the right line.

use std::borrow::Cow;
use std::collections::BTreeSet;

/// `source` without its comments.
pub(super) fn without_comments(source: Cow<'static, str>) -> Cow<'static, str> {
    if !source.contains("//") && !source.contains("/*") {
        return source;
    }
    let bytes = source.as_bytes();
    let mut out = String::with_capacity(source.len());
    let (mut i, mut kept) = (0, 0);
    while i < bytes.len() {
        match (bytes[i], bytes.get(i + 1)) {
            (b'/', Some(b'/')) => {
                out.push_str(&source[kept..i]);
                i = source[i..].find('\n').map_or(bytes.len(), |n| i + n);
                kept = i;
            }
            (b'/', Some(b'*')) => {
                out.push_str(&source[kept..i]);
                // Block comments nest in WGSL; their line breaks stay.
                let mut depth = 0usize;
                while i < bytes.len() {
                    match (bytes[i], bytes.get(i + 1)) {
                        (b'/', Some(b'*')) => (depth, i) = (depth + 1, i + 2),
                        (b'*', Some(b'/')) => (depth, i) = (depth - 1, i + 2),
                        (b'\n', _) => {
                            out.push('\n');
                            i += 1;
                        }
                        _ => i += 1,
                    }
                    if depth == 0 {
                        break;
                    }
                }
                kept = i;
            }
            _ => i += 1,
        }
    }
    out.push_str(&source[kept..]);
    Cow::Owned(out)
}

/// One conditional directive of naga_oil's preprocessor.
enum Directive<'s> {
    IfDef(&'s str),
    IfNDef(&'s str),
    Else,
    EndIf,
}

/// The directive on `line`: None for a line of code or an `#import`, Err
/// for a directive this resolver leaves to naga_oil (`#if`, `#else ifdef`,
/// `#define`, ...).
fn directive(line: &str) -> Result<Option<Directive<'_>>, ()> {
    let Some(rest) = line.trim_start().strip_prefix('#') else {
        return Ok(None);
    };
    let mut words = rest.split_whitespace();
    let (keyword, name, more) = (words.next(), words.next(), words.next());
    let name_ok = |n: &str| n.chars().all(|c| c.is_ascii_alphanumeric() || c == '_');
    match (keyword, name, more) {
        (Some("import" | "define_import_path"), ..) => Ok(None),
        (Some("ifdef"), Some(n), None) if name_ok(n) => Ok(Some(Directive::IfDef(n))),
        (Some("ifndef"), Some(n), None) if name_ok(n) => Ok(Some(Directive::IfNDef(n))),
        (Some("else"), None, None) => Ok(Some(Directive::Else)),
        (Some("endif"), None, None) => Ok(Some(Directive::EndIf)),
        _ => Err(()),
    }
}

/// `source` (comments gone) with its `#ifdef` / `#ifndef` / `#else` /
/// `#endif` decided for the switches `defined`: only the lines of code in
/// the branches taken, `#import`s among them; directives, blank lines and
/// the branches not taken are gone. naga_oil composes the same module from
/// it (the same switches are still handed to it, for the libraries). None
/// for a text with a directive this does not decide (`#if`, `#else ifdef`,
/// `#define`, ...) or unbalanced ones: naga_oil decides, or reports, those.
pub(super) fn decide(source: &str, defined: &BTreeSet<&str>) -> Option<String> {
    let mut out = String::with_capacity(source.len() / 2);
    // Per open conditional: whether its enclosing code is kept, and whether
    // its current branch is.
    let mut open: Vec<(bool, bool)> = Vec::new();
    let mut kept = true;
    for line in source.lines() {
        match directive(line).ok()? {
            None => {
                if kept && !line.trim().is_empty() {
                    out.push_str(line);
                    out.push('\n');
                }
            }
            Some(d @ (Directive::IfDef(name) | Directive::IfNDef(name))) => {
                let branch = defined.contains(name) == matches!(d, Directive::IfDef(_));
                open.push((kept, branch));
                kept = kept && branch;
            }
            Some(Directive::Else) => {
                let (outer, branch) = open.last_mut()?;
                *branch = !*branch;
                kept = *outer && *branch;
            }
            Some(Directive::EndIf) => kept = open.pop()?.0,
        }
    }
    open.is_empty().then_some(out)
}

#[cfg(test)]
mod tests {
    use super::super::{ShaderComposer, ShaderFile, ShaderKey};
    use super::*;

    #[test]
    fn comments_go_and_every_line_stays_where_it_was() {
        let source = "// a file comment\n\
                      let a = 1; // after code\n\
                      /* a block\n\
                      over /* nested */ two lines */ let b = a / 2;\n\
                      let c = b * 3;";
        let stripped = without_comments(Cow::Borrowed(source));
        assert_eq!(stripped, "\nlet a = 1; \n\n let b = a / 2;\nlet c = b * 3;");
        assert_eq!(stripped.lines().count(), source.lines().count());
        // Without a comment the text is not copied.
        assert!(matches!(
            without_comments(Cow::Borrowed("let a = 1;")),
            Cow::Borrowed(_)
        ));
        // An unclosed block comment ends the text, as naga's lexer would end it.
        assert_eq!(without_comments(Cow::Borrowed("a /* b\nc")), "a \n");
    }

    const NESTED: &str =
        "a\n#ifdef X\nx\n#ifndef Y\nnot y\n#else\ny\n#endif\n\n#else\nno x\n#endif\nz";

    #[test]
    fn only_the_code_of_the_branches_taken_stays() {
        let decide =
            |defs: &[&str]| decide(NESTED, &defs.iter().copied().collect()).expect("decided");
        assert_eq!(decide(&[]), "a\nno x\nz\n");
        assert_eq!(decide(&["X"]), "a\nx\nnot y\nz\n");
        assert_eq!(decide(&["X", "Y"]), "a\nx\ny\nz\n");
        assert_eq!(decide(&["Y"]), "a\nno x\nz\n");
    }

    #[test]
    fn what_it_does_not_decide_is_left_to_naga_oil() {
        let defs = ["X"].into_iter().collect();
        for source in [
            "#if X == 2\na\n#endif",
            "#ifdef X\na\n#else ifdef Y\nb\n#endif",
            "#define X\n#ifdef X\na\n#endif",
            "#ifdef X\na",
            "a\n#endif",
            "#else\na",
        ] {
            assert_eq!(decide(source, &defs), None, "{source}");
        }
        let imports = "#import spreadlight::packing\n#ifdef X\n  a\n#endif";
        assert_eq!(
            decide(imports, &defs).as_deref(),
            Some("#import spreadlight::packing\n  a\n")
        );
    }

    /// The real shaders: every permutation of a few files composes to the
    /// same module from the decided text as naga_oil composes from the file
    /// as written.
    #[test]
    fn a_decided_text_composes_to_the_module_of_the_text_as_written() {
        let mut composer = ShaderComposer::unshared().expect("libraries compose");
        // Every entry shader's first permutations (the exhaustive test
        // composes them all, decided).
        let mut per_file = std::collections::HashMap::<&str, usize>::new();
        let keys: Vec<ShaderKey> = crate::permutations::all_permutations()
            .into_iter()
            .filter(|k| {
                let n = per_file.entry(k.file.path).or_default();
                *n += 1;
                *n <= 4
            })
            .collect();
        assert!(keys.len() >= 100, "{} keys", keys.len());
        // As WGSL: naga's spans (byte offsets) differ, the code may not.
        let wgsl = |module: naga::Module| {
            let info = naga::valid::Validator::new(
                naga::valid::ValidationFlags::all(),
                naga::valid::Capabilities::all(),
            )
            .validate(&module)
            .expect("valid");
            naga::back::wgsl::write_string(&module, &info, naga::back::wgsl::WriterFlags::empty())
                .expect("writes")
        };
        for key in keys {
            let text = decide(composer.source_of(key.file), &key.features);
            assert!(text.is_some(), "{} is decided here", key.path());
            let decided = composer.compose(&key).expect("composes");
            let written = composer
                .compose_as_written(&key)
                .expect("composes as written");
            assert_eq!(wgsl(decided), wgsl(written), "{}", key.path());
        }
    }

    #[test]
    fn an_error_names_the_line_of_the_file_with_its_comments() {
        static BROKEN: ShaderFile = ShaderFile {
            path: "fixture/commented.wgsl",
            source: "// one\n// two\n/* three\nfour */\n@compute @workgroup_size(1)\n\
                     fn main() {\n#ifdef NEVER\n    let w = 1;\n#endif\n    let v = undeclared_name;\n}\n",
            features: &[],
            library: false,
            keys: None,
        };
        let mut composer = ShaderComposer::unshared().expect("libraries compose");
        let err = composer
            .compose(&ShaderKey::new(&BROKEN, []))
            .expect_err("an undeclared name")
            .to_string();
        assert!(err.contains(":10:"), "line 10 of the file: {err}");
    }
}
