//! A shader node's evaluation: per slice of its spreads, the permutation its
//! switches select, the uniform block filled from its pins, and a recipe
//! whose passes the frame graph runs (or culls). A spread on any pin gives a
//! spread of textures, one recipe per slice, as vvvv's TextureFX do.
//! Where a version of the file cannot run (a permutation that does not
//! compile, a device limit), the version it replaced runs instead, with the
//! error shown on the node.

use std::sync::Arc;

use spreadlight_graph::{EvalContext, Node, NodeError, ResourceKind};
use spreadlight_render::TextureRef;
use spreadlight_render::gbuffer::GBuffer;
use spreadlight_render::material::MaterialWorld;
use spreadlight_render::shader_nodes::{ShaderNodeError, ShaderNodeInputs, ShaderNodeRecipe};

use super::params::{numbers, slice_defines, write_param};
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

/// Why a version of a file could not evaluate: the file's own fault (a
/// permutation that does not compile, a device limit), which its previous
/// version may not have, or the node's (an input not connected).
pub(super) enum Failure {
    Shader(ShaderNodeError),
    Node(NodeError),
}

impl From<NodeError> for Failure {
    fn from(e: NodeError) -> Self {
        Failure::Node(e)
    }
}

impl Node for ShaderNode {
    fn evaluate(&mut self, cx: &mut EvalContext<'_>) -> Result<(), NodeError> {
        let mut shown: Vec<String> = self.error.iter().map(ToString::to_string).collect();
        let result = match run(&self.ty, cx) {
            // The version before runs in its place, showing why.
            Err(Failure::Shader(e)) => match self.ty.previous() {
                Some(previous) => {
                    shown.push(e.to_string());
                    run(previous, cx).map_err(|_| Failure::Shader(e))
                }
                None => Err(Failure::Shader(e)),
            },
            other => other,
        };
        match result {
            Ok(()) => {
                if !shown.is_empty() {
                    cx.report(NodeError::Other(shown.join("\n")));
                }
                Ok(())
            }
            Err(Failure::Shader(e)) => Err(NodeError::Other(e.to_string())),
            Err(Failure::Node(e)) => Err(e),
        }
    }
}

/// Evaluate one version of the file.
fn run(ty: &Arc<ShaderType>, cx: &mut EvalContext<'_>) -> Result<(), Failure> {
    if ty.is_material() {
        return super::material::evaluate(ty, cx);
    }
    if ty.is_light() {
        return super::light::evaluate(ty, cx);
    }
    let renderer = renderer(cx)?;
    let inputs = ty.notes.inputs.len();
    let mut textures = Vec::with_capacity(inputs);
    for pin in 0..inputs {
        let t = resources::<TextureRef>(cx, pin)?;
        if t.is_empty() {
            return Err(cx.input_error(pin, "no texture connected").into());
        }
        textures.push(t);
    }
    let gbuffers = if ty.reads_gbuffer() {
        let g = resources::<GBuffer>(cx, inputs)?;
        if g.is_empty() {
            return Err(cx.input_error(inputs, "no G-buffer connected").into());
        }
        g
    } else {
        Vec::new()
    };
    let worlds = if ty.materials_pin() {
        let pin = inputs + usize::from(ty.reads_gbuffer());
        let w = resources::<MaterialWorld>(cx, pin)?;
        if w.is_empty() {
            return Err(cx
                .input_error(
                    pin,
                    "no Material World connected (the file imports spreadlight::materials): wire a MaterialBuffer",
                )
                .into());
        }
        w
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
    if ty.materials_pin() {
        lens.push(worlds.len());
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
        let defines = slice_defines(ty, cx, first + params.len(), slice);
        let (program, fresh) = ty.program(&defines).map_err(Failure::Shader)?;
        program
            .check_limits(&limits, renderer.output_size())
            .map_err(Failure::Shader)?;
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
                gbuffer: (!gbuffers.is_empty()).then(|| gbuffers[slice % gbuffers.len()].clone()),
                materials: (!worlds.is_empty()).then(|| worlds[slice % worlds.len()].clone()),
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
    Ok(())
}
