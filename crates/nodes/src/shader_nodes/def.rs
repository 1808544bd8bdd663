//! The node type of a shader file: its pins (uniform fields, texture
//! inputs, switches), help and constructor. Apart from `shader_type.rs` (what
//! a file declares) and `node.rs` (how a node of it evaluates), so neither
//! of those needs the other's insides.

use std::sync::Arc;

use spreadlight_graph::{NodeDef, NodeError, PinType, ResourceKind};
use spreadlight_render::shader_nodes::ShaderNodeError;

use super::node::{Broken, ShaderNode};
use super::pins::ShaderPins;
use super::shader_type::ShaderType;

pub use super::pins::MATERIAL_WORLD;

impl ShaderType {
    /// The node type; `error` (a newer version of the file that failed) is
    /// shown on every node of it while this version keeps rendering.
    pub fn node_def(self: &Arc<Self>, error: Option<ShaderNodeError>) -> NodeDef {
        let category = self
            .notes
            .category
            .clone()
            .unwrap_or_else(|| "Shader".into());
        let mut help = self.notes.help.join(" ");
        let ranges: Vec<String> = self
            .params()
            .iter()
            .filter(|p| p.min.is_some() || p.max.is_some())
            .map(|p| {
                let f = |v: Option<f32>| v.map_or(String::new(), |v| v.to_string());
                format!("{} {}..{}", p.display, f(p.min), f(p.max))
            })
            .collect();
        if !ranges.is_empty() {
            help.push_str(&format!(" Ranges: {}.", ranges.join(", ")));
        }
        if self.materials_pin() {
            help.push_str(
                " Material World: the MaterialBuffer whose materials it reads (spreadlight::materials).",
            );
        }
        if self.is_material() {
            help.push_str(
                " A material: wire a DeferredBase's Layer through it into MRE; its surface function \
                 shades the layer's pixels in the G-buffer (albedo, normal, roughness, metallic, \
                 occlusion, emission).",
            );
        }
        if self.is_light() {
            help.push_str(
                " A light shader: its light function shades every light of the Lights buffer                  reaching a pixel of the G-buffer (through CookTorrance's clusters and the                  Shadows), in place of CookTorrance; wire Diffuse and Specular into                  CompositeLight. Light Loop as CookTorrance's.",
            );
        }
        help.push_str(&format!(" (Shader node: {}.)", self.file));
        let mut def = NodeDef::new(self.name.clone(), format!("Shader/{category}"), help);
        if self.time_dependent() {
            def = def.time_dependent();
        }
        if self.stateful() {
            def = def.stateful();
        }
        let ty = self.clone();
        let error = error.map(|e| NodeError::Other(e.to_string()));
        def.with_pins_node(|p| {
            let pins = Arc::new(ShaderPins::declare(&ty, p));
            move || ShaderNode::new(ty.clone(), pins.clone(), error.clone())
        })
    }
}

/// A node type for a file that has never compiled: no pins, and its error
/// on every node of it (patches that use it keep their values and links).
pub fn broken_def(name: &str, error: &ShaderNodeError) -> NodeDef {
    let message = error.to_string();
    NodeDef::new(
        name.to_owned(),
        "Shader",
        format!("Shader node whose file does not compile: {message}"),
    )
    .output_typed("Texture", PinType::Resource(ResourceKind::Texture))
    // Its values and links wait, without a problem each, for the file to compile.
    .pins_unknown()
    .construct(move || Broken(message.clone()))
}
