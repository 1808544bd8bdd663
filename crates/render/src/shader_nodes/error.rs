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
