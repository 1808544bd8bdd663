//! Shader nodes: WGSL files that are node types (docs/shader-nodes.md).
//! [`ShaderType`] turns one file into a node type, [`ShaderNode`] evaluates
//! it into frame-graph passes, [`ShaderLibrary`] finds files beside the patch
//! and in the user's library and reloads them when they change. The examples
//! in the repository's `shaders/nodes/` are built in.

pub mod builtin_blur;
pub mod def;
pub mod library;
pub mod material;
pub mod node;
pub mod shader_type;

pub use library::{Changes, ShaderLibrary};
pub use node::ShaderNode;
pub use shader_type::{ShaderType, type_name};

use spreadlight_graph::Registry;

macro_rules! example {
    ($stem:literal) => {
        (
            $stem,
            concat!("shaders/nodes/", $stem, ".wgsl"),
            include_str!(concat!("../../../../shaders/nodes/", $stem, ".wgsl")),
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
];

/// Register the shipped examples. One that does not compile (a bug a test
/// catches) is registered as a node that shows its error.
pub fn register(r: &mut Registry) {
    builtin_blur::register(r);
    for (stem, path, source) in EXAMPLES {
        let name = type_name(stem);
        match ShaderType::load(&name, path, source) {
            Ok(ty) => r.add(ty.node_def(None)),
            Err(e) => r.add(def::broken_def(&name, &e)),
        }
    }
}

#[cfg(test)]
mod material_tests;
#[cfg(test)]
mod tests;
