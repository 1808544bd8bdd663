//! Post-processing passes: texture in, texture out, in compute.

pub mod autofocus;
pub mod dof;
pub mod eye_adaptation;
pub mod fxaa;
pub mod glare;
pub mod motion_blur;
pub mod taa;
pub mod tonemap;
pub mod transparency;

pub use autofocus::Autofocus;
pub use dof::{Dof, DofSettings, Focus};
pub use eye_adaptation::{AdaptationSettings, EyeAdaptation};
pub use fxaa::{Fxaa, FxaaQuality};
pub use glare::{Glare, GlareSettings};
pub use motion_blur::{MotionBlur, MotionBlurSettings};
pub use taa::{Taa, TaaQuality, TaaSettings, is_cut};
pub use tonemap::{AdaptedExposure, Tonemap};
pub use transparency::{Transparency, TransparencySettings};

use crate::error::RenderError;
use crate::frame_graph::PassContext;
use crate::shaders::ShaderKey;

/// The largest value the half-float targets are clamped to (65504 overflows).
pub const HALF_MAX: f32 = 65000.0;

/// A uniform buffer holding `words` (f32 or u32 bits, 16-byte aligned by
/// the caller), kept for node `owner` across frames ([`Renderer::uniform`]).
pub(crate) fn uniform(
    renderer: &crate::renderer::Renderer,
    owner: Option<u32>,
    label: &'static str,
    words: &[u32],
) -> wgpu::Buffer {
    renderer.uniform(owner, label, bytemuck::cast_slice(words))
}

/// One compute entry point of `key` over `size` pixels in 8x8 groups, with
/// `bindings` at group 0 (those the entry does not use are dropped).
pub(crate) fn dispatch_entry(
    cx: &mut PassContext<'_>,
    label: &str,
    key: &ShaderKey,
    entry: &'static str,
    bindings: &[(u32, wgpu::BindingResource<'_>)],
    size: (u32, u32),
) -> Result<(), RenderError> {
    dispatch_groups(
        cx,
        label,
        key,
        entry,
        bindings,
        (size.0.div_ceil(8), size.1.div_ceil(8)),
    )
}

/// `entry` in `groups` workgroups: [`dispatch_entry`]'s one per 8x8
/// texels, or a tile pass's one per tile (whose lanes share the tile's pixels).
pub(crate) fn dispatch_groups(
    cx: &mut PassContext<'_>,
    label: &str,
    key: &ShaderKey,
    entry: &'static str,
    bindings: &[(u32, wgpu::BindingResource<'_>)],
    groups: (u32, u32),
) -> Result<(), RenderError> {
    let device = cx.gpu.device.clone();
    let pipeline = cx.shaders.compute_pipeline(&device, key, entry)?;
    let group = cx
        .shaders
        .bind_group(&device, key, entry, &pipeline, 0, bindings)?;
    cx.dispatch(label, &pipeline, &[&group], (groups.0, groups.1, 1));
    Ok(())
}

/// The pass a node that has nothing to do runs instead of its effect: a
/// copy of `source` into `output` (any float format to RGBA16F), with
/// NaN made 0 and values clamped to the half-float range.
pub(crate) fn copy(
    cx: &mut PassContext<'_>,
    source: &str,
    output: &str,
) -> Result<(), RenderError> {
    let (from, to) = (cx.view_named(source)?, cx.view_named(output)?);
    let size = {
        let t = cx.texture_named(output)?;
        (t.width(), t.height())
    };
    let all = [
        (0, wgpu::BindingResource::TextureView(&from)),
        (1, wgpu::BindingResource::TextureView(&to)),
    ];
    cx.dispatch_image_numbered("copy", &ShaderKey::new("post/copy.wgsl", []), &all, size)
}

/// The size of a texture in the frame.
pub(crate) fn size_of(cx: &PassContext<'_>, name: &str) -> Result<(u32, u32), RenderError> {
    let t = cx.texture_named(name)?;
    Ok((t.width(), t.height()))
}

/// f32s as uniform words.
pub(crate) fn words(values: &[f32]) -> Vec<u32> {
    values.iter().map(|v| v.to_bits()).collect()
}
