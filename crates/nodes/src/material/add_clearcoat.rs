//! `AddClearcoat`: the Clearcoat feature (id 7, glTF's
//! `KHR_materials_clearcoat`) on a material from a patch, without a glTF
//! file: a clear lacquer whose GGX lobe CookTorrance adds over the base,
//! dimming the base by the coat's Fresnel reflectance. Factor and Roughness
//! are per material (no texture layer: no shader reads one for the coat).
//! Made by the feature helpers' one function (`add_feature::helper`).

use spreadlight_graph::Registry;
use spreadlight_render::material::Feature;

use super::add_feature::{ValuePin, helper};

pub fn register(r: &mut Registry) {
    r.add(helper(
        "AddClearcoat",
        "Sets a clear coat on each material (glTF's KHR_materials_clearcoat, feature id 7): a colourless \
         lacquer (f0 0.04) over the surface whose own GGX highlight CookTorrance adds, taking from the base the \
         light it reflects. Factor 0..1: how much of the surface is coated; Roughness 0..1: the coat's own \
         roughness (0: a sharp highlight over a rough base, like car paint). Lights through CookTorrance; \
         set AddCookTorrance for the base. No material in: new ones.",
        Feature::Clearcoat,
        false,
        |p| {
            let factor = p.input("Factor", 1.0f32);
            p.range(0.0, 1.0);
            let roughness = p.input("Roughness", 0.0f32);
            p.range(0.0, 1.0);
            vec![ValuePin::Float(factor), ValuePin::Float(roughness)]
        },
    ));
}
