//! Materials in patch space (category "Material"), after Emeshe:
//! `FeatureManager` sets one feature, by id, on a material; `AddCookTorrance`,
//! `AddEmission`, `AddFakeSSS`, `AddReflection`, `AddMatCap` and
//! `AddAmbientOcclusion` (in `add_feature.rs`) wrap it per built-in feature,
//! as `AddClearcoat` and `AddUnlit` do for the features glTF brought;
//! `ParameterTexture` maps one parameter of a built-in feature by a texture
//! layer; `MaterialManager` places materials at material IDs; `MaterialByName`
//! picks a named one (a glTF file's) to change; `MaterialBuffer`
//! uploads a spread of materials (slice i = material id i) as a `MaterialWorld`.
//!
//! Two resource kinds travel: `ResourceKind::Material` carries CPU-side
//! `Arc<Material>`s (cheap to build and chain, no GPU), and
//! `ResourceKind::MaterialWorld` the uploaded `Arc<MaterialWorld>`, which is
//! what shading passes bind. Only `MaterialBuffer` needs the renderer.

pub mod add_clearcoat;
pub mod add_feature;
pub mod add_iridescence;
pub mod add_unlit;
pub mod feature_manager;
pub mod material_buffer;
pub mod material_by_name;
pub mod material_manager;
pub mod parameter_texture;

use std::sync::Arc;

use spreadlight_graph::typed_pins::InputPin;
use spreadlight_graph::{EvalContext, In, NodeError, Out, Pins, Registry, Res, ResourceKind};
use spreadlight_render::material::{Feature, FeatureError, Material};

pub const CATEGORY: &str = "Material";

pub fn register(r: &mut Registry) {
    feature_manager::register(r);
    add_feature::register(r);
    add_clearcoat::register(r);
    add_iridescence::register(r);
    add_unlit::register(r);
    material_manager::register(r);
    parameter_texture::register(r);
    material_by_name::register(r);
    material_buffer::register(r);
}

/// A pin of CPU-side materials (unconnected: no slices, read as "a new
/// material" by the feature nodes).
pub fn material_input(p: &mut Pins<'_>, name: &'static str) -> In<Res<Material>> {
    p.input_resource::<Material>(name, ResourceKind::Material)
}

/// An output of CPU-side materials.
pub fn material_output(p: &mut Pins<'_>, name: &'static str) -> Out<Res<Material>> {
    p.output_resource::<Material>(name, ResourceKind::Material)
}

/// How many materials a feature node outputs: the spread count of its
/// parameter pins (`counts`), and of its material input unless that is empty,
/// which stands for new materials rather than for nothing.
pub fn slice_count_with_materials(
    materials: usize,
    counts: impl IntoIterator<Item = usize>,
) -> usize {
    let n = spreadlight_graph::spread::slice_count(counts);
    if materials == 0 || n == 0 {
        n
    } else {
        n.max(materials)
    }
}

/// The Texture ID pin every feature node has: which layer of the
/// MaterialBuffer's texture array scales the feature's first parameter.
pub const TEXTURE_ID: &str = "Texture ID";

/// Set `feature` on each of `n` materials from `pin` (wrapping; empty = new
/// materials) with `params(slice)`, and output them on `out`. A refused
/// setting becomes an error on `param_pin` naming the slice. `texture_pin`,
/// when the node has one, holds each slice's texture layer (negative: none).
pub fn set_feature(
    cx: &mut EvalContext<'_>,
    pin: In<Res<Material>>,
    out: Out<Res<Material>>,
    n: usize,
    param_pin: impl InputPin,
    texture_pin: Option<In<i64>>,
    mut params: impl FnMut(&EvalContext<'_>, usize) -> Result<(Feature, Vec<[f32; 4]>), NodeError>,
) -> Result<(), NodeError> {
    let textures = match texture_pin {
        Some(pin) => cx.get(pin)?.to_vec(),
        None => Vec::new(),
    };
    let inputs = cx.resources(pin)?;
    let mut materials = Vec::with_capacity(n);
    for slice in 0..n {
        let (feature, values) = params(cx, slice)?;
        let mut material = match inputs.len() {
            0 => Material::new(),
            len => Material::clone(&inputs[slice % len]),
        };
        material
            .set(feature, &values)
            .map_err(|e| refused(cx, param_pin, slice, e))?;
        let layer = match textures.len() {
            0 => None,
            len => u32::try_from(textures[slice % len]).ok(),
        };
        material.set_texture(feature, layer);
        materials.push(Arc::new(material));
    }
    cx.put_resources(out, materials);
    Ok(())
}

/// A `FeatureError` as an input error on `pin` at `slice`.
pub fn refused(
    cx: &EvalContext<'_>,
    pin: impl InputPin,
    slice: usize,
    e: FeatureError,
) -> NodeError {
    cx.error(pin, format!("slice {slice}: {e}"))
}

/// The error for a NaN or infinity on `pin` at `slice`.
pub fn not_finite(cx: &EvalContext<'_>, pin: impl InputPin, slice: usize) -> NodeError {
    cx.error(pin, format!("slice {slice} is NaN or infinite"))
}

#[cfg(test)]
mod lit_tests;
#[cfg(test)]
mod tests;
