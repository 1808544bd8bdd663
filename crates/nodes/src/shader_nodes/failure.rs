//! Why a version of a shader file could not evaluate, shared by the node
//! (node.rs, which runs the version before in its place) and the kinds it
//! evaluates (material.rs, light.rs): below all of them, so none imports
//! the node to name it.

use spreadlight_graph::NodeError;
use spreadlight_render::shader_nodes::ShaderNodeError;

/// The file's own fault (a permutation that does not compile, a device
/// limit), which its previous version may not have, or the node's (an
/// input not connected).
pub(super) enum Failure {
    Shader(ShaderNodeError),
    Node(NodeError),
}

impl From<NodeError> for Failure {
    fn from(e: NodeError) -> Self {
        Failure::Node(e)
    }
}

impl Failure {
    /// Pins made for another kind of file than `file` (a version that
    /// changed kind keeps no previous version, so this is never expected).
    pub(super) fn other_kind(file: &str) -> Self {
        Failure::Node(NodeError::Other(format!(
            "{file}: the node's pins were made for another kind of shader file"
        )))
    }
}
