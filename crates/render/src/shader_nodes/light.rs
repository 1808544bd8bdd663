//! The light kind of shader node (`// @light point spot sun`): a file that
//! defines `fn light(in: LightInput) -> LightOutput` (structs from
//! `shaders/lib/light_shader.wgsl`), which the CookTorrance light loop calls
//! for every light of a declared type that reaches a pixel, through the same
//! clusters and shadow maps, summing its outputs into Diffuse and Specular:
//! breezEngine's light passes. Like a material it has no passes or targets;
//! its uniform block (pins), texture inputs and samplers are bound in group
//! 2 (group 0 is the light loop's, group 1 the material world's).

use super::annotations::Annotations;
use super::error::{ShaderNodeError, Span};
use super::hook::Hook;
use crate::light_kind::LightKind;
use crate::lighting::cook_torrance_key::CookTorranceKey;
use crate::shaders::{Permutation, ShaderKey};

// The light loop's splice point: the library a light shader's file takes
// the place of, and the group of its own bindings (the loop's, as it binds them).
pub use crate::lighting::cook_torrance_key::{LIGHT_GROUP, LIGHT_MODULE};

/// The function a light shader file defines.
pub const LIGHT_FUNCTION: &str = "light";

/// The light loop's permutation a light shader is spliced into, for a
/// light type (the rest of the key is what the scene calls for).
pub fn loop_key(kind: LightKind) -> ShaderKey {
    CookTorranceKey::custom_light(kind).key()
}

/// What the light loop asks of a light shader's file.
const HOOK: Hook = Hook {
    annotation: "a `@light` shader",
    kind: "a light shader",
    caller: "the light loop",
    function: LIGHT_FUNCTION,
    input: "LightInput",
    output: "LightOutput",
    library: "spreadlight::light_shader",
};

/// Annotations that make no sense for a light shader, at their place.
pub fn check_annotations(file: &str, notes: &Annotations) -> Result<(), ShaderNodeError> {
    let why = format!(
        "the light loop calls its `{LIGHT_FUNCTION}` function for every light reaching a pixel"
    );
    if let Some(at) = notes.material {
        return Err(ShaderNodeError::at(
            file,
            at,
            format!(
                "{} has no `@material` (a file is a material or a light shader): {why} \
                 (see docs/shader-nodes.md)",
                HOOK.annotation
            ),
        ));
    }
    HOOK.check_annotations(
        file,
        notes,
        &why,
        "G-buffer bindings (its `LightInput` carries the pixel's surface)",
    )
}

/// The file defines `light(LightInput) -> LightOutput` and no entry point,
/// and composes into the light loop for each light type it declares.
pub fn check(
    file: &str,
    text: &str,
    notes: &Annotations,
    module: &naga::Module,
) -> Result<(), ShaderNodeError> {
    let (at_light, kinds) = notes
        .light
        .as_ref()
        .map_or((Span { line: 1, column: 1 }, &[][..]), |(at, k)| {
            (*at, k.as_slice())
        });
    if !super::compose::imports(text) || !text.contains(HOOK.library) {
        return Err(ShaderNodeError::at(
            file,
            at_light,
            format!(
                "a light shader imports the light loop's structs: it defines {}",
                HOOK.signature_and_import()
            ),
        ));
    }
    HOOK.check_function(file, text, at_light, module)?;
    let passes: Vec<(ShaderKey, &str)> = kinds
        .iter()
        .map(|k| (loop_key(*k), "the light loop"))
        .collect();
    super::compose::check_spliced(file, text, LIGHT_MODULE, &passes)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn light_types_parse_in_any_separator_and_are_refused_by_name() {
        let notes = Annotations::parse("t.wgsl", "// @light point|spot, sun\n").expect("parses");
        let kinds = notes.light.expect("declared").1;
        assert_eq!(kinds, [LightKind::Point, LightKind::Spot, LightKind::Sun]);
        let e = Annotations::parse("t.wgsl", "\n// @light point area\n").expect_err("area");
        assert_eq!(e.at.line, 2);
        assert!(e.message.contains("unknown light type `area`"), "{e}");
        let e = Annotations::parse("t.wgsl", "// @light\n").expect_err("none");
        assert!(e.message.contains("point, spot, sun"), "{e}");
        let e = Annotations::parse("t.wgsl", "// @light sun sun\n").expect_err("twice");
        assert!(e.message.contains("twice"), "{e}");
    }
}
