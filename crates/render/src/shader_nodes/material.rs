//! The material kind of shader node (`// @material`): a file that defines
//! `fn surface(in: SurfaceInput) -> SurfaceOutput` (structs from
//! `shaders/lib/surface.wgsl`), which the G-buffer's surface resolve calls
//! for every pixel of the layer it is given to: the DrawFX of this renderer.
//! The file has no passes or targets; its uniform block (pins), texture
//! inputs and samplers are bound in group 1 of the resolve. What is checked
//! here is what the resolve relies on, each at its place in the file.

use super::annotations::Annotations;
use super::error::{ShaderNodeError, Span};
use super::hook::Hook;

/// The library a material's file takes the place of in the resolve.
pub use crate::gbuffer::SURFACE_MODULE;

/// The function a material file defines.
pub const SURFACE_FUNCTION: &str = "surface";

/// What the G-buffer resolve asks of a material's file.
const HOOK: Hook = Hook {
    annotation: "a `@material`",
    kind: "a material",
    caller: "the G-buffer resolve",
    function: SURFACE_FUNCTION,
    input: "SurfaceInput",
    output: "SurfaceOutput",
    library: "spreadlight::surface",
};

/// Annotations that make no sense for a material, at their place.
pub fn check_annotations(file: &str, notes: &Annotations) -> Result<(), ShaderNodeError> {
    HOOK.check_annotations(
        file,
        notes,
        "it shades a DeferredBase layer's pixels in the G-buffer resolve",
        "G-buffer inputs (it writes the G-buffer)",
    )
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
    if !super::compose::imports(text) || !text.contains(HOOK.library) {
        return Err(ShaderNodeError::at(
            file,
            at_material,
            "a material imports the resolve's structs:              `#import spreadlight::surface::{SurfaceInput, SurfaceOutput}`",
        ));
    }
    HOOK.check_function(file, text, at_material, module)
}
