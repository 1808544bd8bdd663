//! `AddCookTorrance`, `AddEmission`, `AddFakeSSS`, `AddReflection`,
//! `AddMatCap`, `AddAmbientOcclusion`: `FeatureManager` with the feature
//! fixed and its vec4 named pin by pin. Each takes a material (none = a new
//! one) and outputs it with the feature set, replacing an earlier setting.
//! One function serves all six: the vec4 is the node's pins after Material,
//! in order, a Float giving one component and a Color three (rgb); then
//! Texture ID, the layer of the MaterialBuffer's texture array that scales
//! that vec4 at each pixel's UV (-1: none), on the features a shader maps
//! (CookTorrance, Emission, FakeSSS; not Reflection or AO). `AddMatCap` has
//! its own pins: Strength, Mode and Mapping, and MatCap Texture ID, the layer
//! that is the matcap image itself.

use spreadlight_graph::typed_pins::InputPin;
use spreadlight_graph::{
    Choice, Choices, Color, EvalContext, In, NodeDef, NodeError, Out, Pins, Registry, Res,
};
use spreadlight_render::material::{Feature, MatCapMapping, MatCapMode, Material, matcap_params};

use super::{
    CATEGORY, TEXTURE_ID, material_input, material_output, not_finite, set_feature,
    slice_count_with_materials,
};

/// One of a helper's value pins: a Float gives one component of the
/// feature's vec4, a Color three (rgb).
#[derive(Clone, Copy)]
pub(super) enum ValuePin {
    Float(In<f32>),
    Color(In<Color>),
}

/// Either kind names its pin in an error.
impl InputPin for ValuePin {
    fn input_index(self) -> usize {
        match self {
            ValuePin::Float(pin) => pin.input_index(),
            ValuePin::Color(pin) => pin.input_index(),
        }
    }
}

/// A helper's pins: Material, the values, Texture ID where the feature is
/// mapped by a texture; and its Material output.
#[derive(Clone)]
struct FeaturePins {
    material: In<Res<Material>>,
    values: Vec<ValuePin>,
    /// The first value pin, named when the feature refuses a setting.
    param: ValuePin,
    texture: Option<In<i64>>,
    out: Out<Res<Material>>,
}

