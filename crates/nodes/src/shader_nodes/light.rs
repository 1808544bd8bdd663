//! Evaluating a light shader node (`// @light point spot sun`): the
//! CookTorrance light loop over one light buffer, the same clusters and
//! shadow maps, with the file's `light` function in place of the BRDF. Its
//! Diffuse and Specular outputs go into CompositeLight as CookTorrance's do.
//! One light buffer, one G-buffer and one pass: a spread on a pin gives its
//! first slice (the loop's cluster buffers are kept per node).

use std::sync::Arc;

use spreadlight_graph::EvalContext;
use spreadlight_render::lighting::{CookTorrance, LightBuffer, LightKind, Surfaces};

use super::failure::Failure;
use super::params::slice_defines;
use super::pins::{Main, ShaderPins};
use super::shader_type::ShaderType;
use crate::gpu::renderer;

fn kind_name(kind: LightKind) -> &'static str {
    match kind {
        LightKind::Point => "point",
        LightKind::Spot => "spot",
        LightKind::Sun => "sun",
    }
}

pub(super) fn evaluate(
    ty: &Arc<ShaderType>,
    pins: &ShaderPins,
    cx: &mut EvalContext<'_>,
) -> Result<(), Failure> {
    let (Some(light), Main::Light { diffuse, specular }) = (pins.light, pins.main) else {
        return Err(Failure::other_kind(&ty.file));
    };
    let renderer = renderer(cx)?;
    let gbuffer = cx
        .first_resource(light.gbuffer)?
        .ok_or_else(|| cx.error(light.gbuffer, "no G-buffer connected"))?;
    let declared = ty.light_kinds();
    let lights = match cx.first_resource(light.lights)? {
        Some(l) => l,
        None => LightBuffer::points(&renderer, &[]),
    };
    // A type the file does not declare is not compiled: refused here, at the pin.
    if !declared.contains(&lights.kind) && lights.count() > 0 {
        let names: Vec<&str> = declared.iter().map(|k| kind_name(*k)).collect();
        return Err(cx
            .error(
                light.lights,
                format!(
                    "holds {} lights, but {} shades only {} lights (`// @light {}`)",
                    kind_name(lights.kind),
                    ty.file,
                    names.join(" and "),
                    names.join(" ")
                ),
            )
            .into());
    }
    let shadows = cx.first_resource(light.shadows)?;
    if let Some(s) = &shadows
        && s.kind != lights.kind
    {
        return Err(cx
            .error(
                light.shadows,
                format!(
                    "holds shadows of {:?} lights, but Lights holds {:?} lights",
                    s.kind, lights.kind
                ),
            )
            .into());
    }
    let surfaces = match cx.first_resource(light.materials)? {
        Some(world) => Surfaces::Materials(world),
        None => Surfaces::PerMaterialId(Vec::new()),
    };
    let mode = cx.choice(light.light_loop)?;
    let textures = super::material::textures(pins, cx)?;
    let defines = slice_defines(ty, pins, cx, 0);
    let (program, fresh) = ty.program(&defines).map_err(Failure::Shader)?;
    let shader = super::material::spliced(ty, pins, cx, &program, 0, &textures, u64::from(fresh));
    let recipe = CookTorrance::with_light_shader(
        &renderer,
        Some(cx.node_id.0),
        gbuffer,
        lights,
        mode,
        surfaces,
        shadows,
        Arc::new(shader),
    );
    cx.put_resources(diffuse, vec![Arc::new(recipe.diffuse_texture())]);
    cx.put_resources(specular, vec![Arc::new(recipe.specular_texture())]);
    Ok(())
}
