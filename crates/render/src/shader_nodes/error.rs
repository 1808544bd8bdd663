//! A shader node's error: what is wrong, and where in which file, as
//! `file:line:col: message` (editors jump to it).

use thiserror::Error;

/// A 1-based line and column in a shader file.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Span {
    pub line: u32,
    pub column: u32,
}

#[derive(Clone, Debug, Error, PartialEq)]
#[error("{file}:{}:{}: {message}", at.line, at.column)]
pub struct ShaderNodeError {
    pub file: String,
    pub at: Span,
    pub message: String,
}

impl ShaderNodeError {
    pub fn at(file: &str, at: Span, message: impl Into<String>) -> Self {
        ShaderNodeError {
            file: file.to_owned(),
            at,
            message: message.into(),
        }
    }

    /// An error at a byte offset of `source`.
    pub fn at_offset(file: &str, source: &str, offset: usize, message: impl Into<String>) -> Self {
        Self::at(file, span_of(source, offset), message)
    }
}

/// The line and column of a byte offset.
pub fn span_of(source: &str, offset: usize) -> Span {
    let offset = offset.min(source.len());
    let before = &source[..offset];
    let line = before.matches('\n').count() as u32 + 1;
    let column = before.rfind('\n').map_or(offset, |n| offset - n - 1) as u32 + 1;
    Span { line, column }
}

/// What naga_oil wraps the module of an imported name in.
const DECORATION_PRE: &str = "X_naga_oil_mod_X";

/// `nameX_naga_oil_mod_XENCODEDX` -> `name`, in a message.
pub fn undecorate(message: &str) -> String {
    let mut out = String::with_capacity(message.len());
    let mut rest = message;
    while let Some(i) = rest.find(DECORATION_PRE) {
        out.push_str(&rest[..i]);
        let after = &rest[i + DECORATION_PRE.len()..];
        let encoded = after
            .find(|c: char| !(c.is_ascii_uppercase() || c.is_ascii_digit()))
            .unwrap_or(after.len());
        // The encoded module name ends with an `X` (itself a base32 digit).
        rest = if after[..encoded].ends_with('X') {
            &after[encoded..]
        } else {
            after
        };
    }
    out.push_str(rest);
    out
}