/// A helper node for `feature`: `values` declares its value pins after
/// Material; `mapped` gives it a Texture ID pin after them.
pub(super) fn helper(
    name: &'static str,
    help: &'static str,
    feature: Feature,
    mapped: bool,
    values: impl FnOnce(&mut Pins<'_>) -> Vec<ValuePin>,
) -> NodeDef {
    NodeDef::new(name, CATEGORY, help).with_pins(|p| {
        let material = material_input(p, "Material");
        let values = values(p);
        let texture = mapped.then(|| p.input(TEXTURE_ID, -1i64));
        let out = material_output(p, "Material");
        let param = *values.first().expect("every helper has a value pin");
        let pins = FeaturePins {
            material,
            values,
            param,
            texture,
            out,
        };
        move |cx| add(cx, &pins, feature)
    })
}

pub fn register(r: &mut Registry) {
    let color = |r, g, b| Color { r, g, b, a: 1.0 };
    r.add(helper(
        "AddCookTorrance",
        "Sets CookTorrance shading on each material: GGX roughness 0..1, metallic 0..1 and reflectance, the f0 of the dielectric part (0.04 for most; 0..1). No material in: new ones.",
        Feature::CookTorrance,
        true,
        |p| {
            vec![
                ValuePin::Float(p.input("Roughness", 0.5f32)),
                ValuePin::Float(p.input("Metallic", 0.0f32)),
                ValuePin::Float(p.input("Reflectance", 0.04f32)),
            ]
        },
    ));
    r.add(helper(
        "AddEmission",
        "Sets emission on each material: linear colour and strength (both >= 0). No material in: new ones.",
        Feature::Emission,
        true,
        |p| {
            vec![
                ValuePin::Color(p.input("Color", color(1.0, 1.0, 1.0))),
                ValuePin::Float(p.input("Strength", 1.0f32)),
            ]
        },
    ));
    r.add(helper(
        "AddFakeSSS",
        "Sets faked subsurface scattering on each material: scatter colour and strength (both >= 0). No material in: new ones.",
        Feature::FakeSss,
        true,
        |p| {
            vec![
                ValuePin::Color(p.input("Color", color(1.0, 0.2, 0.1))),
                ValuePin::Float(p.input("Strength", 1.0f32)),
            ]
        },
    ));
    let strength = |p: &mut Pins<'_>| vec![ValuePin::Float(p.input("Strength", 1.0f32))];
    r.add(helper(
        "AddReflection",
        "Sets environment reflection on each material: how much of CompositeLight's Reflection input it takes, 0..1. No material in: new ones.",
        Feature::Reflection,
        false,
        strength,
    ));
    r.add(
        NodeDef::new(
            "AddMatCap",
            CATEGORY,
            "Sets matcap (ZBrush MatCap) shading on each material: CompositeLight looks up a matcap image by each \
             pixel's view-space normal and adds it, times Strength (>= 0). Mode Multiply tints it by the surface's \
             albedo, Add adds it as light. Mapping Normal uses the normal (the image stays put on screen); Reflected \
             uses the view vector reflected about the normal (sphere mapping: the image slides like a reflection). \
             MatCap Texture ID: the layer of the MaterialBuffer's texture array that is the matcap image (-1: a \
             neutral built-in clay matcap). No material in: new ones.",
        )
        .with_pins(|p| {
            let pins = MatCapPins {
                material: material_input(p, "Material"),
                strength: p.input("Strength", 1.0f32),
                mode: p.input_choice("Mode", &MATCAP_MODE, MatCapMode::Multiply),
                mapping: p.input_choice("Mapping", &MATCAP_MAPPING, MatCapMapping::Normal),
                layer: p.input(MATCAP_TEXTURE_ID, -1i64),
                out: material_output(p, "Material"),
            };
            move |cx| add_matcap(cx, pins)
        }),
    );
    r.add(helper(
        "AddAmbientOcclusion",
        "Sets ambient occlusion on each material: how much CompositeLight's AO input darkens its ambient light, 0..1 (0: unaffected). No material in: new ones.",
        Feature::AmbientOcclusion,
        false,
        strength,
    ));
}

pub static MATCAP_MODE: Choices<MatCapMode> = Choices::new(
    "MatCap Mode",
    &["Multiply", "Add"],
    &[MatCapMode::Multiply, MatCapMode::Add],
);

pub static MATCAP_MAPPING: Choices<MatCapMapping> = Choices::new(
    "MatCap Mapping",
    &["Normal", "Reflected"],
    &[MatCapMapping::Normal, MatCapMapping::Reflected],
);

/// AddMatCap's layer pin: the matcap image, not a scale of a parameter.
pub const MATCAP_TEXTURE_ID: &str = "MatCap Texture ID";

/// `AddMatCap`'s pins: Material, Strength, Mode, Mapping, MatCap Texture ID.
#[derive(Clone, Copy)]
struct MatCapPins {
    material: In<Res<Material>>,
    strength: In<f32>,
    mode: In<Choice<MatCapMode>>,
    mapping: In<Choice<MatCapMapping>>,
    layer: In<i64>,
    out: Out<Res<Material>>,
}

fn add_matcap(cx: &mut EvalContext<'_>, pins: MatCapPins) -> Result<(), NodeError> {
    let strength = cx.get(pins.strength)?;
    let modes = cx.choices(pins.mode)?;
    let mappings = cx.choices(pins.mapping)?;
    let layers = cx.get(pins.layer)?;
    let n = slice_count_with_materials(
        cx.spread(pins.material).len(),
        [strength.len(), modes.len(), mappings.len(), layers.len()],
    );
    let mut params = Vec::with_capacity(n);
    for slice in 0..n {
        let s = strength[slice % strength.len()];
        if !s.is_finite() {
            return Err(not_finite(cx, pins.strength, slice));
        }
        let mode = modes[slice % modes.len()];
        let mapping = mappings[slice % mappings.len()];
        params.push(matcap_params(s, mode, mapping));
    }
    set_feature(
        cx,
        pins.material,
        pins.out,
        n,
        pins.strength,
        Some(pins.layer),
        |_, slice| Ok((Feature::MatCap, vec![params[slice]])),
    )
}

/// The value pins of a helper as per-slice components.
enum Values<'a> {
    Float(&'a [f32]),
    Color(&'a [Color]),
}

impl Values<'_> {
    fn len(&self) -> usize {
        match self {
            Values::Float(v) => v.len(),
            Values::Color(v) => v.len(),
        }
    }
}

/// `feature` from the helper's value pins.
fn add(cx: &mut EvalContext<'_>, pins: &FeaturePins, feature: Feature) -> Result<(), NodeError> {
    let mut values = Vec::with_capacity(pins.values.len());
    for pin in &pins.values {
        values.push(match *pin {
            ValuePin::Color(pin) => Values::Color(cx.get(pin)?),
            ValuePin::Float(pin) => Values::Float(cx.get(pin)?),
        });
    }
    let n = slice_count_with_materials(
        cx.spread(pins.material).len(),
        values.iter().map(Values::len),
    );
    let mut params = Vec::with_capacity(n);
    for slice in 0..n {
        // n > 0 means no pin is empty.
        let mut components = Vec::with_capacity(4);
        for (pin, slices) in pins.values.iter().zip(&values) {
            let start = components.len();
            match slices {
                Values::Float(s) => components.push(s[slice % s.len()]),
                Values::Color(s) => {
                    let c = s[slice % s.len()];
                    components.extend([c.r, c.g, c.b]);
                }
            }
            if components[start..].iter().any(|c| !c.is_finite()) {
                return Err(not_finite(cx, *pin, slice));
            }
        }
        components.resize(4, 0.0);
        params.push([components[0], components[1], components[2], components[3]]);
    }
    // A refused setting is named on the first value pin.
    set_feature(
        cx,
        pins.material,
        pins.out,
        n,
        pins.param,
        pins.texture,
        |_, slice| Ok((feature, vec![params[slice]])),
    )
}
