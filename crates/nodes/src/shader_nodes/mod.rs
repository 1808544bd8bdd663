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

/// Register the shipped examples. One that does not compile (a bug a test
/// catches) is registered as a node that shows its error.
pub fn register(r: &mut Registry) {
    builtin_blur::register(r);
    for (name, loaded) in examples() {
        match loaded {
            Ok(ty) => r.add(ty.node_def(None)),
            Err(e) => r.add(def::broken_def(name, e)),
        }
    }
}

/// The shipped example named `name` (a type name), if it compiled.
fn shipped(name: &str) -> Option<Arc<ShaderType>> {
    examples()
        .iter()
        .find(|(n, _)| n == name)
        .and_then(|(_, loaded)| loaded.as_ref().ok().cloned())
}

/// A shipped example's node type name and what loading it gave.
type LoadedExample = (String, Result<Arc<ShaderType>, ShaderNodeError>);

/// The shipped examples, parsed and validated once per process: their
/// sources are compiled in, so every registry (each CLI command, runtime
/// and test builds one) would otherwise run naga over the same files again.
fn examples() -> &'static [LoadedExample] {
    static EXAMPLES_LOADED: std::sync::OnceLock<Vec<LoadedExample>> = std::sync::OnceLock::new();
    EXAMPLES_LOADED.get_or_init(|| {
        EXAMPLES
            .iter()
            .map(|(stem, path, source)| {
                let name = type_name(stem);
                let loaded = ShaderType::load(&name, path, source);
                (name, loaded)
            })
            .collect()
    })
}

#[cfg(test)]
mod light_tests;
#[cfg(test)]
mod material_tests;
#[cfg(test)]
mod tests;
#[cfg(test)]
mod world_tests;
