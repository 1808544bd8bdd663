//! A shader node's pins as handles: declared once from what its file
//! declares (def.rs makes the node type through [`ShaderPins::declare`]) and
//! read by its evaluation (node.rs, material.rs, light.rs, params.rs). How
//! many pins a node has is its file's: texture inputs, fields, switches,
//! enums and extra outputs are families, a handle each, in the file's order.

use std::sync::Mutex;

use spreadlight_graph::{
    AnySpread, Choice, Color, EnumDef, EvalContext, In, Out, PinType, Pins, Res, ResourceKind,
    Spread,
};
use spreadlight_render::TextureRef;
use spreadlight_render::gbuffer::{GBuffer, Layer};
use spreadlight_render::lighting::{LightBuffer, LightLoop};
use spreadlight_render::material::MaterialWorld;
use spreadlight_render::shader_nodes::{ParamKind, ParamPin};
use spreadlight_render::shadows::ShadowMaps;

use super::shader_type::{BoolPin, ShaderType};

/// The pin of an image effect that reads the material world.
pub const MATERIAL_WORLD: &str = "Material World";

/// The pins a light shader has before its own, as CookTorrance's.
#[derive(Clone, Copy)]
pub(super) struct LightPins {
    pub gbuffer: In<Res<GBuffer>>,
    pub lights: In<Res<LightBuffer>>,
    pub materials: In<Res<MaterialWorld>>,
    pub shadows: In<Res<ShadowMaps>>,
    pub light_loop: In<Choice<LightLoop>>,
}

/// What the node gives, by the file's kind.
#[derive(Clone, Copy)]
pub(super) enum Main {
    /// An image effect's texture (its main target).
    Texture(Out<Res<TextureRef>>),
    /// A material's shaded layer.
    Layer(Out<Res<Layer>>),
    /// A light shader's diffuse and specular light.
    Light {
        diffuse: Out<Res<TextureRef>>,
        specular: Out<Res<TextureRef>>,
    },
}

/// Every pin of one shader node type.
#[derive(Clone)]
pub(super) struct ShaderPins {
    /// A material's Layer input.
    pub layer: Option<In<Res<Layer>>>,
    /// A light shader's fixed inputs.
    pub light: Option<LightPins>,
    /// The file's texture inputs (`@input`), in order.
    pub textures: Vec<In<Res<TextureRef>>>,
    /// The G-buffer, when the file reads it.
    pub gbuffer: Option<In<Res<GBuffer>>>,
    /// The material world of an image effect that reads it.
    pub materials: Option<In<Res<MaterialWorld>>>,
    /// One pin per uniform field, in the block's order.
    pub params: Vec<In<AnySpread>>,
    /// One Bool pin per `@switch`.
    pub switches: Vec<In<bool>>,
    /// One pin per `@enum` (its options are the file's).
    pub enums: Vec<In<AnySpread>>,
    pub main: Main,
    /// The file's further render targets as outputs (`@output`).
    pub outputs: Vec<Out<Res<TextureRef>>>,
}

