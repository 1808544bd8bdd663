//! `MaterialByName`: picks materials out of a spread by name, with their
//! material ids, so a patch can change one material of a glTF file (the
//! glTF node's Materials and Material Names) and put it back with a
//! `MaterialManager`: glTF -> MaterialByName -> AddReflection ->
//! MaterialManager (Materials: the glTF's, Material ID: this node's) ->
//! MaterialBuffer. The file's other materials, and their ids, stay as they were.

use std::sync::Arc;

use spreadlight_graph::{NodeDef, Registry};
use spreadlight_render::material::Material;

use super::{CATEGORY, MATERIAL, no_materials};
use crate::gpu::{resource_spread, resources};

pub fn register(r: &mut Registry) {
    r.add(
        NodeDef::new(
            "MaterialByName",
            CATEGORY,
            "Finds each Name among Names (slice i names material i, as the glTF node's Material Names does) and \
             outputs that material and its Material ID, one slice per name found. A name that is not there is an \
             error naming it.",
        )
        .input_spread("Materials", MATERIAL, no_materials())
        .input_spread("Names", spreadlight_graph::PinType::String, spreadlight_graph::Spread::String(Vec::new()))
        .input("Name", String::new())
        .output_typed("Material", MATERIAL)
        .output::<i64>("Material ID")
        .evaluate(|cx| {
            let materials = resources::<Material>(cx, 0)?;
            let names = cx.slices::<String>(1)?.to_vec();
            let wanted = cx.slices::<String>(2)?.to_vec();
            let mut found: Vec<Arc<Material>> = Vec::new();
            let mut ids = Vec::new();
            for name in &wanted {
                let Some(id) = names.iter().position(|n| n == name) else {
                    return Err(cx.input_error(2, format!("no material is named `{name}`")));
                };
                let Some(material) = materials.get(id) else {
                    return Err(cx.input_error(
                        0,
                        format!("`{name}` is material {id}, but only {} materials arrive", materials.len()),
                    ));
                };
                found.push(material.clone());
                ids.push(id as i64);
            }
            cx.set_output(0, resource_spread(spreadlight_graph::ResourceKind::Material, found));
            cx.set(1, ids);
            Ok(())
        }),
    );
}
