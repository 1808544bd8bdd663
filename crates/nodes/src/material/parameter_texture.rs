//! `ParameterTexture`: one parameter of a built-in feature scaled by a layer
//! of the MaterialBuffer's texture array at each pixel's UV, on its own: a
//! number by the layer's red channel (a grayscale map), a colour by its rgb.
//! The feature helpers' Texture ID scales the whole vec4 channel by channel;
//! this maps roughness, metallic, a strength... each by a map of its own.

use std::sync::Arc;

use spreadlight_graph::{EnumDef, NodeDef, Registry, ResourceKind};
use spreadlight_render::material::{Feature, Material};

use super::{CATEGORY, MATERIAL, TEXTURE_ID, no_materials, slice_count_with_materials};
use crate::gpu::{resource_spread, resources};

/// Every built-in feature's parameter names (`Feature::parameters`).
pub static PARAMETER: EnumDef = EnumDef {
    name: "Material Parameter",
    options: &["Roughness", "Metallic", "Reflectance", "Color", "Strength"],
};

const FEATURE_ID: usize = 1;
const PARAMETER_PIN: usize = 2;
const TEXTURE: usize = 3;

pub fn register(r: &mut Registry) {
    r.add(
        NodeDef::new(
            "ParameterTexture",
            CATEGORY,
            "Scales one parameter of feature Feature ID on each material by layer Texture ID of the MaterialBuffer's \
             texture array, at each pixel's UV: a number by the layer's red channel (a grayscale map), a colour by \
             its rgb; the feature's other parameters keep their Texture ID. Parameters: CookTorrance (0) Roughness, \
             Metallic, Reflectance; Emission (1) and FakeSSS (2) Color, Strength. -1: no texture. The material \
             must have the feature (set it first).",
        )
        .input_spread("Material", MATERIAL, no_materials())
        .input("Feature ID", 0i64)
        .input_enum("Parameter", &PARAMETER, "Roughness")
        .input(TEXTURE_ID, -1i64)
        .output_typed("Material", MATERIAL)
        .evaluate(|cx| {
            let inputs = resources::<Material>(cx, 0)?;
            let ids = cx.slices::<i64>(FEATURE_ID)?.to_vec();
            let params = cx.enum_slices(PARAMETER_PIN)?.to_vec();
            let layers = cx.slices::<i64>(TEXTURE)?.to_vec();
            if inputs.is_empty() {
                return Err(cx.input_error(0, "no material: set the feature first (AddCookTorrance...)"));
            }
            let n = slice_count_with_materials(inputs.len(), [ids.len(), params.len(), layers.len()]);
            let mut out = Vec::with_capacity(n);
            for slice in 0..n {
                let id = ids[slice % ids.len()];
                // Only the features whose parameters shading maps (feature_param_at).
                let feature = match id {
                    0 => Feature::CookTorrance,
                    1 => Feature::Emission,
                    2 => Feature::FakeSss,
                    _ => {
                        return Err(cx.input_error(
                            FEATURE_ID,
                            format!("slice {slice}: feature {id} has no mapped parameters (0 CookTorrance, 1 Emission, 2 FakeSSS)"),
                        ));
                    }
                };
                let name = params[slice % params.len()].as_str();
                let Some(param) = feature.parameters().iter().position(|(p, _)| *p == name) else {
                    let names: Vec<&str> = feature.parameters().iter().map(|(p, _)| *p).collect();
                    return Err(cx.input_error(
                        PARAMETER_PIN,
                        format!("slice {slice}: {feature} has no {name}; its parameters are {}", names.join(", ")),
                    ));
                };
                let mut material = Material::clone(&inputs[slice % inputs.len()]);
                if material.params(feature).is_none() {
                    return Err(cx.input_error(
                        0,
                        format!("slice {slice}: the material has no {feature} to map: set it first"),
                    ));
                }
                material.set_param_texture(feature, param, u32::try_from(layers[slice % layers.len()]).ok());
                out.push(Arc::new(material));
            }
            cx.set_output(0, resource_spread(ResourceKind::Material, out));
            Ok(())
        }),
    );
}
