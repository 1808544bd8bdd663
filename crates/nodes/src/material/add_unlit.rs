//! `AddUnlit`: the Unlit feature (id 8, glTF's `KHR_materials_unlit`) on a
//! material from a patch, without a glTF file: CompositeLight shows the
//! surface's albedo in place of its lighting, mixed by Strength. Made by the
//! feature helpers' one function (`add_feature::helper`).

use spreadlight_graph::Registry;
use spreadlight_render::material::Feature;

use super::add_feature::{ValuePin, helper};

pub fn register(r: &mut Registry) {
    r.add(helper(
        "AddUnlit",
        "Makes each material unlit (glTF's KHR_materials_unlit, feature id 8): CompositeLight shows the \
         surface's albedo (DeferredBase's Color and Color Texture) instead of its lighting, mixed over the lit \
         colour by Strength 0..1 (1: the albedo alone, whatever the lights; 0.5: halfway). No material in: new ones.",
        Feature::Unlit,
        false,
        |p| {
            let strength = p.input("Strength", 1.0f32);
            p.range(0.0, 1.0);
            vec![ValuePin::Float(strength)]
        },
    ));
}
