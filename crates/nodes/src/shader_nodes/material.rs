//! Evaluating a material shader node (`// @material`): per slice, the
//! incoming DeferredBase layer with the file's `surface` function attached,
//! its pins written into the uniform block, so the G-buffer resolve shades
//! the layer's pixels with it. A spread of pin values gives a spread of
//! layers (one per slice, layers wrapping), as vvvv's DrawFX do.

use std::sync::Arc;

use spreadlight_graph::EvalContext;
use spreadlight_render::TextureRef;
use spreadlight_render::gbuffer::{SurfaceBinding, SurfaceShader};
use spreadlight_render::shader_nodes::{Builtin, Program, Role};

use super::failure::Failure;
use super::params::{slice_defines, uniform_bytes};
use super::pins::{Main, ShaderPins};
use super::shader_type::ShaderType;

pub(super) fn evaluate(
    ty: &Arc<ShaderType>,
    pins: &ShaderPins,
    cx: &mut EvalContext<'_>,
) -> Result<(), Failure> {
    let (Some(layer_in), Main::Layer(out)) = (pins.layer, pins.main) else {
        return Err(Failure::other_kind(&ty.file));
    };
    let layers = cx.resources(layer_in)?;
    // It reads the material world: every layer it shades must bring one.
    let reads_materials = ty.reads_materials();
    if reads_materials && layers.iter().any(|l| l.materials.is_none()) {
        return Err(cx
            .error(
                layer_in,
                "the file reads the material world (spreadlight::materials), but the layer's \
                 DeferredBase has no Material World: wire a MaterialBuffer to it",
            )
            .into());
    }
    let textures = textures(pins, cx)?;
    // vvvv's rule: as many slices as the longest input, none if one is empty.
    let mut lens = vec![layers.len()];
    lens.extend(textures.iter().map(Vec::len));
    lens.extend(pins.value_lens(cx));
    let count = if lens.contains(&0) {
        0
    } else {
        lens.into_iter().max().unwrap_or(1)
    };
    let mut programs = Vec::with_capacity(count);
    let mut compiled = 0;
    for slice in 0..count {
        let defines = slice_defines(ty, pins, cx, slice);
        let (program, fresh) = ty.program(&defines).map_err(Failure::Shader)?;
        compiled += u64::from(fresh);
        programs.push(program);
    }
    let mut layers_out = Vec::with_capacity(count);
    for (slice, program) in programs.into_iter().enumerate() {
        let surface = spliced(
            ty,
            pins,
            cx,
            &program,
            slice,
            &textures,
            if slice == 0 { compiled } else { 0 },
        )
        .reading_materials(reads_materials);
        let layer = (*layers[slice % layers.len()])
            .clone()
            .with_surface(Some(Arc::new(surface)));
        layers_out.push(Arc::new(layer));
    }
    cx.put_resources(out, layers_out);
    Ok(())
}

/// The textures on the file's texture input pins, each a spread; an
/// unconnected one is an error at its pin.
pub(super) fn textures(
    pins: &ShaderPins,
    cx: &EvalContext<'_>,
) -> Result<Vec<Vec<Arc<TextureRef>>>, Failure> {
    let mut textures = Vec::with_capacity(pins.textures.len());
    for pin in &pins.textures {
        let t = cx.resources(*pin)?;
        if t.is_empty() {
            return Err(cx.error(*pin, "no texture connected").into());
        }
        textures.push(t);
    }
    Ok(textures)
}

/// Slice `slice` of a material or light shader node as the file spliced
/// into a built-in pass: its text, its bindings, the uniform block with the
/// pins and built-ins written, its texture inputs.
pub(super) fn spliced(
    ty: &Arc<ShaderType>,
    pins: &ShaderPins,
    cx: &EvalContext<'_>,
    program: &Program,
    slice: usize,
    textures: &[Vec<Arc<TextureRef>>],
    compiled: u64,
) -> SurfaceShader {
    let size = program.uniform.as_ref().map_or(0, |u| u.size as usize);
    let mut bytes = uniform_bytes(ty, pins, cx, size, slice);
    // The built-ins a spliced file has: the clock and its slice (the rest are 0).
    for (builtin, offset) in program.uniform.iter().flat_map(|u| &u.builtins) {
        let word = match builtin {
            Builtin::Time => (cx.clock.time as f32).to_bits(),
            Builtin::Delta => (cx.clock.delta as f32).to_bits(),
            Builtin::Slice => slice as u32,
            _ => continue,
        };
        let at = *offset as usize;
        if let Some(slot) = bytes.get_mut(at..at + 4) {
            slot.copy_from_slice(&word.to_le_bytes());
        }
    }
    let bindings = program
        .bindings
        .iter()
        .filter_map(|(binding, role)| {
            let what = match role {
                Role::Uniform => SurfaceBinding::Uniform,
                Role::Input(i) => SurfaceBinding::Texture(*i),
                Role::Sampler(d) => SurfaceBinding::Sampler { repeat: d.repeat },
                // Refused for materials and light shaders when the file compiled.
                _ => return None,
            };
            Some((*binding, what))
        })
        .collect();
    SurfaceShader::new(
        format!("{} #{}", ty.name, cx.node_id.0),
        program.file.clone(),
        program.text.clone(),
        program.key,
        bindings,
        bytes,
        textures
            .iter()
            .map(|t| (*t[slice % t.len()]).clone())
            .collect(),
        compiled,
    )
}
