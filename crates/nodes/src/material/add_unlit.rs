//! `AddUnlit`: the Unlit feature (id 8, glTF's `KHR_materials_unlit`) on a
//! material from a patch, without a glTF file: CompositeLight shows the
//! surface's albedo in place of its lighting, mixed by Strength.

use spreadlight_graph::{NodeDef, Registry, ResourceKind};
use spreadlight_render::material::{Feature, Material};

use super::add_clearcoat::per_slice;
use super::{CATEGORY, set_feature};

pub fn register(r: &mut Registry) {
    r.add(
        NodeDef::new(
            "AddUnlit",
            CATEGORY,
            "Makes each material unlit (glTF's KHR_materials_unlit, feature id 8): CompositeLight shows the \
             surface's albedo (DeferredBase's Color and Color Texture) instead of its lighting, mixed over the lit \
             colour by Strength 0..1 (1: the albedo alone, whatever the lights; 0.5: halfway). No material in: new ones.",
        )
        .with_pins(|p| {
            let material = p.input_resource::<Material>("Material", ResourceKind::Material);
            let strength = p.input("Strength", 1.0f32);
            p.range(0.0, 1.0);
            let out = p.output_resource::<Material>("Material", ResourceKind::Material);
            move |cx| {
                let params = per_slice(cx, material, &[strength])?;
                set_feature(cx, material, out, params.len(), strength, None, |_, slice| {
                    Ok((Feature::Unlit, vec![params[slice]]))
                })
            }
        }),
    );
}