impl ShaderPins {
    /// Declare the pins of `ty`'s node: a material's Layer, a light
    /// shader's G-Buffer, Lights, Material World, Shadows and Light Loop,
    /// then the textures, the G-buffer (if read), the Material World (if an
    /// effect reads it), the fields, the switches and the enums.
    pub fn declare(ty: &ShaderType, p: &mut Pins<'_>) -> Self {
        let texture = |p: &mut Pins<'_>, name: String| {
            p.input_resource::<TextureRef>(name, ResourceKind::Texture)
        };
        let layer = ty
            .is_material()
            .then(|| p.input_resource::<Layer>("Layer", ResourceKind::Layer));
        let light = ty.is_light().then(|| LightPins {
            gbuffer: p.input_resource::<GBuffer>("G-Buffer", ResourceKind::GBuffer),
            lights: p.input_resource::<LightBuffer>("Lights", ResourceKind::LightWorld),
            materials: p
                .input_resource::<MaterialWorld>("Material World", ResourceKind::MaterialWorld),
            shadows: p.input_resource::<ShadowMaps>("Shadows", ResourceKind::Shadows),
            light_loop: p.input_choice(
                "Light Loop",
                &crate::lighting::cook_torrance::LIGHT_LOOPS,
                LightLoop::Auto,
            ),
        });
        let textures = ty
            .notes
            .inputs
            .iter()
            .map(|(_, pin, _)| texture(p, pin.clone()))
            .collect();
        let gbuffer = ty
            .reads_gbuffer()
            .then(|| p.input_resource::<GBuffer>("G-Buffer", ResourceKind::GBuffer));
        let materials = ty.materials_pin().then(|| {
            p.input_resource::<MaterialWorld>(MATERIAL_WORLD, ResourceKind::MaterialWorld)
        });
        let params = ty
            .params()
            .iter()
            .map(|field| {
                let (pin_type, default) = pin_default(field);
                let pin = p.input_any(field.display.clone(), pin_type, default);
                // Colours and matrices are not ranges (write_param holds the rest to it).
                if (field.min.is_some() || field.max.is_some())
                    && !matches!(
                        field.kind,
                        ParamKind::Color | ParamKind::Mat4 | ParamKind::Bool
                    )
                {
                    p.range(
                        field.min.map_or(f64::NEG_INFINITY, f64::from),
                        field.max.map_or(f64::INFINITY, f64::from),
                    );
                }
                pin
            })
            .collect();
        let switches = ty
            .notes
            .switches
            .iter()
            .map(|s| p.input(s.display.clone(), s.default))
            .collect();
        let enums = ty
            .notes
            .enums
            .iter()
            .map(|e| {
                let options: Vec<&str> = e.options.iter().map(String::as_str).collect();
                p.input_any(
                    e.display.clone(),
                    PinType::Enum(enum_def(&e.display, &options)),
                    Spread::Enum(vec![e.options[e.default].clone()]),
                )
            })
            .collect();
        let texture_out = |p: &mut Pins<'_>, name: &str| {
            p.output_resource::<TextureRef>(name.to_owned(), ResourceKind::Texture)
        };
        let main = if ty.is_material() {
            Main::Layer(p.output_resource::<Layer>("Layer", ResourceKind::Layer))
        } else if ty.is_light() {
            Main::Light {
                diffuse: texture_out(p, "Diffuse"),
                specular: texture_out(p, "Specular"),
            }
        } else {
            Main::Texture(texture_out(p, "Texture"))
        };
        let outputs = ty
            .notes
            .outputs
            .iter()
            .map(|(target, _)| {
                texture_out(
                    p,
                    &spreadlight_render::shader_nodes::annotations::title(target),
                )
            })
            .collect();
        ShaderPins {
            layer,
            light,
            textures,
            gbuffer,
            materials,
            params,
            switches,
            enums,
            main,
            outputs,
        }
    }

    /// The spread on a Bool pin a pass's `skip` names.
    pub fn bool_spread<'c>(&self, cx: &'c EvalContext<'_>, pin: BoolPin) -> Option<&'c Spread> {
        match pin {
            BoolPin::Field(i) => self.params.get(i).map(|p| cx.spread(*p)),
            BoolPin::Switch(i) => self.switches.get(i).map(|p| cx.spread(*p)),
        }
    }

    /// The slice counts of the value pins (fields, switches, enums).
    pub fn value_lens(&self, cx: &EvalContext<'_>) -> Vec<usize> {
        let params = self.params.iter().map(|p| cx.spread(*p).len());
        let switches = self.switches.iter().map(|p| cx.spread(*p).len());
        let enums = self.enums.iter().map(|p| cx.spread(*p).len());
        params.chain(switches).chain(enums).collect()
    }
}

/// The `EnumDef` of a shader file's `@enum` pin. Pin types name enums by
/// `&'static`, so each distinct (name, options) is made once and kept:
/// reloading a file that did not change its options makes none.
fn enum_def(name: &str, options: &[&str]) -> &'static EnumDef {
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
