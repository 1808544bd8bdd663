//! `AddClearcoat`: the Clearcoat feature (id 7, glTF's
//! `KHR_materials_clearcoat`) on a material from a patch, without a glTF
//! file: a clear lacquer whose GGX lobe CookTorrance adds over the base,
//! dimming the base by the coat's Fresnel reflectance. Factor and Roughness
//! are per material (no texture layer: no shader reads one for the coat).

use spreadlight_graph::{In, NodeDef, Registry, ResourceKind};
use spreadlight_render::material::{Feature, Material};

use super::{CATEGORY, not_finite, set_feature, slice_count_with_materials};

pub fn register(r: &mut Registry) {
    r.add(
        NodeDef::new(
            "AddClearcoat",
            CATEGORY,
            "Sets a clear coat on each material (glTF's KHR_materials_clearcoat, feature id 7): a colourless \
             lacquer (f0 0.04) over the surface whose own GGX highlight CookTorrance adds, taking from the base the \
             light it reflects. Factor 0..1: how much of the surface is coated; Roughness 0..1: the coat's own \
             roughness (0: a sharp highlight over a rough base, like car paint). Lights through CookTorrance; \
             set AddCookTorrance for the base. No material in: new ones.",
        )
        .with_pins(|p| {
            let material = p.input_resource::<Material>("Material", ResourceKind::Material);
            let factor = p.input("Factor", 1.0f32);
            p.range(0.0, 1.0);
            let roughness = p.input("Roughness", 0.0f32);
            p.range(0.0, 1.0);
            let out = p.output_resource::<Material>("Material", ResourceKind::Material);
            move |cx| {
                let params = per_slice(cx, material, &[factor, roughness])?;
                set_feature(cx, material, out, params.len(), factor, None, |_, slice| {
                    Ok((Feature::Clearcoat, vec![params[slice]]))
                })
            }
        }),
    );
}

/// The feature's vec4 for each output slice: `pins` in order, one component
/// each (the rest 0), spread over the longest of them and the materials.
/// A NaN or infinity is an error naming its pin and slice; the material
/// clamps the rest into range (`Feature::sanitize`).
pub(super) fn per_slice(
    cx: &spreadlight_graph::EvalContext<'_>,
    material: In<spreadlight_graph::Res<Material>>,
    pins: &[In<f32>],
) -> Result<Vec<[f32; 4]>, spreadlight_graph::NodeError> {
    let values = pins
        .iter()
        .map(|pin| cx.get(*pin))
        .collect::<Result<Vec<_>, _>>()?;
    let n = slice_count_with_materials(cx.spread(material).len(), values.iter().map(|v| v.len()));
    (0..n)
        .map(|slice| {
            let mut out = [0.0; 4];
            for ((pin, v), o) in pins.iter().zip(&values).zip(&mut out) {
                // n > 0 means no pin is empty.
                *o = v[slice % v.len()];
                if !o.is_finite() {
                    return Err(not_finite(cx, *pin, slice));
                }
            }
            Ok(out)
        })
        .collect()
}
