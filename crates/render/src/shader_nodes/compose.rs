//! Shader node files that `#import` the project's WGSL libraries
//! (`shaders/lib/`, e.g. `#import spreadlight::packing::safe_normalize`), and
//! materials (which import `spreadlight::surface`), are composed by naga_oil
//! like every built-in pass, through one shared composer. Its errors are
//! placed back in the file as `file:line:col`, and the places of bindings
//! and structs (whose spans naga_oil shifts) are found in the text.

use std::sync::{Mutex, OnceLock};

use naga_oil::compose::{ComposerError, ComposerErrorInner, ErrSource};

use super::error::{ShaderNodeError, Span, span_of, undecorate};
use crate::gbuffer::resolve_key::ResolveKey;
use crate::shaders::{Permutation, ShaderComposer};

/// naga_oil keeps a module index above this many bits of a span.
const SPAN_BITS: usize = 21;

/// Whether `text` (already preprocessed for its switches) imports a library.
pub fn imports(text: &str) -> bool {
    text.lines().any(|l| l.trim_start().starts_with("#import"))
}

/// The composer all shader node files share: the libraries are composed once.
fn composer() -> Result<&'static Mutex<ShaderComposer>, String> {
    static COMPOSER: OnceLock<Result<Mutex<ShaderComposer>, String>> = OnceLock::new();
    COMPOSER
        .get_or_init(|| {
            ShaderComposer::new()
                .map(Mutex::new)
                .map_err(|e| e.to_string())
        })
        .as_ref()
        .map_err(Clone::clone)
}

/// Compose `text` (the file's lines, switches resolved) with its imports.
pub fn compose(file: &str, text: &str) -> Result<naga::Module, ShaderNodeError> {
    let first = |message: String| ShaderNodeError::at(file, Span { line: 1, column: 1 }, message);
    let lock = composer().map_err(|e| first(format!("the shader libraries: {e}")))?;
    let mut composer = lock.lock().unwrap_or_else(|e| e.into_inner());
    composer
        .compose_external(file, text)
        .map_err(|e| place(file, text, &e, None))
}

/// Check that a material's `text` composes into the G-buffer resolve in
/// place of `spreadlight::custom_surface` (naga_oil is stricter with an
/// imported module than with a top-level one: names ending in a digit, say).
pub fn check_material(file: &str, text: &str) -> Result<(), ShaderNodeError> {
    let key = ResolveKey::custom_surface().key();
    check_spliced(
        file,
        text,
        crate::gbuffer::SURFACE_MODULE,
        &[(key, "the G-buffer resolve")],
    )
}

/// Check that `text` composes into each of `passes` (a permutation and what
/// to call it in an error) in place of library `module`.
pub fn check_spliced(
    file: &str,
    text: &str,
    module: &str,
    passes: &[(crate::shaders::ShaderKey, &str)],
) -> Result<(), ShaderNodeError> {
    let first = |message: String| ShaderNodeError::at(file, Span { line: 1, column: 1 }, message);
    let lock = composer().map_err(|e| first(format!("the shader libraries: {e}")))?;
    let mut composer = lock.lock().unwrap_or_else(|e| e.into_inner());
    let replaced = composer
        .replace_library(module, file, text)
        .map_err(|e| place(file, text, &e, Some(module)));
    let composed = replaced.and_then(|()| {
        passes.iter().try_for_each(|(key, what)| {
            composer
                .compose(key)
                .map(|_| ())
                .map_err(|e| first(format!("in {what}: {}", undecorate(&e.to_string()))))
        })
    });
    let restored = composer
        .restore_library(module)
        .map_err(|e| first(e.to_string()));
    composed.and(restored)
}

