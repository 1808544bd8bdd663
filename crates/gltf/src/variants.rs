//! `KHR_materials_variants`: a file names material variants (a shoe in
//! three colours) and each primitive maps some of them to a material of its
//! own; a primitive without a mapping for the chosen variant keeps its
//! default material. Read from the raw JSON (the gltf crate's
//! `extension_value`), so a malformed mapping is a warning naming the mesh
//! and primitive and the rest of the file loads.
//!
//! The loaded scene keeps every variant ([`GltfScene::variants`], and per
//! instance [`MeshInstance::variant_materials`]); which one is shown is
//! chosen when the instances are drawn ([`MeshInstance::material_in`]), so
//! switching variants neither reloads nor re-uploads anything.

use gltf::Document;
use gltf::json::Value;
use thiserror::Error;

use super::{GltfScene, Importer, MeshInstance};

/// The extension's name, in the file and in messages.
const NAME: &str = "KHR_materials_variants";

/// A variant asked for by a name (or an index) the file does not have.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
#[error("{}", unknown_message(.asked, .variants))]
pub struct UnknownVariant {
    /// What was asked for.
    pub asked: String,
    /// The file's variants, in file order.
    pub variants: Vec<String>,
}

fn unknown_message(asked: &str, variants: &[String]) -> String {
    if variants.is_empty() {
        format!(
            "material variant `{asked}`: the file has no {NAME} variants; its default materials are shown"
        )
    } else {
        let names: Vec<String> = variants.iter().map(|v| format!("`{v}`")).collect();
        format!(
            "material variant `{asked}` is not one of the file's {} ({}, or an index 0..={}); its default materials are shown",
            variants.len(),
            names.join(", "),
            variants.len() - 1
        )
    }
}

impl GltfScene {
    /// The variant `choice` names: `None` for an empty choice (the file's
    /// default mapping), else the variant of that name, else the variant of
    /// that index (a name takes precedence over a number). An unknown one is
    /// an error listing the file's variants.
    pub fn variant(&self, choice: &str) -> Result<Option<usize>, UnknownVariant> {
        let choice = choice.trim();
        if choice.is_empty() {
            return Ok(None);
        }
        if let Some(i) = self.variants.iter().position(|v| v == choice) {
            return Ok(Some(i));
        }
        match choice.parse::<usize>() {
            Ok(i) if i < self.variants.len() => Ok(Some(i)),
            _ => Err(UnknownVariant {
                asked: choice.to_owned(),
                variants: self.variants.clone(),
            }),
        }
    }
}

impl MeshInstance {
    /// The instance's material in `variant` (`None`: the default mapping):
    /// its primitive's mapping for that variant, else its default material.
    pub fn material_in(&self, variant: Option<usize>) -> Option<usize> {
        variant
            .and_then(|v| self.variant_materials.get(v).copied().flatten())
            .or(self.material)
    }
}

impl Importer<'_> {
    /// The root extension's variant names, in file order ("variant i" for
    /// one without a name, warned).
    pub(super) fn variant_names(&mut self, document: &Document) -> Vec<String> {
        let Some(ext) = document
            .as_json()
            .extensions
            .as_ref()
            .and_then(|e| e.others.get(NAME))
        else {
            return Vec::new();
        };
        let Some(list) = ext.get("variants").and_then(Value::as_array) else {
            self.warn(format!(
                "{NAME}: the root extension has no `variants` array; no variants"
            ));
            return Vec::new();
        };
        list.iter()
            .enumerate()
            .map(|(i, v)| match v.get("name").and_then(Value::as_str) {
                Some(name) => name.to_owned(),
                None => {
                    let name = format!("variant {i}");
                    self.warn(format!("{NAME}: variants[{i}] has no name: `{name}` used"));
                    name
                }
            })
            .collect()
    }

    /// `primitive`'s material per variant (`variants` of them): `Some`
    /// where one of its mappings names the variant. Mappings to a material
    /// or a variant the file does not have are warned and left out; a
    /// variant mapped twice keeps its first mapping (warned).
    pub(super) fn variant_materials(
        &mut self,
        mesh: &gltf::Mesh,
        primitive: &gltf::mesh::Primitive,
        variants: usize,
        materials: usize,
    ) -> Vec<Option<usize>> {
        let mut out = vec![None; variants];
        let Some(ext) = primitive.extension_value(NAME) else {
            return out;
        };
        let who = match mesh.name() {
            Some(name) => format!(
                "mesh {} `{name}` primitive {}",
                mesh.index(),
                primitive.index()
            ),
            None => format!("mesh {} primitive {}", mesh.index(), primitive.index()),
        };
        let Some(mappings) = ext.get("mappings").and_then(Value::as_array) else {
            self.warn(format!("{who}: {NAME} has no `mappings` array; ignored"));
            return out;
        };
        for (m, mapping) in mappings.iter().enumerate() {
            let material = mapping.get("material").and_then(Value::as_u64);
            let Some(material) = material.and_then(|x| usize::try_from(x).ok()) else {
                self.warn(format!(
                    "{who}: {NAME} mappings[{m}] has no material index; ignored"
                ));
                continue;
            };
            if material >= materials {
                self.warn(format!(
                    "{who}: {NAME} mappings[{m}] names material {material}, the file has {materials}; ignored"
                ));
                continue;
            }
            let listed = mapping.get("variants").and_then(Value::as_array);
            for v in listed.into_iter().flatten() {
                let slot = v
                    .as_u64()
                    .and_then(|v| usize::try_from(v).ok())
                    .and_then(|v| out.get_mut(v));
                match slot {
                    Some(slot) if slot.is_none() => *slot = Some(material),
                    Some(_) => self.warn(format!(
                        "{who}: {NAME} mappings[{m}] maps variant {v} again; its first mapping is kept"
                    )),
                    None => self.warn(format!(
                        "{who}: {NAME} mappings[{m}] names variant {v}, the file has {variants}; ignored"
                    )),
                }
            }
        }
        out
    }
}
