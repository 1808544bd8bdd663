//! Shader nodes: WGSL files that are node types (docs/shader-nodes.md).
//! [`ShaderType`] turns one file into a node type, [`ShaderNode`] evaluates
//! it into frame-graph passes, [`ShaderLibrary`] finds files beside the patch
//! and in the user's library and reloads them when they change. The examples
//! in the repository's `shaders/nodes/` are built in.

pub mod builtin_blur;
pub mod def;
mod failure;
pub mod library;
pub mod light;
pub mod material;
pub mod node;
mod params;
mod pins;
pub mod shader_type;

pub use library::{Changes, ShaderLibrary};
pub use node::ShaderNode;
pub use shader_type::{ShaderType, type_name};

use spreadlight_graph::Registry;
use spreadlight_render::shader_nodes::ShaderNodeError;
use std::sync::Arc;

macro_rules! example {
    ($stem:literal) => {
        (
            $stem,
            concat!("shaders/nodes/", $stem, ".wgsl"),
            spreadlight_render::shader_source!("nodes/", $stem, ".wgsl"),
        )
    };
}

/// The shipped examples: (file stem, path in the repository, source).
pub const EXAMPLES: &[(&str, &str, &str)] = &[
    example!("blur"),
    example!("edge_detect"),
    example!("chromatic_aberration"),
    example!("color_grade"),
    example!("lut_warm"),
    example!("noise"),
    example!("feedback"),
    example!("eye_adaptation_chain"),
    example!("procedural_material"),
    example!("rim_light"),
    example!("toon_lights"),
    example!("ashikhmin_shirley"),
];

/// Register the shipped examples, each made (parsed and validated) the
/// first time its type is looked up: a patch that uses none of them, like
/// most, never pays for them (`spreadlight render`'s cold start). One that
/// does not compile (a bug a test catches) is a node that shows its error.
pub fn register(r: &mut Registry) {
    builtin_blur::register(r);
    for (i, (stem, _, _)) in EXAMPLES.iter().enumerate() {
        let name = type_name(stem);
        r.add_lazy(name.clone(), move || match example(i) {
            Some(Ok(ty)) => ty.node_def(None),
            Some(Err(e)) => def::broken_def(&name, e),
            None => def::broken_def(
                &name,
                &ShaderNodeError::at(&name, Default::default(), "no such example".to_owned()),
            ),
        });
    }
}

/// The shipped example named `name` (a type name), if it compiled.
fn shipped(name: &str) -> Option<Arc<ShaderType>> {
    let i = EXAMPLES
        .iter()
        .position(|(stem, _, _)| type_name(stem) == name)?;
    example(i).and_then(|loaded| loaded.as_ref().ok().cloned())
}

/// What loading a shipped example gave.
type LoadedExample = Result<Arc<ShaderType>, ShaderNodeError>;

/// Shipped example `i` of [`EXAMPLES`], parsed and validated once per
/// process and only when asked for: their sources are compiled in, so
/// every registry (each CLI command, runtime and test builds one) would
/// otherwise run naga over the same files again.
fn example(i: usize) -> Option<&'static LoadedExample> {
    static LOADED: [std::sync::OnceLock<LoadedExample>; EXAMPLES.len()] =
        [const { std::sync::OnceLock::new() }; EXAMPLES.len()];
    let (stem, path, source) = EXAMPLES.get(i)?;
    Some(
        LOADED
            .get(i)?
            .get_or_init(|| ShaderType::load(&type_name(stem), path, source)),
    )
}

#[cfg(test)]
mod light_tests;
#[cfg(test)]
mod material_tests;
#[cfg(test)]
mod tests;
#[cfg(test)]
mod world_tests;
