//! The uniform block of a shader node file: its fields become the node's
//! pins (type, default, range from the field's `// @` annotation) or
//! built-ins the host fills (size, time, ...), at their byte offsets. Apart
//! from program.rs because it reads one struct type and its annotations, not
//! the bindings and passes of the whole file; program.rs re-exports its types.

use naga::{TypeInner, VectorSize};

use super::annotations::{Annotations, PinDecl};
use super::error::{ShaderNodeError, Span, span_of};

/// The type of a uniform field that is a pin.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ParamKind {
    Float,
    Int,
    /// A `u32` field annotated `bool`: 0 or 1.
    Bool,
    Vec2,
    Vec3,
    Vec4,
    /// A `vec4<f32>` annotated `color`: linear RGBA.
    Color,
    Mat4,
}

/// A uniform field the host fills itself rather than a pin.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Builtin {
    /// `size: vec2<f32>`: the pass's destination size in pixels.
    Size,
    /// `texel: vec2<f32>`: one over it.
    Texel,
    /// `time: f32`, seconds.
    Time,
    /// `delta: f32`, seconds since the last frame.
    Delta,
    /// `iteration: u32`: which repetition of a repeated pass.
    Iteration,
    /// `fresh: u32`: 1 when a persistent destination holds no history (first frame, after a cut).
    Fresh,
    /// `slice: u32`: which slice of the node's spread.
    Slice,
}

impl Builtin {
    fn by_name(name: &str) -> Option<(Builtin, &'static str)> {
        Some(match name {
            "size" => (Builtin::Size, "vec2<f32>"),
            "texel" => (Builtin::Texel, "vec2<f32>"),
            "time" => (Builtin::Time, "f32"),
            "delta" => (Builtin::Delta, "f32"),
            "iteration" => (Builtin::Iteration, "u32"),
            "fresh" => (Builtin::Fresh, "u32"),
            "slice" => (Builtin::Slice, "u32"),
            _ => return None,
        })
    }
}

/// A pin made from a uniform field.
#[derive(Clone, Debug, PartialEq)]
pub struct ParamPin {
    pub field: String,
    pub display: String,
    pub kind: ParamKind,
    /// As many numbers as the kind has (16 for Mat4, column-major).
    pub default: Vec<f32>,
    pub min: Option<f32>,
    pub max: Option<f32>,
    /// Byte offset in the uniform block.
    pub offset: u32,
}

/// The uniform block: its size, its pins and its built-ins.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct UniformLayout {
    pub binding: u32,
    pub size: u32,
    pub pins: Vec<ParamPin>,
    pub builtins: Vec<(Builtin, u32)>,
}

fn kind_of(inner: &TypeInner) -> Option<(&'static str, usize)> {
    use naga::Scalar;
    Some(match inner {
        TypeInner::Scalar(Scalar::F32) => ("f32", 1),
        TypeInner::Scalar(Scalar::I32) => ("i32", 1),
        TypeInner::Scalar(Scalar::U32) => ("u32", 1),
        TypeInner::Vector { size, scalar } if *scalar == Scalar::F32 => match size {
            VectorSize::Bi => ("vec2<f32>", 2),
            VectorSize::Tri => ("vec3<f32>", 3),
            VectorSize::Quad => ("vec4<f32>", 4),
        },
        TypeInner::Matrix {
            columns: VectorSize::Quad,
            rows: VectorSize::Quad,
            scalar,
        } if *scalar == Scalar::F32 => ("mat4x4<f32>", 16),
        _ => return None,
    })
}

/// The line a field is declared on: the first `name:` after the struct's start.
fn field_line(source: &str, struct_offset: usize, field: &str) -> Span {
    let rest = &source[struct_offset.min(source.len())..];
    let found = rest
        .match_indices(field)
        .find(|(i, _)| {
            let after = rest[i + field.len()..].trim_start();
            let before_ok = *i == 0
                || !rest[..*i]
                    .chars()
                    .next_back()
                    .is_some_and(|c| c.is_alphanumeric() || c == '_');
            before_ok && after.starts_with(':')
        })
        .map_or(0, |(i, _)| i);
    span_of(source, struct_offset + found)
}

