//! WGSL parsed and validated by naga, its errors turned into
//! [`ShaderNodeError`]s at a file, line and column. It stands apart from
//! program.rs, which decides what a valid module means, because it only
//! answers whether naga accepts the text and, if not, where.

use super::error::{ShaderNodeError, Span};

fn location(file: &str, source: &str, span: naga::Span, message: String) -> ShaderNodeError {
    match span.to_range() {
        Some(range) => ShaderNodeError::at_offset(file, source, range.start, message),
        None => ShaderNodeError::at(file, Span { line: 1, column: 1 }, message),
    }
}

/// Parse and validate WGSL: syntax and naga's validation errors at their place.
pub(super) fn parse_and_validate(
    file: &str,
    text: &str,
) -> Result<(naga::Module, naga::valid::ModuleInfo), ShaderNodeError> {
    let module = naga::front::wgsl::parse_str(text).map_err(|e| {
        let at = e
            .location(text)
            .map_or(Span { line: 1, column: 1 }, |l| Span {
                line: l.line_number,
                column: l.line_position,
            });
        ShaderNodeError::at(file, at, format!("WGSL syntax: {}", e.message()))
    })?;
    let info = naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::default(),
    )
    .validate(&module)
    .map_err(|e| {
        let mut message = format!("validation: {}", e.as_inner());
        let mut source_error: &dyn std::error::Error = e.as_inner();
        while let Some(next) = source_error.source() {
            message.push_str(&format!(": {next}"));
            source_error = next;
        }
        let span = e.spans().next().map(|(s, _)| *s).unwrap_or_default();
        location(file, text, span, message)
    })?;
    Ok((module, info))
}

/// Validate a module composed by naga_oil: its spans point into the
/// composed text, not the file, so errors are placed at the file's start
/// with naga_oil's mangled names undone.
pub(super) fn validate_composed(
    file: &str,
    module: &naga::Module,
) -> Result<naga::valid::ModuleInfo, ShaderNodeError> {
    naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::default(),
    )
    .validate(module)
    .map_err(|e| {
        ShaderNodeError::at(
            file,
            Span { line: 1, column: 1 },
            format!("validation: {}", super::compose::undecorate(&e.to_string())),
        )
    })
}
