//! What a shader file plugged into a fixed pass must be: a material (called
//! by the G-buffer resolve) and a light shader (called by the light loop)
//! each define one function of one struct to another, have no entry point,
//! and declare no passes, targets or outputs of their own. The checks are
//! the same for both; [`Hook`] names what differs, for the messages.

use naga::TypeInner;

use super::annotations::Annotations;
use super::error::{ShaderNodeError, Span};

/// A kind of shader file that a fixed pass calls into.
pub struct Hook {
    /// The annotation, as messages name it: "a `@material`".
    pub annotation: &'static str,
    /// The kind of file, as messages name it: "a material".
    pub kind: &'static str,
    /// The pass that calls the function: "the G-buffer resolve".
    pub caller: &'static str,
    /// The function the file defines.
    pub function: &'static str,
    /// Its argument's struct.
    pub input: &'static str,
    /// Its result's struct.
    pub output: &'static str,
    /// The library both structs come from.
    pub library: &'static str,
}

impl Hook {
    /// `fn surface(in: SurfaceInput) -> SurfaceOutput`, in backquotes.
    fn signature(&self) -> String {
        let Hook {
            function,
            input,
            output,
            ..
        } = self;
        format!("`fn {function}(in: {input}) -> {output}`")
    }

    /// The signature and the import that brings its structs.
    pub fn signature_and_import(&self) -> String {
        let Hook {
            input,
            output,
            library,
            ..
        } = self;
        format!(
            "{} (`#import {library}::{{{input}, {output}}}`)",
            self.signature()
        )
    }

    /// Refuses passes, render targets, extra outputs and G-buffer bindings,
    /// at their place; `why` says how the file is used instead, and
    /// `gbuffer` what a G-buffer binding would be for this kind.
    pub fn check_annotations(
        &self,
        file: &str,
        notes: &Annotations,
        why: &str,
        gbuffer: &str,
    ) -> Result<(), ShaderNodeError> {
        let refuse = |at: Span, what: &str| {
            Err(ShaderNodeError::at(
                file,
                at,
                format!(
                    "{} has no {what}: {why} (see docs/shader-nodes.md)",
                    self.annotation
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
            return refuse(*at, gbuffer);
        }
        Ok(())
    }

    /// The module has no entry point and defines the function from the
    /// input struct to the output struct; errors point into `text`, or at
    /// `at` (the annotation) where there is no better place.
    pub fn check_function(
        &self,
        file: &str,
        text: &str,
        at: Span,
        module: &naga::Module,
    ) -> Result<(), ShaderNodeError> {
        let Hook {
            annotation,
            kind,
            caller,
            function: name,
            input,
            output,
            library,
        } = self;
        let place = |needle: &str| {
            text.find(needle)
                .map_or(at, |o| super::error::span_of(text, o))
        };
        if let Some(entry) = module.entry_points.first() {
            return Err(ShaderNodeError::at(
                file,
                place(&format!("fn {}", entry.name)),
                format!(
                    "`{}` is an entry point: {kind} has none, {caller} calls its `{name}` function",
                    entry.name
                ),
            ));
        }
        let function = module
            .functions
            .iter()
            .map(|(_, f)| f)
            .find(|f| f.name.as_deref() == Some(*name))
            .ok_or_else(|| {
                ShaderNodeError::at(
                    file,
                    at,
                    format!("{annotation} defines {}", self.signature_and_import()),
                )
            })?;
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
        if argument != *input || result != *output || !structs {
            return Err(ShaderNodeError::at(
                file,
                place(&format!("fn {name}")),
                format!(
                    "`{name}` must be {} with the structs of {library} \
                     (found ({argument}) -> {result})",
                    self.signature()
                ),
            ));
        }
        Ok(())
    }
}

/// The type's name as written (naga_oil decorates imported names).
fn type_name(module: &naga::Module, ty: naga::Handle<naga::Type>) -> String {
    module.types[ty]
        .name
        .as_deref()
        .map(super::error::undecorate)
        .unwrap_or_default()
}
