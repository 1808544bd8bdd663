//! `AddIridescence`: the Iridescence feature (id 11, glTF's
//! `KHR_materials_iridescence`) on a material from a patch, without a glTF
//! file: a thin dielectric film (a soap bubble, an oil slick, a beetle's
//! shell) whose interference colours replace Schlick's Fresnel in
//! CookTorrance's lobes and Reflection's. Per material (no texture layer).
//! Made by the feature helpers' one function (`add_feature::helper`).

use spreadlight_graph::Registry;
use spreadlight_render::material::Feature;

use super::add_feature::{ValuePin, helper};

pub fn register(r: &mut Registry) {
    r.add(helper(
        "AddIridescence",
        "Sets a thin film on each material (glTF's KHR_materials_iridescence, feature id 11): its reflection \
         takes interference colours that change with the viewing angle, as a soap bubble's or an oil slick's \
         do (Belcour & Barla's thin-film Fresnel, as the Khronos sample viewer evaluates it). Factor 0..1: how \
         much of the Fresnel is the film's; IOR: the film's index of refraction (1.3 soap, 1.5 oil; kept at 1 \
         or more); Thickness: the film's thickness in nanometres (about 100..1200 shows colours; 0: no film). \
         Lights through CookTorrance and Reflection; set AddCookTorrance for the base. No material in: new ones.",
        Feature::Iridescence,
        false,
        |p| {
            let factor = p.input("Factor", 1.0f32);
            p.range(0.0, 1.0);
            let ior = p.input("IOR", 1.3f32);
            p.range(1.0, 3.0);
            let thickness = p.input("Thickness", 400.0f32);
            p.range(0.0, 1200.0);
            // The thickness minimum is a thickness map's, which a patch has none of.
            vec![
                ValuePin::Float(factor),
                ValuePin::Float(ior),
                ValuePin::Float(thickness),
                ValuePin::Float(thickness),
            ]
        },
    ));
}
