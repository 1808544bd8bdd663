//! The material kind of shader node (`// @material`): a file that defines
//! `fn surface(in: SurfaceInput) -> SurfaceOutput` (structs from
//! `shaders/lib/surface.wgsl`), which the G-buffer's surface resolve calls
//! for every pixel of the layer it is given to: the DrawFX of this renderer.
//! The file has no passes or targets; its uniform block (pins), texture
//! inputs and samplers are bound in group 1 of the resolve. What is checked
//! here is what the resolve relies on, each at its place in the file.

use naga::TypeInner;

use super::annotations::Annotations;
use super::error::{ShaderNodeError, Span};

/// The library a material's file takes the place of in the resolve.
pub use crate::gbuffer::SURFACE_MODULE;

/// The function a material file defines.
pub const SURFACE_FUNCTION: &str = "surface";

/// Annotations that make no sense for a material, at their place.
pub fn check_annotations(file: &str, notes: &Annotations) -> Result<(), ShaderNodeError> {
    let refuse = |at: Span, what: &str| {
        Err(ShaderNodeError::at(
            file,
            at,
            format!(
                "a `@material` has no {what}: it shades a DeferredBase layer's pixels in the \
                 G-buffer resolve (see docs/shader-nodes.md)"
            ),
        ))
    };
    if let Some(p) = notes.passes.first() {
        return refuse(p.at, "passes");
    }
    if let Some(t) = notes.targets.first() {
        return refuse(t.at, "render targets");
    }
    if let Some((_, at)) = notes.outputs.first() {
        return refuse(*at, "extra outputs");
    }
    if let Some((_, at)) = notes.gbuffer.first() {
        return refuse(*at, "G-buffer inputs (it writes the G-buffer)");
    }
    Ok(())
}

/// The type's name as written (naga_oil decorates imported names).
fn type_name(module: &naga::Module, ty: naga::Handle<naga::Type>) -> String {
    module.types[ty]
        .name
        .as_deref()
        .map(super::compose::undecorate)
        .unwrap_or_default()
}

/// The file defines `surface(SurfaceInput) -> SurfaceOutput` and no entry point.
pub fn check(
    file: &str,
    text: &str,
    notes: &Annotations,
    module: &naga::Module,
) -> Result<(), ShaderNodeError> {
    let at_material = notes.material.unwrap_or(Span { line: 1, column: 1 });
    // Its own structs of the same names would not be the resolve's.
    if !super::compose::imports(text) || !text.contains("spreadlight::surface") {
        return Err(ShaderNodeError::at(
            file,
            at_material,
            "a material imports the resolve's structs:              `#import spreadlight::surface::{SurfaceInput, SurfaceOutput}`",
        ));
    }
    if let Some(entry) = module.entry_points.first() {
        let at = text
            .find(&format!("fn {}", entry.name))
            .map_or(at_material, |o| super::error::span_of(text, o));
        return Err(ShaderNodeError::at(
            file,
            at,
            format!(
                "`{}` is an entry point: a material has none, the G-buffer resolve calls its `{SURFACE_FUNCTION}` function",
                entry.name
            ),
        ));
    }
    let function = module
        .functions
        .iter()
        .map(|(_, f)| f)
        .find(|f| f.name.as_deref() == Some(SURFACE_FUNCTION))
        .ok_or_else(|| {
            ShaderNodeError::at(
                file,
                at_material,
                format!(
                    "a `@material` defines `fn {SURFACE_FUNCTION}(in: SurfaceInput) -> SurfaceOutput` \
                     (`#import spreadlight::surface::{{SurfaceInput, SurfaceOutput}}`)"
                ),
            )
        })?;
    let at = text
        .find(&format!("fn {SURFACE_FUNCTION}"))
        .map_or(at_material, |o| super::error::span_of(text, o));
    let argument = match function.arguments.as_slice() {
        [a] => type_name(module, a.ty),
        _ => String::new(),
    };
    let result = function
        .result
        .as_ref()
        .map(|r| type_name(module, r.ty))
        .unwrap_or_default();
    let structs = function
        .arguments
        .iter()
        .all(|a| matches!(module.types[a.ty].inner, TypeInner::Struct { .. }));
    if argument != "SurfaceInput" || result != "SurfaceOutput" || !structs {
        return Err(ShaderNodeError::at(
            file,
            at,
            format!(
                "`{SURFACE_FUNCTION}` must be `fn {SURFACE_FUNCTION}(in: SurfaceInput) -> SurfaceOutput` \
                 with the structs of spreadlight::surface (found ({argument}) -> {result})"
            ),
        ));
    }
    Ok(())
}
