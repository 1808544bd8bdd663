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

use spreadlight_graph::{EvalContext, NodeError, Registry, ResourceKind};
use spreadlight_render::TextureRef;
use spreadlight_render::gbuffer::GBuffer;

use crate::gpu::{resource_spread, resources};

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
pub(crate) fn texture(cx: &EvalContext<'_>, pin: usize) -> Result<TextureRef, NodeError> {
    resources::<TextureRef>(cx, pin)?
        .into_iter()
        .next()
        .map(|t| (*t).clone())
        .ok_or_else(|| cx.input_error(pin, "no texture connected"))
}

/// The first texture on `pin` if one is connected.
pub(crate) fn optional_texture(
    cx: &EvalContext<'_>,
    pin: usize,
) -> Result<Option<TextureRef>, NodeError> {
    Ok(resources::<TextureRef>(cx, pin)?
        .into_iter()
        .next()
        .map(|t| (*t).clone()))
}

/// The first G-buffer on `pin`, or an error saying what it is for.
pub(crate) fn gbuffer(
    cx: &EvalContext<'_>,
    pin: usize,
    why: &str,
) -> Result<Arc<GBuffer>, NodeError> {
    resources::<GBuffer>(cx, pin)?
        .into_iter()
        .next()
        .ok_or_else(|| cx.input_error(pin, format!("no G-buffer connected: {why}")))
}

/// The first float on `pin`; NaN (and infinity unless `infinite_ok`) is an error naming the pin.
pub(crate) fn float(
    cx: &EvalContext<'_>,
    pin: usize,
    fallback: f32,
    infinite_ok: bool,
) -> Result<f32, NodeError> {
    let v = cx.slices::<f32>(pin)?.first().copied().unwrap_or(fallback);
    if v.is_nan() || (!infinite_ok && v.is_infinite()) {
        return Err(cx.input_error(pin, format!("slice 0 is {v}")));
    }
    Ok(v)
}

/// The first integer on `pin`, within `lo..=hi`, or an error naming the pin.
pub(crate) fn count(
    cx: &EvalContext<'_>,
    pin: usize,
    fallback: i64,
    lo: i64,
    hi: i64,
) -> Result<u32, NodeError> {
    let v = cx.slices::<i64>(pin)?.first().copied().unwrap_or(fallback);
    if !(lo..=hi).contains(&v) {
        return Err(cx.input_error(pin, format!("{v} is not in {lo}..{hi}")));
    }
    Ok(v as u32)
}

/// Output a texture on pin 0.
pub(crate) fn set_texture(cx: &mut EvalContext<'_>, texture: TextureRef) {
    cx.set_output(
        0,
        resource_spread::<TextureRef>(ResourceKind::Texture, vec![Arc::new(texture)]),
    );
}
