//! Shader nodes: an artist's WGSL file is a node type. Its `// @` comment
//! annotations (see docs/shader-nodes.md) declare the node's help and
//! category, texture inputs, G-buffer reads, render targets and passes; the
//! fields of its uniform block are its pins. This module reads and checks a
//! file ([`Program`]) and declares its passes into the frame graph
//! ([`ShaderNodeRecipe`]); the node library turns files into node types and
//! reloads them when they change.

pub mod annotations;
pub mod builtin_blur;
pub(crate) mod builtin_blur_key;
pub mod compose;
pub mod error;
mod hook;
pub mod light;
pub mod material;
mod preprocess;
pub mod program;
pub mod recipe;
mod uniform_layout;
mod utility;
mod validate;

pub use annotations::Annotations;
pub use error::{ShaderNodeError, Span};
pub use program::{Builtin, Kind, ParamKind, ParamPin, Program, Role, UniformLayout};
pub use recipe::{ShaderNodeInputs, ShaderNodeRecipe};