pub(super) fn uniform_layout(
    file: &str,
    source: &str,
    notes: &Annotations,
    module: &naga::Module,
    ty: naga::Handle<naga::Type>,
    var_at: usize,
    composed: bool,
) -> Result<UniformLayout, ShaderNodeError> {
    let TypeInner::Struct { members, span } = &module.types[ty].inner else {
        return Err(ShaderNodeError::at_offset(
            file,
            source,
            var_at,
            "the uniform block must be a struct (its fields become pins)",
        ));
    };
    let struct_offset = if composed {
        module.types[ty]
            .name
            .as_deref()
            .and_then(|n| super::compose::struct_offset(source, n))
            .unwrap_or(0)
    } else {
        module.types.get_span(ty).to_range().map_or(0, |r| r.start)
    };
    let mut layout = UniformLayout {
        size: *span,
        ..Default::default()
    };
    // The lines of the `@pin` annotations a field took.
    let mut annotated = Vec::new();
    for member in members {
        let name = member.name.clone().unwrap_or_default();
        let at = field_line(source, struct_offset, &name);
        let fail = |m: String| ShaderNodeError::at(file, at, m);
        let (wgsl, count) = kind_of(&module.types[member.ty].inner).ok_or_else(|| {
            fail(format!(
                "field `{name}`: a pin is f32, i32, u32, vec2/3/4<f32> or mat4x4<f32>"
            ))
        })?;
        if let Some((builtin, expected)) = Builtin::by_name(&name) {
            if wgsl != expected {
                return Err(fail(format!(
                    "field `{name}` is the built-in {builtin:?} and must be {expected}, not {wgsl}"
                )));
            }
            layout.builtins.push((builtin, member.offset));
            continue;
        }
        // A pad field is not a pin.
        if name.starts_with('_') {
            continue;
        }
        // The annotation sits on the field's line, or alone on the line above
        // it (one after the field above belongs to that field).
        let line = Some(at.line)
            .filter(|l| notes.pins.contains_key(l))
            .or_else(|| {
                let above = at.line.saturating_sub(1);
                notes.pins.get(&above).filter(|d| d.own_line).map(|_| above)
            });
        let decl = match line {
            Some(line) => {
                annotated.push(line);
                notes.pins.get(&line).cloned().unwrap_or_default()
            }
            None => PinDecl::default(),
        };
        // An annotation's mistakes are at the annotation; a field's own at the field.
        let fail_pin = |m: String| ShaderNodeError::at(file, line.map_or(at, |_| decl.at), m);
        let kind = match (wgsl, decl.color, decl.boolean) {
            ("f32", false, false) => ParamKind::Float,
            ("i32", false, false) => ParamKind::Int,
            ("u32", false, false) => ParamKind::Int,
            ("u32", false, true) => ParamKind::Bool,
            ("vec2<f32>", false, false) => ParamKind::Vec2,
            ("vec3<f32>", false, false) => ParamKind::Vec3,
            ("vec4<f32>", false, false) => ParamKind::Vec4,
            ("vec4<f32>", true, false) => ParamKind::Color,
            ("mat4x4<f32>", false, false) => ParamKind::Mat4,
            _ => {
                return Err(fail_pin(format!(
                    "field `{name}` ({wgsl}): `color` is for vec4<f32>, `bool` for u32"
                )));
            }
        };
        // The settings agree with each other (annotations.rs); here, with the field.
        let range_at = decl.range_at.unwrap_or(decl.at);
        if kind == ParamKind::Mat4 && decl.range_at.is_some() {
            return Err(ShaderNodeError::at(
                file,
                range_at,
                format!(
                    "field `{name}` (mat4x4<f32>) is a matrix, not a range: it takes no `min=` or `max=`"
                ),
            ));
        }
        if decl.default.is_none()
            && (decl.min.is_some_and(|m| m > 0.0) || decl.max.is_some_and(|m| m < 0.0))
        {
            return Err(ShaderNodeError::at(
                file,
                range_at,
                format!(
                    "field `{name}` has no `default=`, and its default 0 is outside its range {}",
                    super::annotations::range_text(&decl)
                ),
            ));
        }
        let default = match &decl.default {
            Some(values) if values.len() == count => values.clone(),
            Some(values) if values.len() == 1 && kind != ParamKind::Mat4 => vec![values[0]; count],
            Some(values) => {
                return Err(fail_pin(format!(
                    "field `{name}`: default has {} numbers, {wgsl} needs {count}",
                    values.len()
                )));
            }
            None if kind == ParamKind::Mat4 => glam::Mat4::IDENTITY.to_cols_array().to_vec(),
            None if kind == ParamKind::Color => vec![1.0; 4],
            None => vec![0.0; count],
        };
        layout.pins.push(ParamPin {
            display: decl
                .display
                .clone()
                .unwrap_or_else(|| super::annotations::title(&name)),
            field: name,
            kind,
            default,
            min: decl.min,
            max: decl.max,
            offset: member.offset,
        });
    }
    if let Some(stray) = notes
        .pins
        .values()
        .find(|d| !annotated.contains(&d.at.line))
    {
        return Err(ShaderNodeError::at(
            file,
            stray.at,
            "`@pin` annotates no pin: put it on a uniform field's line, or alone on the line \
             above one (built-ins and `_` fields are not pins)",
        ));
    }
    Ok(layout)
}
