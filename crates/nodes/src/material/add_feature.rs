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

use spreadlight_graph::{Color, EnumDef, EvalContext, NodeDef, NodeError, Registry, Spread};
use spreadlight_render::material::{Feature, MatCapMapping, MatCapMode, matcap_params};

use super::{
    CATEGORY, MATERIAL, TEXTURE_ID, no_materials, not_finite, set_feature,
    slice_count_with_materials,
};

pub fn register(r: &mut Registry) {
    let node = |name, help| {
        NodeDef::new(name, CATEGORY, help)
            .input_spread("Material", MATERIAL, no_materials())
            .output_typed("Material", MATERIAL)
    };
    let color = |r, g, b| Color { r, g, b, a: 1.0 };
    r.add(
        node("AddCookTorrance", "Sets CookTorrance shading on each material: GGX roughness 0..1, metallic 0..1 and reflectance, the f0 of the dielectric part (0.04 for most; 0..1). No material in: new ones.")
            .input("Roughness", 0.5f32)
            .input("Metallic", 0.0f32)
            .input("Reflectance", 0.04f32)
            .input(TEXTURE_ID, -1i64)
            .evaluate(|cx| add(cx, Feature::CookTorrance, 3)),
    );
    r.add(
        node("AddEmission", "Sets emission on each material: linear colour and strength (both >= 0). No material in: new ones.")
            .input("Color", color(1.0, 1.0, 1.0))
            .input("Strength", 1.0f32)
            .input(TEXTURE_ID, -1i64)
            .evaluate(|cx| add(cx, Feature::Emission, 2)),
    );
    r.add(
        node("AddFakeSSS", "Sets faked subsurface scattering on each material: scatter colour and strength (both >= 0). No material in: new ones.")
            .input("Color", color(1.0, 0.2, 0.1))
            .input("Strength", 1.0f32)
            .input(TEXTURE_ID, -1i64)
            .evaluate(|cx| add(cx, Feature::FakeSss, 2)),
    );
    let strength = |name, help| node(name, help).input("Strength", 1.0f32);
    r.add(
        strength("AddReflection", "Sets environment reflection on each material: how much of CompositeLight's Reflection input it takes, 0..1. No material in: new ones.")
            .evaluate(|cx| add(cx, Feature::Reflection, 1)),
    );
    r.add(
        node(
            "AddMatCap",
            "Sets matcap (ZBrush MatCap) shading on each material: CompositeLight looks up a matcap image by each \
             pixel's view-space normal and adds it, times Strength (>= 0). Mode Multiply tints it by the surface's \
             albedo, Add adds it as light. Mapping Normal uses the normal (the image stays put on screen); Reflected \
             uses the view vector reflected about the normal (sphere mapping: the image slides like a reflection). \
             MatCap Texture ID: the layer of the MaterialBuffer's texture array that is the matcap image (-1: a \
             neutral built-in clay matcap). No material in: new ones.",
        )
        .input("Strength", 1.0f32)
        .input_enum("Mode", &MATCAP_MODE, "Multiply")
        .input_enum("Mapping", &MATCAP_MAPPING, "Normal")
        .input(MATCAP_TEXTURE_ID, -1i64)
        .evaluate(add_matcap),
    );
    r.add(
        strength("AddAmbientOcclusion", "Sets ambient occlusion on each material: how much CompositeLight's AO input darkens its ambient light, 0..1 (0: unaffected). No material in: new ones.")
            .evaluate(|cx| add(cx, Feature::AmbientOcclusion, 1)),
    );
}

pub static MATCAP_MODE: EnumDef = EnumDef {
    name: "MatCap Mode",
    options: &["Multiply", "Add"],
};

pub static MATCAP_MAPPING: EnumDef = EnumDef {
    name: "MatCap Mapping",
    options: &["Normal", "Reflected"],
};

/// AddMatCap's layer pin: the matcap image, not a scale of a parameter.
pub const MATCAP_TEXTURE_ID: &str = "MatCap Texture ID";

/// `AddMatCap`: Material, Strength, Mode, Mapping, MatCap Texture ID.
fn add_matcap(cx: &mut EvalContext<'_>) -> Result<(), NodeError> {
    let strength = cx.slices::<f32>(1)?;
    let modes = cx.enum_slices(2)?;
    let mappings = cx.enum_slices(3)?;
    let layers = cx.slices::<i64>(4)?;
    let n = slice_count_with_materials(
        cx.input(0).len(),
        [strength.len(), modes.len(), mappings.len(), layers.len()],
    );
    let mut params = Vec::with_capacity(n);
    for slice in 0..n {
        let s = strength[slice % strength.len()];
        if !s.is_finite() {
            return Err(not_finite(cx, 1, slice));
        }
        let mode = match modes[slice % modes.len()].as_str() {
            "Add" => MatCapMode::Add,
            _ => MatCapMode::Multiply,
        };
        let mapping = match mappings[slice % mappings.len()].as_str() {
            "Reflected" => MatCapMapping::Reflected,
            _ => MatCapMapping::Normal,
        };
        params.push(matcap_params(s, mode, mapping));
    }
    set_feature(cx, 0, n, 1, Some(4), |_, slice| {
        Ok((Feature::MatCap, vec![params[slice]]))
    })
}

/// The value pins of a helper as per-slice components.
enum Pin<'a> {
    Float(&'a [f32]),
    Color(&'a [Color]),
}

impl Pin<'_> {
    fn len(&self) -> usize {
        match self {
            Pin::Float(v) => v.len(),
            Pin::Color(v) => v.len(),
        }
    }
}

/// `feature` from the `values` pins after Material (1..=values).
fn add(cx: &mut EvalContext<'_>, feature: Feature, values: usize) -> Result<(), NodeError> {
    let mut pins = Vec::with_capacity(values);
    for k in 1..=values {
        pins.push(match cx.input(k) {
            Spread::Color(_) => Pin::Color(cx.slices::<Color>(k)?),
            _ => Pin::Float(cx.slices::<f32>(k)?),
        });
    }
    let n = slice_count_with_materials(cx.input(0).len(), pins.iter().map(Pin::len));
    let mut params = Vec::with_capacity(n);
    for slice in 0..n {
        // n > 0 means no pin is empty.
        let mut components = Vec::with_capacity(4);
        for (k, pin) in pins.iter().enumerate() {
            let start = components.len();
            match pin {
                Pin::Float(s) => components.push(s[slice % s.len()]),
                Pin::Color(s) => {
                    let c = s[slice % s.len()];
                    components.extend([c.r, c.g, c.b]);
                }
            }
            if components[start..].iter().any(|c| !c.is_finite()) {
                return Err(not_finite(cx, k + 1, slice));
            }
        }
        components.resize(4, 0.0);
        params.push([components[0], components[1], components[2], components[3]]);
    }
    // Only features a shader maps by texture have a Texture ID pin (after the values).
    let texture_pin = (cx.input_count() > values + 1).then_some(values + 1);
    set_feature(cx, 0, n, 1, texture_pin, |_, slice| {
        Ok((feature, vec![params[slice]]))
    })
}
