//! A shader node's pins as values: the numbers a slice gives, the defines
//! its switches select, and their place in the uniform block. Shared by the
//! pass and image kinds (node.rs) and the material kind (material.rs).

use std::collections::BTreeSet;

use spreadlight_graph::{EvalContext, Spread};
use spreadlight_render::shader_nodes::ParamKind;
use spreadlight_render::shader_nodes::ParamPin;

use super::pins::ShaderPins;
use super::shader_type::ShaderType;

/// Slice `i` of a spread as numbers (wrapping), for the uniform block.
pub(super) fn numbers(spread: &Spread, i: usize) -> Vec<f32> {
    fn at<T: Clone>(v: &[T], i: usize) -> Option<T> {
        (!v.is_empty()).then(|| v[i % v.len()].clone())
    }
    match spread {
        Spread::Float(v) => at(v, i).map(|x| vec![x]),
        Spread::Int(v) => at(v, i).map(|x| vec![x as f32]),
        Spread::Bool(v) => at(v, i).map(|x| vec![f32::from(u8::from(x))]),
        Spread::Vec2(v) => at(v, i).map(|x| x.to_array().to_vec()),
        Spread::Vec3(v) => at(v, i).map(|x| x.to_array().to_vec()),
        Spread::Vec4(v) => at(v, i).map(|x| x.to_array().to_vec()),
        Spread::Color(v) => at(v, i).map(|c| vec![c.r, c.g, c.b, c.a]),
        Spread::Mat4(v) => at(v, i).map(|m| m.to_cols_array().to_vec()),
        _ => None,
    }
    .unwrap_or_default()
}

/// The defines slice `slice` selects with the switch and enum pins.
pub(super) fn slice_defines(
    ty: &ShaderType,
    pins: &ShaderPins,
    cx: &EvalContext<'_>,
    slice: usize,
) -> BTreeSet<String> {
    ty.defines(
        &|k| {
            pins.switches
                .get(k)
                .map_or_else(Vec::new, |pin| numbers(cx.spread(*pin), slice))
        },
        &|k| match pins.enums.get(k).map(|pin| cx.spread(*pin)) {
            Some(Spread::Enum(v)) if !v.is_empty() => Some(v[slice % v.len()].clone()),
            _ => None,
        },
    )
}

/// Write every field pin's slice `slice` into a uniform block of `size` bytes.
pub(super) fn uniform_bytes(
    ty: &ShaderType,
    pins: &ShaderPins,
    cx: &EvalContext<'_>,
    size: usize,
    slice: usize,
) -> Vec<u8> {
    let mut bytes = vec![0u8; size];
    for (field, pin) in ty.params().iter().zip(&pins.params) {
        write_param(&mut bytes, field, &numbers(cx.spread(*pin), slice));
    }
    bytes
}

/// Write one pin's value into the uniform block, held to its range.
fn write_param(bytes: &mut [u8], pin: &ParamPin, values: &[f32]) {
    let clamp = |v: f32| {
        let v = if v.is_finite() { v } else { 0.0 };
        let v = pin.min.map_or(v, |m| v.max(m));
        pin.max.map_or(v, |m| v.min(m))
    };
    let words: Vec<u32> = match pin.kind {
        ParamKind::Int => values.iter().map(|v| (clamp(*v) as i32) as u32).collect(),
        ParamKind::Bool => values.iter().map(|v| u32::from(*v != 0.0)).collect(),
        // Colours and matrices are not ranges.
        ParamKind::Color | ParamKind::Mat4 => values
            .iter()
            .map(|v| if v.is_finite() { *v } else { 0.0 }.to_bits())
            .collect(),
        _ => values.iter().map(|v| clamp(*v).to_bits()).collect(),
    };
    for (k, w) in words.iter().enumerate() {
        let at = pin.offset as usize + 4 * k;
        if let Some(slot) = bytes.get_mut(at..at + 4) {
            slot.copy_from_slice(&w.to_le_bytes());
        }
    }
}
