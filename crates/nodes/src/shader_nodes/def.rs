//! The node type of a shader file: its pins (uniform fields, texture
//! inputs, switches), help and constructor. Apart from `shader_type.rs` (what
//! a file declares) and `node.rs` (how a node of it evaluates), so neither
//! of those needs the other's insides.

use std::sync::Arc;

use spreadlight_graph::{Color, NodeDef, NodeError, PinType, ResourceKind, Spread};
use spreadlight_render::shader_nodes::{ParamKind, ParamPin, ShaderNodeError};

use super::node::{Broken, ShaderNode};
use super::shader_type::ShaderType;

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
        help.push_str(&format!(" (Shader node: {}.)", self.file));
        let texture = PinType::Resource(ResourceKind::Texture);
        let mut def = NodeDef::new(self.name.clone(), format!("Shader/{category}"), help);
        for (_, pin, _) in &self.notes.inputs {
            def = def.input_spread(
                pin.clone(),
                texture,
                Spread::Resource(ResourceKind::Texture, vec![]),
            );
        }
        if self.reads_gbuffer() {
            def = def.input_spread(
                "G-Buffer",
                PinType::Resource(ResourceKind::GBuffer),
                Spread::Resource(ResourceKind::GBuffer, vec![]),
            );
        }
        for p in self.params() {
            let (ty, default) = pin_default(p);
            def = def.input_spread(p.display.clone(), ty, default);
        }
        for s in &self.notes.switches {
            def = def.input(s.display.clone(), s.default);
        }
        def = def.output_typed("Texture", texture);
        for (target, _) in &self.notes.outputs {
            def = def.output_typed(
                spreadlight_render::shader_nodes::annotations::title(target),
                texture,
            );
        }
        if self.time_dependent() {
            def = def.time_dependent();
        }
        let ty = self.clone();
        let error = error.map(|e| NodeError::Other(e.to_string()));
        def.construct(move || ShaderNode::new(ty.clone(), error.clone()))
    }
}

/// A field's pin type and its default as a one-slice spread.
fn pin_default(p: &ParamPin) -> (PinType, Spread) {
    let v = &p.default;
    let at = |i: usize| v.get(i).copied().unwrap_or(0.0);
    match p.kind {
        ParamKind::Float => (PinType::Float, Spread::Float(vec![at(0)])),
        ParamKind::Int => (PinType::Int, Spread::Int(vec![at(0) as i64])),
        ParamKind::Bool => (PinType::Bool, Spread::Bool(vec![at(0) != 0.0])),
        ParamKind::Vec2 => (
            PinType::Vec2,
            Spread::Vec2(vec![glam::Vec2::new(at(0), at(1))]),
        ),
        ParamKind::Vec3 => (
            PinType::Vec3,
            Spread::Vec3(vec![glam::Vec3::new(at(0), at(1), at(2))]),
        ),
        ParamKind::Vec4 => (
            PinType::Vec4,
            Spread::Vec4(vec![glam::Vec4::new(at(0), at(1), at(2), at(3))]),
        ),
        ParamKind::Color => (
            PinType::Color,
            Spread::Color(vec![Color::rgba(at(0), at(1), at(2), at(3))]),
        ),
        ParamKind::Mat4 => {
            let mut cols = [0.0; 16];
            for (i, c) in cols.iter_mut().enumerate() {
                *c = at(i);
            }
            (
                PinType::Mat4,
                Spread::Mat4(vec![glam::Mat4::from_cols_array(&cols)]),
            )
        }
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
    .construct(move || Broken(message.clone()))
}
