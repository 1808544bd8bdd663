//! The `#ifdef` preprocessor of shader node files: a switch set picks one
//! permutation's text before naga sees it. It stands apart from the compile
//! in program.rs because it works on lines of text alone (no naga, no
//! annotations), and keeps every line so errors point into the file as written.

use std::collections::BTreeSet;

use super::error::{ShaderNodeError, Span};

/// Replace `#ifdef NAME` / `#ifndef NAME` / `#else` / `#endif` by what the
/// switches select, keeping every line (excluded ones become empty) so naga's
/// lines and columns are the file's.
pub fn preprocess(
    file: &str,
    source: &str,
    defines: &BTreeSet<String>,
) -> Result<String, ShaderNodeError> {
    let mut out = String::with_capacity(source.len());
    // Per open #if: (this branch is on, the enclosing is on, its line).
    let mut stack: Vec<(bool, bool, u32)> = Vec::new();
    for (i, line) in source.lines().enumerate() {
        let line_no = i as u32 + 1;
        let trimmed = line.trim_start();
        let active = stack.last().is_none_or(|s| s.0 && s.1);
        let at = Span {
            line: line_no,
            column: (line.len() - trimmed.len()) as u32 + 1,
        };
        let mut words = trimmed.split_whitespace();
        match words.next() {
            Some(d @ ("#ifdef" | "#ifndef")) => {
                let name = words
                    .next()
                    .ok_or_else(|| ShaderNodeError::at(file, at, format!("`{d}` needs a name")))?;
                let on = defines.contains(name) == (d == "#ifdef");
                stack.push((on, active, line_no));
            }
            Some("#else") => {
                let top = stack
                    .last_mut()
                    .ok_or_else(|| ShaderNodeError::at(file, at, "`#else` without `#ifdef`"))?;
                top.0 = !top.0;
            }
            Some("#endif") => {
                stack
                    .pop()
                    .ok_or_else(|| ShaderNodeError::at(file, at, "`#endif` without `#ifdef`"))?;
            }
            _ if active => out.push_str(line),
            _ => {}
        }
        out.push('\n');
    }
    if let Some(&(_, _, line)) = stack.last() {
        return Err(ShaderNodeError::at(
            file,
            Span { line, column: 1 },
            "`#ifdef` without `#endif`",
        ));
    }
    Ok(out)
}