/// A naga_oil error at its place in the file; `spliced` is the library the
/// file was composed as (a material's or light shader's), whose errors are the file's own.
fn place(file: &str, text: &str, e: &ComposerError, spliced: Option<&str>) -> ShaderNodeError {
    let shift = e.source.offset();
    let unshift = |start: usize| (start & ((1 << SPAN_BITS) - 1)).saturating_sub(shift);
    let (offset, message) = match &e.inner {
        // At the `#import` line that names it (naga_oil says where it is used).
        ComposerErrorInner::ImportNotFound(name, pos) => (
            match import_line(text, name) {
                Some(offset) => {
                    return ShaderNodeError::at_offset(
                        file,
                        text,
                        offset,
                        format!(
                            "`#import {name}`: no such library (the libraries are \
                             shaders/lib/*.wgsl, imported as spreadlight::NAME)"
                        ),
                    );
                }
                None => Some(*pos),
            },
            format!(
                "`#import {name}`: no such library (the libraries are shaders/lib/*.wgsl, \
                 imported as spreadlight::NAME)"
            ),
        ),
        ComposerErrorInner::ImportParseError(message, pos) => {
            (Some(*pos), format!("`#import`: {message}"))
        }
        ComposerErrorInner::WgslParseError(p) => {
            // Offsets into the text naga_oil parsed: the file's, or the constructed source.
            let parsed = match &e.source {
                ErrSource::Constructing { source, .. } => source.as_str(),
                ErrSource::Module { .. } => text,
            };
            super::validate::front_end_error(p, parsed, &|span| {
                span.to_range().map(|r| unshift(r.start))
            })
        }
        ComposerErrorInner::ShaderValidationError(v)
        | ComposerErrorInner::HeaderValidationError(v) => {
            let mut message = format!("validation: {}", v.as_inner());
            let mut source: &dyn std::error::Error = v.as_inner();
            while let Some(next) = source.source() {
                message.push_str(&format!(": {next}"));
                source = next;
            }
            // naga's spans are the function, statement and expression at
            // fault, in no fixed order; naga_oil names the module of the
            // last. The narrowest span in that module is the expression.
            let ranges: Vec<_> = v.spans().filter_map(|(s, _)| s.to_range()).collect();
            let module = ranges.last().map(|r| r.start >> SPAN_BITS);
            (
                ranges
                    .iter()
                    .filter(|r| Some(r.start >> SPAN_BITS) == module)
                    .min_by_key(|r| r.len())
                    .map(|r| unshift(r.start)),
                message,
            )
        }
        ComposerErrorInner::NotEnoughEndIfs(pos)
        | ComposerErrorInner::TooManyEndIfs(pos)
        | ComposerErrorInner::ElseWithoutCondition(pos)
        | ComposerErrorInner::UnknownShaderDef { pos, .. }
        | ComposerErrorInner::UnknownShaderDefOperator { pos, .. }
        | ComposerErrorInner::DefineInModule(pos) => (Some(*pos), e.inner.to_string()),
        ComposerErrorInner::InvalidIdentifier { original, at } => (
            at.to_range().map(|r| unshift(r.start)),
            format!(
                "`{original}`: a material is composed as a module, whose names must not end \
                 in a digit or hold `__` (naga_oil)"
            ),
        ),
        other => (None, other.to_string()),
    };
    let message = undecorate(&message);
    match (&e.source, offset) {
        // In the file itself: its lines are the text's (naga_oil keeps them).
        // Offsets are into naga_oil's text, whose lines are the file's but
        // whose imported names are longer: the line is exact, the column close.
        (ErrSource::Constructing { source, .. }, Some(offset)) => {
            ShaderNodeError::at(file, span_of(source, offset), message)
        }
        // A material or light shader composed in place of its library: the file itself.
        (ErrSource::Module { name, .. }, Some(offset)) if spliced == Some(name.as_str()) => {
            ShaderNodeError::at_offset(file, text, offset, message)
        }
        // In an imported library: at the file's first `#import`, naming the library.
        (ErrSource::Module { name, .. }, _) => ShaderNodeError::at(
            file,
            first_import(text),
            format!("in imported library `{name}`: {message}"),
        ),
        _ => ShaderNodeError::at(file, first_import(text), message),
    }
}

/// The offset of the `#import` line that names `module`.
fn import_line(text: &str, module: &str) -> Option<usize> {
    let mut offset = 0;
    for line in text.split_inclusive('\n') {
        let trimmed = line.trim_start();
        if trimmed.starts_with("#import") && trimmed.contains(module) {
            return Some(offset + line.len() - trimmed.len());
        }
        offset += line.len();
    }
    None
}

fn first_import(text: &str) -> Span {
    text.find("#import")
        .map_or(Span { line: 1, column: 1 }, |o| span_of(text, o))
}

/// Whether `text[i..]` starts the whole word `word`.
fn word_at(text: &str, i: usize, word: &str) -> bool {
    let before = text[..i]
        .chars()
        .next_back()
        .is_some_and(|c| c.is_alphanumeric() || c == '_');
    let after = text[i + word.len()..]
        .chars()
        .next()
        .is_some_and(|c| c.is_alphanumeric() || c == '_');
    !before && !after
}

/// Where `var NAME` (or `var<space> NAME`) is declared in `text`.
pub fn var_offset(text: &str, name: &str) -> Option<usize> {
    text.match_indices(name).map(|(i, _)| i).find(|&i| {
        if !word_at(text, i, name) {
            return false;
        }
        let before = text[..i].trim_end();
        let line = &text[text[..i].rfind('\n').map_or(0, |n| n + 1)..i];
        before.ends_with("var") || (before.ends_with('>') && line.contains("var"))
    })
}

/// Where `struct NAME` is declared in `text`.
pub fn struct_offset(text: &str, name: &str) -> Option<usize> {
    text.match_indices(name)
        .map(|(i, _)| i)
        .find(|&i| word_at(text, i, name) && text[..i].trim_end().ends_with("struct"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decorated_names_read_as_written() {
        let decorated = naga_oil::compose::Composer::decorated_name(
            Some("spreadlight::packing"),
            "safe_normalize",
        );
        assert_eq!(
            undecorate(&format!("call to `{decorated}` failed")),
            "call to `safe_normalize` failed"
        );
        assert_eq!(undecorate(&decorated), "safe_normalize");
    }

    #[test]
    fn declarations_are_found_by_name() {
        let text = "struct Params { a: f32 }\n@group(0) @binding(0) var<uniform> params: Params;\n";
        assert_eq!(struct_offset(text, "Params"), Some(7));
        assert_eq!(span_of(text, var_offset(text, "params").unwrap()).line, 2);
    }
}
