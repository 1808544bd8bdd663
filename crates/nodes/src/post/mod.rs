//! Post-processing nodes (category "Post"): texture in, texture out.

pub mod autofocus;
pub mod dof;
pub mod eye_adaptation;
pub mod fxaa;
pub mod glare;
pub mod motion_blur;
pub mod taa;
pub mod tonemap;
pub mod transparency;

use std::sync::Arc;

use spreadlight_graph::{EvalContext, In, NodeError, Out, Pins, Registry, Res, ResourceKind};
use spreadlight_render::TextureRef;
use spreadlight_render::gbuffer::GBuffer;

pub fn register(r: &mut Registry) {
    eye_adaptation::register(r);
    tonemap::register(r);
    fxaa::register(r);
    dof::register(r);
    autofocus::register(r);
    motion_blur::register(r);
    glare::register(r);
    taa::register(r);
    transparency::register(r);
}

/// The first texture on `pin`, or an error naming it.
pub(crate) fn texture(
    cx: &EvalContext<'_>,
    pin: In<Res<TextureRef>>,
) -> Result<TextureRef, NodeError> {
    cx.first_resource(pin)?
        .map(|t| (*t).clone())
        .ok_or_else(|| cx.error(pin, "no texture connected"))
}

/// The first texture on `pin` if one is connected.
pub(crate) fn optional_texture(
    cx: &EvalContext<'_>,
    pin: In<Res<TextureRef>>,
) -> Result<Option<TextureRef>, NodeError> {
    Ok(cx.first_resource(pin)?.map(|t| (*t).clone()))
}

/// The first G-buffer on `pin`, or an error saying what it is for.
pub(crate) fn gbuffer(
    cx: &EvalContext<'_>,
    pin: In<Res<GBuffer>>,
    why: &str,
) -> Result<Arc<GBuffer>, NodeError> {
    cx.first_resource(pin)?
        .ok_or_else(|| cx.error(pin, format!("no G-buffer connected: {why}")))
}

/// The first float on `pin`; NaN (and infinity unless `infinite_ok`) is an error naming the pin.
pub(crate) fn float(
    cx: &EvalContext<'_>,
    pin: In<f32>,
    fallback: f32,
    infinite_ok: bool,
) -> Result<f32, NodeError> {
    let v = cx.first(pin, fallback)?;
    if v.is_nan() || (!infinite_ok && v.is_infinite()) {
        return Err(cx.error(pin, format!("slice 0 is {v}")));
    }
    Ok(v)
}

/// The first integer on `pin`, within `lo..=hi`, or an error naming the pin.
pub(crate) fn count(
    cx: &EvalContext<'_>,
    pin: In<i64>,
    fallback: i64,
    lo: i64,
    hi: i64,
) -> Result<u32, NodeError> {
    let v = cx.first(pin, fallback)?;
    if !(lo..=hi).contains(&v) {
        return Err(cx.error(pin, format!("{v} is not in {lo}..{hi}")));
    }
    Ok(v as u32)
}

/// Output one texture.
pub(crate) fn set_texture(
    cx: &mut EvalContext<'_>,
    pin: Out<Res<TextureRef>>,
    texture: TextureRef,
) {
    cx.put_resources(pin, vec![Arc::new(texture)]);
}

/// The texture input most post nodes take first.
pub(crate) fn texture_input(p: &mut Pins<'_>, name: &'static str) -> In<Res<TextureRef>> {
    p.input_resource::<TextureRef>(name, ResourceKind::Texture)
}

/// A G-buffer input.
pub(crate) fn gbuffer_input(p: &mut Pins<'_>) -> In<Res<GBuffer>> {
    p.input_resource::<GBuffer>("G-Buffer", ResourceKind::GBuffer)
}

/// The texture output every post node gives.
pub(crate) fn texture_output(p: &mut Pins<'_>, name: &'static str) -> Out<Res<TextureRef>> {
    p.output_resource::<TextureRef>(name, ResourceKind::Texture)
}
