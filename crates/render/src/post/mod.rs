//! Post-processing passes: texture in, texture out, in compute.

pub mod autofocus;
pub(crate) mod autofocus_key;
pub(crate) mod copy_key;
pub mod dof;
pub(crate) mod dof_key;
pub mod eye_adaptation;
pub(crate) mod eye_adaptation_key;
pub mod fxaa;
pub(crate) mod fxaa_key;
pub mod glare;
pub(crate) mod glare_key;
pub mod motion_blur;
pub(crate) mod motion_blur_key;
pub mod taa;
pub(crate) mod taa_key;
pub mod tonemap;
pub(crate) mod tonemap_key;
pub mod transparency;

pub use autofocus::Autofocus;
pub use dof::{Dof, DofSettings, Focus};
pub use eye_adaptation::{AdaptationSettings, EyeAdaptation};
pub use fxaa::{Fxaa, FxaaQuality};
pub use glare::{Glare, GlareSettings};
pub use motion_blur::{MotionBlur, MotionBlurSettings};
pub use taa::{Taa, TaaQuality, TaaSettings, is_cut};
pub use tonemap::{AdaptedExposure, Tonemap};
pub use transparency::{
    LitBy, RefractionBlur, TransmissionSettings, Transparency, TransparencyKey,
    TransparencySettings, TransparencyShading, TransparentLights,
};

use crate::error::RenderError;
use crate::frame_graph::{Bindings, FrameGraph, PassContext, Tex, TextureDesc};
use crate::report::PassName;
use crate::shaders::{Permutation, ShaderKey};

pub use copy_key::CopyKey;

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

/// Workgroups for one thread per pixel of `size` in 8x8 groups (what
/// [`PassContext::dispatch_image`](crate::frame_graph::PassContext::dispatch_image)
/// does for `main`), for other entry points.
pub(crate) fn per_pixel(size: (u32, u32)) -> (u32, u32, u32) {
    (size.0.div_ceil(8), size.1.div_ceil(8), 1)
}

/// Entry `entry` of `key` writing `output`, with the G-buffer's `camera`
/// and the pass's `params` beside what it declared in `bindings`: one
/// workgroup per texel of `output` for a `tiled` entry (its lanes share the
/// tile's pixels), else one thread per pixel.
#[allow(clippy::too_many_arguments)]
pub(crate) fn dispatch_entry(
    cx: &mut PassContext<'_>,
    key: &ShaderKey,
    entry: &'static str,
    tiled: bool,
    camera: &wgpu::Buffer,
    params: &wgpu::Buffer,
    bindings: Bindings<'_>,
    output: Tex,
) -> Result<(), RenderError> {
    let size = cx.size_of(output)?;
    let groups = if tiled {
        (size.0, size.1, 1)
    } else {
        per_pixel(size)
    };
    let bindings = Bindings::new()
        .buffer("camera", camera)
        .buffer("params", params)
        .extend(bindings);
    cx.dispatch_shader(entry, key, entry, bindings, groups)
}

/// Declare the pass a node that has nothing to do runs instead of its
/// effect: a copy of `source` into `output` (any float format to RGBA16F,
/// NaN made 0, values clamped to the half-float range), counted as `counter`.
pub(crate) fn declare_copy<'a>(
    fg: &mut FrameGraph<'a>,
    name: PassName,
    owner: Option<u32>,
    source: &str,
    output: (&str, TextureDesc),
    counter: &'static str,
) {
    let mut pass = fg.pass(name, owner);
    let source = pass.read(source);
    let output = pass.write(output.0, output.1);
    pass.will_dispatch(&CopyKey.key(), "main");
    pass.run(move |cx| {
        cx.count(counter, 1);
        let size = cx.size_of(output)?;
        cx.dispatch_image(
            "copy",
            &CopyKey.key(),
            Bindings::new()
                .texture("source", source)
                .texture("output", output),
            size,
        )
    });
}

/// f32s as uniform words.
pub(crate) fn words(values: &[f32]) -> Vec<u32> {
    values.iter().map(|v| v.to_bits()).collect()
}
