//! A shader node's evaluation: per slice of its spreads, the permutation its
//! switches select, the uniform block filled from its pins, and a recipe
//! whose passes the frame graph runs (or culls). A spread on any pin gives a
//! spread of textures, one recipe per slice, as vvvv's TextureFX do.

use std::collections::BTreeSet;
use std::sync::Arc;

use spreadlight_graph::{EvalContext, Node, NodeError, ResourceKind, Spread};
use spreadlight_render::TextureRef;
use spreadlight_render::gbuffer::GBuffer;
use spreadlight_render::shader_nodes::{ParamKind, ParamPin, ShaderNodeInputs, ShaderNodeRecipe};

use super::shader_type::ShaderType;
use crate::gpu::{renderer, resource_spread, resources};

pub struct ShaderNode {
    ty: Arc<ShaderType>,
    /// A newer version of the file that failed: shown while this one renders.
    error: Option<NodeError>,
}

impl ShaderNode {
    pub fn new(ty: Arc<ShaderType>, error: Option<NodeError>) -> Self {
        ShaderNode { ty, error }
    }
}

/// A node of a file that never compiled.
pub struct Broken(pub String);

impl Node for Broken {
    fn evaluate(&mut self, _: &mut EvalContext<'_>) -> Result<(), NodeError> {
        Err(NodeError::Other(self.0.clone()))
    }
}

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

/// The defines slice `slice` selects with the switch and enum pins from input `first_switch`.
pub(super) fn slice_defines(
    ty: &ShaderType,
    cx: &EvalContext<'_>,
    first_switch: usize,
    slice: usize,
) -> BTreeSet<String> {
    ty.defines(
        first_switch,
        &|pin| numbers(cx.input(pin), slice),
        &|pin| match cx.input(pin) {
            Spread::Enum(v) if !v.is_empty() => Some(v[slice % v.len()].clone()),
            _ => None,
        },
    )
}

/// Write one pin's value into the uniform block, held to its range.
pub(super) fn write_param(bytes: &mut [u8], pin: &ParamPin, values: &[f32]) {
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

impl Node for ShaderNode {
    fn evaluate(&mut self, cx: &mut EvalContext<'_>) -> Result<(), NodeError> {
        let ty = self.ty.clone();
        if ty.is_material() {
            super::material::evaluate(&ty, cx)?;
            if let Some(error) = &self.error {
                cx.report(error.clone());
            }
            return Ok(());
        }
        let renderer = renderer(cx)?;
        let inputs = ty.notes.inputs.len();
        let mut textures = Vec::with_capacity(inputs);
        for pin in 0..inputs {
            let t = resources::<TextureRef>(cx, pin)?;
            if t.is_empty() {
                return Err(cx.input_error(pin, "no texture connected"));
            }
            textures.push(t);
        }
        let gbuffers = if ty.reads_gbuffer() {
            let g = resources::<GBuffer>(cx, inputs)?;
            if g.is_empty() {
                return Err(cx.input_error(inputs, "no G-buffer connected"));
            }
            g
        } else {
            Vec::new()
        };
        let first = ty.first_param();
        let params = ty.params();
        // vvvv's rule: as many slices as the longest input, none if one is empty.
        let mut lens: Vec<usize> = textures.iter().map(Vec::len).collect();
        if ty.reads_gbuffer() {
            lens.push(gbuffers.len());
        }
        lens.extend((first..cx.input_count()).map(|pin| cx.input(pin).len()));
        let count = if lens.contains(&0) {
            0
        } else {
            lens.into_iter().max().unwrap_or(1)
        };
        let limits = renderer.gpu.device.limits();
        let main = ty.main_target().to_owned();
        let mut outputs: Vec<Vec<Arc<TextureRef>>> = vec![Vec::new(); 1 + ty.notes.outputs.len()];
        // The permutations first, so slice 0's recipe can count every compile.
        let mut programs = Vec::with_capacity(count);
        let mut compiled = 0;
        for slice in 0..count {
            let defines = slice_defines(&ty, cx, first + params.len(), slice);
            let (program, fresh) = ty
                .program(&defines)
                .map_err(|e| NodeError::Other(e.to_string()))?;
            program
                .check_limits(&limits, renderer.output_size())
                .map_err(|e| NodeError::Other(e.to_string()))?;
            compiled += u64::from(fresh);
            programs.push(program);
        }
        for (slice, program) in programs.into_iter().enumerate() {
            let mut bytes = vec![0u8; program.uniform.as_ref().map_or(0, |u| u.size as usize)];
            for (i, pin) in params.iter().enumerate() {
                write_param(&mut bytes, pin, &numbers(cx.input(first + i), slice));
            }
            let skips = program
                .passes
                .iter()
                .map(|p| {
                    p.skip
                        .as_ref()
                        .and_then(|pin| ty.bool_pin_index(pin))
                        .is_some_and(|k| numbers(cx.input(k), slice) == [1.0])
                })
                .collect();
            let recipe = ShaderNodeRecipe::new(
                Some(cx.node_id.0),
                &ty.name,
                program,
                ShaderNodeInputs {
                    textures: textures
                        .iter()
                        .map(|t| Some((*t[slice % t.len()]).clone()))
                        .collect(),
                    gbuffer: (!gbuffers.is_empty())
                        .then(|| gbuffers[slice % gbuffers.len()].clone()),
                    params: bytes,
                    skips,
                    time: cx.clock.time as f32,
                    delta: cx.clock.delta as f32,
                    slice: slice as u32,
                    compiled: if slice == 0 { compiled } else { 0 },
                },
            );
            outputs[0].push(Arc::new(recipe.texture(&main)));
            for (k, (target, _)) in ty.notes.outputs.iter().enumerate() {
                outputs[k + 1].push(Arc::new(recipe.texture(target)));
            }
        }
        for (k, out) in outputs.into_iter().enumerate() {
            cx.set_output(k, resource_spread(ResourceKind::Texture, out));
        }
        if let Some(error) = &self.error {
            cx.report(error.clone());
        }
        Ok(())
    }
}
