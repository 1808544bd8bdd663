//! A shader node's evaluation: per slice of its spreads, the permutation its
//! switches select, the uniform block filled from its pins, and a recipe
//! whose passes the frame graph runs (or culls). A spread on any pin gives a
//! spread of textures, one recipe per slice, as vvvv's TextureFX do.
//! Where a version of the file cannot run (a permutation that does not
//! compile, a device limit), the version it replaced runs instead, with the
//! error shown on the node.

use std::sync::Arc;

use spreadlight_graph::{EvalContext, Node, NodeError};
use spreadlight_render::TextureRef;
use spreadlight_render::shader_nodes::{ShaderNodeInputs, ShaderNodeRecipe};

use super::failure::Failure;
use super::params::{numbers, slice_defines, uniform_bytes};
use super::pins::{Main, ShaderPins};
use super::shader_type::ShaderType;
use crate::gpu::renderer;

pub struct ShaderNode {
    ty: Arc<ShaderType>,
    /// The node type's pins; a previous version of the file has the same.
    pins: Arc<ShaderPins>,
    /// A newer version of the file that failed: shown while this one renders.
    error: Option<NodeError>,
}

impl ShaderNode {
    pub(super) fn new(
        ty: Arc<ShaderType>,
        pins: Arc<ShaderPins>,
        error: Option<NodeError>,
    ) -> Self {
        ShaderNode { ty, pins, error }
    }
}

/// A node of a file that never compiled.
pub struct Broken(pub String);

impl Node for Broken {
    fn evaluate(&mut self, _: &mut EvalContext<'_>) -> Result<(), NodeError> {
        Err(NodeError::Other(self.0.clone()))
    }
}

impl Node for ShaderNode {
    fn evaluate(&mut self, cx: &mut EvalContext<'_>) -> Result<(), NodeError> {
        let mut shown: Vec<String> = self.error.iter().map(ToString::to_string).collect();
        let pins = &self.pins;
        let result = match run(&self.ty, pins, cx) {
            // The version before runs in its place, showing why.
            Err(Failure::Shader(e)) => match self.ty.previous() {
                Some(previous) => {
                    shown.push(e.to_string());
                    run(previous, pins, cx).map_err(|_| Failure::Shader(e))
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
fn run(ty: &Arc<ShaderType>, pins: &ShaderPins, cx: &mut EvalContext<'_>) -> Result<(), Failure> {
    if ty.is_material() {
        return super::material::evaluate(ty, pins, cx);
    }
    if ty.is_light() {
        return super::light::evaluate(ty, pins, cx);
    }
    let Main::Texture(main_out) = pins.main else {
        return Err(Failure::other_kind(&ty.file));
    };
    let renderer = renderer(cx)?;
    let mut textures = Vec::with_capacity(pins.textures.len());
    for pin in &pins.textures {
        let t = cx.resources(*pin)?;
        if t.is_empty() {
            return Err(cx.error(*pin, "no texture connected").into());
        }
        textures.push(t);
    }
    let gbuffers = match pins.gbuffer {
        Some(pin) => {
            let g = cx.resources(pin)?;
            if g.is_empty() {
                return Err(cx.error(pin, "no G-buffer connected").into());
            }
            g
        }
        None => Vec::new(),
    };
    let worlds = match pins.materials {
        Some(pin) => {
            let w = cx.resources(pin)?;
            if w.is_empty() {
                return Err(cx
                    .error(
                        pin,
                        "no Material World connected (the file imports spreadlight::materials): wire a MaterialBuffer",
                    )
                    .into());
            }
            w
        }
        None => Vec::new(),
    };
    // vvvv's rule: as many slices as the longest input, none if one is empty.
    let mut lens: Vec<usize> = textures.iter().map(Vec::len).collect();
    if pins.gbuffer.is_some() {
        lens.push(gbuffers.len());
    }
    if pins.materials.is_some() {
        lens.push(worlds.len());
    }
    lens.extend(pins.value_lens(cx));
    let count = if lens.contains(&0) {
        0
    } else {
        lens.into_iter().max().unwrap_or(1)
    };
    let limits = renderer.gpu.device.limits();
    // Targets scale with the first texture input's size (`ShaderNodeRecipe`'s
    // size basis): known here for an image file's texture, else the frame's.
    let basis = textures
        .first()
        .and_then(|t| t.first())
        .and_then(|t| t.recipe.static_texture())
        .map_or(renderer.output_size(), |g| {
            (g.texture.width(), g.texture.height())
        });
    let main = ty.main_target().to_owned();
    let mut main_textures: Vec<Arc<TextureRef>> = Vec::new();
    let mut outputs: Vec<Vec<Arc<TextureRef>>> = vec![Vec::new(); ty.notes.outputs.len()];
    // The permutations first, so slice 0's recipe can count every compile.
    let mut programs = Vec::with_capacity(count);
    let mut compiled = 0;
    for slice in 0..count {
        let defines = slice_defines(ty, pins, cx, slice);
        let (program, fresh) = ty.program(&defines).map_err(Failure::Shader)?;
        program
            .check_limits(&limits, basis)
            .map_err(Failure::Shader)?;
        compiled += u64::from(fresh);
        programs.push(program);
    }
    for (slice, program) in programs.into_iter().enumerate() {
        let size = program.uniform.as_ref().map_or(0, |u| u.size as usize);
        let bytes = uniform_bytes(ty, pins, cx, size, slice);
        let skips = program
            .passes
            .iter()
            .map(|p| {
                p.skip
                    .as_ref()
                    .and_then(|pin| ty.bool_pin(pin))
                    .and_then(|pin| pins.bool_spread(cx, pin))
                    .is_some_and(|spread| numbers(spread, slice) == [1.0])
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
        main_textures.push(Arc::new(recipe.texture(&main)));
        for ((target, _), out) in ty.notes.outputs.iter().zip(&mut outputs) {
            out.push(Arc::new(recipe.texture(target)));
        }
    }
    cx.put_resources(main_out, main_textures);
    for (pin, out) in pins.outputs.iter().zip(outputs) {
        cx.put_resources(*pin, out);
    }
    Ok(())
}
