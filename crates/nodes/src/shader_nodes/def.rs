//! The node type of a shader file: its pins (uniform fields, texture
//! inputs, switches), help and constructor. Apart from `shader_type.rs` (what
//! a file declares) and `node.rs` (how a node of it evaluates), so neither
//! of those needs the other's insides.

use std::sync::{Arc, Mutex};

use spreadlight_graph::{Color, EnumDef, NodeDef, NodeError, PinType, ResourceKind, Spread};
use spreadlight_render::shader_nodes::{ParamKind, ParamPin, ShaderNodeError};

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

/// The `EnumDef` of a shader file's `@enum` pin. Pin types name enums by
/// `&'static`, so each distinct (name, options) is made once and kept:
/// reloading a file that did not change its options makes none.
pub(super) fn enum_def(name: &str, options: &[&str]) -> &'static EnumDef {
    static DEFS: Mutex<Vec<&'static EnumDef>> = Mutex::new(Vec::new());
    let mut defs = DEFS.lock().unwrap_or_else(|e| e.into_inner());
    if let Some(found) = defs.iter().find(|d| d.name == name && d.options == options) {
        return found;
    }
    let options: Vec<&'static str> = options
        .iter()
        .map(|o| &*Box::leak(o.to_string().into_boxed_str()))
        .collect();
    let made: &'static EnumDef = Box::leak(Box::new(EnumDef {
        name: Box::leak(name.to_owned().into_boxed_str()),
        options: Box::leak(options.into_boxed_slice()),
    }));
    defs.push(made);
    made
}

/// A field's pin type and its default as a one-slice spread.
pub(super) fn pin_default(p: &ParamPin) -> (PinType, Spread) {
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
    // Its values and links wait, without a problem each, for the file to compile.
    .pins_unknown()
    .construct(move || Broken(message.clone()))
}
