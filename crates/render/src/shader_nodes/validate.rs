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

/// naga's WGSL front end parses and type-checks in one step, with one error
/// type whose kinds are private: its messages tell them apart. A message
/// about tokens is a syntax error, one about names a name error, one about
/// types a type error; the rest are other rules of WGSL.
fn front_end_class(message: &str) -> &'static str {
    const SYNTAX: &[&str] = &[
        "expected ",
        "unexpected",
        "unterminated",
        "brace nesting",
        "invalid numeric literal",
        "Identifier can't be",
        "invalid field accessor",
    ];
    const NAME: &[&str] = &[
        "no definition in scope",
        "unknown ",
        "redefinition of",
        "name `",
    ];
    if SYNTAX.iter().any(|p| message.starts_with(p)) {
        "WGSL syntax"
    } else if NAME.iter().any(|p| message.starts_with(p)) {
        "WGSL name"
    } else if message.contains("type")
        || message.contains("convert")
        || message.contains("cast ")
        || message.starts_with("invalid left-hand side")
    {
        "WGSL type"
    } else {
        "WGSL"
    }
}

/// A WGSL front-end error: where it is (an offset of `text`, which `offset`
/// maps naga's spans into) and its message, with its class. A type error is
/// placed at the expression whose type is wrong where naga labels one
/// ("argument #1 has type ...", "this expression has type ..."), and a
/// declaration whose value has the wrong type at the value, not at the name.
pub(super) fn front_end_error(
    e: &naga::front::wgsl::ParseError,
    text: &str,
    offset: &dyn Fn(naga::Span) -> Option<usize>,
) -> (Option<usize>, String) {
    let class = front_end_class(e.message());
    let mut message = format!("{class}: {}", e.message());
    let typed = e.labels().find(|(_, label)| label.contains("has type"));
    if let Some((_, label)) = typed {
        message.push_str(&format!(" ({label})"));
    }
    let first = e.labels().next();
    let mut place = typed.or(first).and_then(|(span, _)| offset(span));
    if e.message().starts_with("the type of `")
        && let Some(name) = place
    {
        place = initializer(text, name).or(place);
    }
    (place, message)
}

/// In `let x: T = value;` with `name` the offset of `x`: the offset of `value`.
fn initializer(text: &str, name: usize) -> Option<usize> {
    let rest = text.get(name..)?;
    let end = rest.find(';').unwrap_or(rest.len());
    let equals = rest[..end].find('=')?;
    let value = &rest[equals + 1..];
    Some(name + equals + 1 + (value.len() - value.trim_start().len()))
}

/// Parse and validate WGSL: syntax and naga's validation errors at their place.
pub(super) fn parse_and_validate(
    file: &str,
    text: &str,
) -> Result<(naga::Module, naga::valid::ModuleInfo), ShaderNodeError> {
    let module = naga::front::wgsl::parse_str(text).map_err(|e| {
        let (offset, message) = front_end_error(&e, text, &|span| span.to_range().map(|r| r.start));
        match offset {
            Some(offset) => ShaderNodeError::at_offset(file, text, offset, message),
            None => ShaderNodeError::at(file, Span { line: 1, column: 1 }, message),
        }
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
        // naga's spans are the function, statement and expression at fault,
        // in no fixed order: the narrowest is the expression.
        let span = e
            .spans()
            .map(|(s, _)| *s)
            .filter(|s| s.to_range().is_some())
            .min_by_key(|s| s.to_range().map_or(usize::MAX, |r| r.len()))
            .unwrap_or_default();
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
            format!("validation: {}", super::error::undecorate(&e.to_string())),
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    const HEAD: &str = "struct P { gain: f32, size: vec2<f32> }
@group(0) @binding(0) var<uniform> params: P;
@group(0) @binding(1) var out: texture_storage_2d<rgba16float, write>;
@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
";

    /// The error for `body` as the entry point's first line (line 6).
    fn error(body: &str) -> String {
        let text = format!("{HEAD}{body}\n}}\n");
        match parse_and_validate("t.wgsl", &text) {
            Ok(_) => panic!("`{body}` compiled"),
            Err(e) => e.to_string(),
        }
    }

    /// Each class is named, and placed at the token, the name or the
    /// expression at fault, not at the statement around it.
    #[test]
    fn front_end_and_validation_errors_are_classed_and_placed_at_the_expression() {
        let cases = [
            // Syntax: at the token.
            ("    lett x = 1.0;", "t.wgsl:6:10: WGSL syntax: expected"),
            // A name: at the name.
            (
                "    let x = nothing * 2.0;",
                "t.wgsl:6:13: WGSL name: no definition in scope",
            ),
            // A declared type the value does not have: at the value, not `x`.
            (
                "    let x: f32 = params.size;",
                "t.wgsl:6:18: WGSL type: the type of `x` is expected to be `f32`",
            ),
            // A wrong argument: at the argument, not the call.
            (
                "    let x = sqrt(id.x);",
                "t.wgsl:6:18: WGSL type: wrong type passed as argument #1 to `sqrt` \
                 (argument #1 has type `u32`)",
            ),
            // naga's validation: at the expression, not the `let`.
            (
                "    let x = 2.0 * (params.gain + id.x);",
                "t.wgsl:6:20: validation: ",
            ),
            (
                "    textureStore(out, id.xy, vec4<f32>(1.0) * params.size);",
                "t.wgsl:6:30: validation: ",
            ),
        ];
        for (body, expected) in cases {
            let e = error(body);
            assert!(e.starts_with(expected), "`{body}`: {e}");
        }
        // In a function that is no entry point, naga lists the function's
        // span before the expression's: still at the expression.
        let text = "fn helper(a: f32, b: u32) -> f32 {\n    return 2.0 * (a + b);\n}\n";
        let e = parse_and_validate("t.wgsl", text).expect_err("f32 + u32");
        assert!(
            e.to_string().starts_with("t.wgsl:2:19: validation: "),
            "{e}"
        );
    }
}
