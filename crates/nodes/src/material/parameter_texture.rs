//! `ParameterTexture`: one parameter of a built-in feature scaled by a layer
//! of the MaterialBuffer's texture array at each pixel's UV, on its own: a
//! number by the layer's red channel (a grayscale map), a colour by its rgb.
//! The feature helpers' Texture ID scales the whole vec4 channel by channel;
//! this maps roughness, metallic, a strength... each by a map of its own.

use std::sync::Arc;

use spreadlight_graph::{Choices, NodeDef, Registry};
use spreadlight_render::material::{Feature, Material};

use super::{CATEGORY, TEXTURE_ID, material_input, material_output, slice_count_with_materials};

const PARAMETER_NAMES: &[&str] = &["Roughness", "Metallic", "Reflectance", "Color", "Strength"];

/// Every built-in feature's parameter names (`Feature::parameters`), each
/// standing for itself: which are valid depends on each slice's feature.
pub static PARAMETER: Choices<&'static str> =
    Choices::new("Material Parameter", PARAMETER_NAMES, PARAMETER_NAMES);

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
        .with_pins(|p| {
            let material = material_input(p, "Material");
            let feature_id = p.input("Feature ID", 0i64);
            let parameter = p.input_choice("Parameter", &PARAMETER, "Roughness");
            let texture = p.input(TEXTURE_ID, -1i64);
            let out = material_output(p, "Material");
            move |cx| {
                let inputs = cx.resources(material)?;
                let ids = cx.get(feature_id)?.to_vec();
                let params = cx.choices(parameter)?;
                let layers = cx.get(texture)?.to_vec();
                if inputs.is_empty() {
                    return Err(cx.error(material, "no material: set the feature first (AddCookTorrance...)"));
                }
                let n = slice_count_with_materials(inputs.len(), [ids.len(), params.len(), layers.len()]);
                let mut materials = Vec::with_capacity(n);
                for slice in 0..n {
                    let id = ids[slice % ids.len()];
                    // Only the features whose parameters shading maps (feature_param_at).
                    let feature = match id {
                        0 => Feature::CookTorrance,
                        1 => Feature::Emission,
                        2 => Feature::FakeSss,
                        _ => {
                            return Err(cx.error(
                                feature_id,
                                format!("slice {slice}: feature {id} has no mapped parameters (0 CookTorrance, 1 Emission, 2 FakeSSS)"),
                            ));
                        }
                    };
                    let name = params[slice % params.len()];
                    let Some(param) = feature.parameters().iter().position(|(p, _)| *p == name) else {
                        let names: Vec<&str> = feature.parameters().iter().map(|(p, _)| *p).collect();
                        return Err(cx.error(
                            parameter,
                            format!("slice {slice}: {feature} has no {name}; its parameters are {}", names.join(", ")),
                        ));
                    };
                    let mut m = Material::clone(&inputs[slice % inputs.len()]);
                    if m.params(feature).is_none() {
                        return Err(cx.error(
                            material,
                            format!("slice {slice}: the material has no {feature} to map: set it first"),
                        ));
                    }
                    m.set_param_texture(feature, param, u32::try_from(layers[slice % layers.len()]).ok());
                    materials.push(Arc::new(m));
                }
                cx.put_resources(out, materials);
                Ok(())
            }
        }),
    );
}
