//! `MaterialByName`: picks materials out of a spread by name, with their
//! material ids, so a patch can change one material of a glTF file (the
//! glTF node's Materials and Material Names) and put it back with a
//! `MaterialManager`: glTF -> MaterialByName -> AddReflection ->
//! MaterialManager (Materials: the glTF's, Material ID: this node's) ->
//! MaterialBuffer. The file's other materials, and their ids, stay as they were.

use std::sync::Arc;

use spreadlight_graph::{NodeDef, Registry};
use spreadlight_render::material::Material;

use super::{CATEGORY, material_input, material_output};

pub fn register(r: &mut Registry) {
    r.add(
        NodeDef::new(
            "MaterialByName",
            CATEGORY,
            "Finds each Name among Names (slice i names material i, as the glTF node's Material Names does) and \
             outputs that material and its Material ID, one slice per name found. A name that is not there is an \
             error naming it.",
        )
        .with_pins(|p| {
            let materials_in = material_input(p, "Materials");
            let names_in = p.input_spread::<String>("Names", Vec::new());
            let name_in = p.input("Name", String::new());
            let material_out = material_output(p, "Material");
            let id_out = p.output::<i64>("Material ID");
            move |cx| {
                let materials = cx.resources(materials_in)?;
                let names = cx.get(names_in)?.to_vec();
                let wanted = cx.get(name_in)?.to_vec();
                let mut found: Vec<Arc<Material>> = Vec::new();
                let mut ids = Vec::new();
                for name in &wanted {
                    let Some(id) = names.iter().position(|n| n == name) else {
                        return Err(cx.error(name_in, format!("no material is named `{name}`")));
                    };
                    let Some(material) = materials.get(id) else {
                        return Err(cx.error(
                            materials_in,
                            format!("`{name}` is material {id}, but only {} materials arrive", materials.len()),
                        ));
                    };
                    found.push(material.clone());
                    ids.push(id as i64);
                }
                cx.put_resources(material_out, found);
                cx.put(id_out, ids);
                Ok(())
            }
        }),
    );
}
