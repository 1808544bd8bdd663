//! Evaluating a light shader node (`// @light point spot sun`): the
//! CookTorrance light loop over one light buffer, the same clusters and
//! shadow maps, with the file's `light` function in place of the BRDF. Its
//! Diffuse and Specular outputs go into CompositeLight as CookTorrance's do.
//! One light buffer, one G-buffer and one pass: a spread on a pin gives its
//! first slice (the loop's cluster buffers are kept per node).

use std::sync::Arc;

use spreadlight_graph::{EvalContext, PinType, ResourceKind, Spread};
use spreadlight_render::TextureRef;
use spreadlight_render::gbuffer::GBuffer;
use spreadlight_render::lighting::{CookTorrance, LightBuffer, LightKind, LightLoop, Surfaces};
use spreadlight_render::material::MaterialWorld;
use spreadlight_render::shadows::ShadowMaps;

use super::node::Failure;
use super::params::slice_defines;
use super::shader_type::ShaderType;
use crate::gpu::{renderer, resource_spread, resources};

/// The pins before a light shader's own: G-Buffer, Lights, Material World, Shadows, Light Loop.
pub const LIGHT_PINS: usize = 5;

/// The fixed pins of a light shader node, in order: (name, type, default).
pub(super) fn pins() -> [(&'static str, PinType, Spread); 4] {
    let resource = |kind| (PinType::Resource(kind), Spread::Resource(kind, vec![]));
    let [g, l, m, s] = [
        ResourceKind::GBuffer,
        ResourceKind::LightWorld,
        ResourceKind::MaterialWorld,
        ResourceKind::Shadows,
    ]
    .map(resource);
    [
        ("G-Buffer", g.0, g.1),
        ("Lights", l.0, l.1),
        ("Material World", m.0, m.1),
        ("Shadows", s.0, s.1),
    ]
}

fn kind_name(kind: LightKind) -> &'static str {
    match kind {
        LightKind::Point => "point",
        LightKind::Spot => "spot",
        LightKind::Sun => "sun",
    }
}

pub(super) fn evaluate(ty: &Arc<ShaderType>, cx: &mut EvalContext<'_>) -> Result<(), Failure> {
    let renderer = renderer(cx)?;
    let gbuffer = resources::<GBuffer>(cx, 0)?
        .into_iter()
        .next()
        .ok_or_else(|| cx.input_error(0, "no G-buffer connected"))?;
    let declared = ty.light_kinds();
    let lights = match resources::<LightBuffer>(cx, 1)?.into_iter().next() {
        Some(l) => l,
        None => LightBuffer::points(&renderer, &[]),
    };
    // A type the file does not declare is not compiled: refused here, at the pin.
    if !declared.contains(&lights.kind) && lights.count() > 0 {
        let names: Vec<&str> = declared.iter().map(|k| kind_name(*k)).collect();
        return Err(cx
            .input_error(
                1,
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
    let shadows = resources::<ShadowMaps>(cx, 3)?.into_iter().next();
    if let Some(s) = &shadows
        && s.kind != lights.kind
    {
        return Err(cx
            .input_error(
                3,
                format!(
                    "holds shadows of {:?} lights, but Lights holds {:?} lights",
                    s.kind, lights.kind
                ),
            )
            .into());
    }
    let surfaces = match resources::<MaterialWorld>(cx, 2)?.into_iter().next() {
        Some(world) => Surfaces::Materials(world),
        None => Surfaces::PerMaterialId(Vec::new()),
    };
    let mode = match cx.enum_slices(4)?.first().map(String::as_str) {
        Some("Naive") => LightLoop::Naive,
        Some("Clustered") => LightLoop::Clustered,
        Some("Tiled") => LightLoop::Tiled,
        Some("Per Pixel") => LightLoop::PerPixel,
        _ => LightLoop::Auto,
    };
    let textures = super::material::textures(ty, cx)?;
    let defines = slice_defines(ty, cx, ty.first_param() + ty.params().len(), 0);
    let (program, fresh) = ty.program(&defines).map_err(Failure::Shader)?;
    let shader = super::material::spliced(ty, cx, &program, 0, &textures, u64::from(fresh));
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
    cx.set_output(
        0,
        resource_spread::<TextureRef>(
            ResourceKind::Texture,
            vec![Arc::new(recipe.diffuse_texture())],
        ),
    );
    cx.set_output(
        1,
        resource_spread::<TextureRef>(
            ResourceKind::Texture,
            vec![Arc::new(recipe.specular_texture())],
        ),
    );
    Ok(())
}
