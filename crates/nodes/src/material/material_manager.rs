//! `MaterialManager`: places materials at the material IDs the G-buffer
//! stores, as Emeshe's MaterialManager adds them to the material
//! dictionary. Its Materials output is indexed by ID (slice i = material id
//! i), which is what `MaterialBuffer` uploads; managers chain, each setting
//! its IDs on what arrives at Materials, a later one replacing an ID set
//! earlier, as setting a dictionary key does. IDs nobody sets get the
//! default material.

use std::sync::Arc;

use spreadlight_graph::{NodeDef, Registry};
use spreadlight_render::material::Material;

use super::{CATEGORY, material_input, material_output};

/// IDs beyond this are a mistake in a patch, not a scene: the buffer would be mostly defaults.
const MAX_ID: i64 = 65_535;

pub fn register(r: &mut Registry) {
    r.add(
        NodeDef::new(
            "MaterialManager",
            CATEGORY,
            "Places each Material (from a feature chain such as AddCookTorrance) at its Material ID, on top \
             of the materials arriving at Materials (slice i = material id i); a later manager replaces an ID \
             set earlier. IDs no manager sets hold the default material. Feed the result to MaterialBuffer.",
        )
        .with_pins(|p| {
            let placed_in = material_input(p, "Materials");
            let material_in = material_input(p, "Material");
            let id_in = p.input("Material ID", 0i64);
            let out = material_output(p, "Materials");
            move |cx| {
                let mut placed: Vec<Arc<Material>> = cx.resources(placed_in)?;
                let materials = cx.resources(material_in)?;
                let ids = cx.get(id_in)?.to_vec();
                // Unconnected Material: the default material at each ID. No IDs: nothing placed.
                let n = match (materials.len(), ids.len()) {
                    (_, 0) => 0,
                    (0, ids) => ids,
                    (materials, ids) => materials.max(ids),
                };
                let mut seen = std::collections::HashMap::new();
                for slice in 0..n {
                    let id = ids[slice % ids.len()];
                    if !(0..=MAX_ID).contains(&id) {
                        return Err(cx.error(id_in, format!("slice {slice}: id {id} is outside 0..={MAX_ID}")));
                    }
                    if let Some(first) = seen.insert(id, slice) {
                        return Err(cx.error(id_in, format!("id {id} is given twice (slices {first} and {slice})")));
                    }
                    let id = id as usize;
                    if placed.len() <= id {
                        placed.resize_with(id + 1, || Arc::new(Material::default_material()));
                    }
                    placed[id] = match materials.len() {
                        0 => Arc::new(Material::default_material()),
                        len => materials[slice % len].clone(),
                    };
                }
                cx.put_resources(out, placed);
                Ok(())
            }
        }),
    );
}
