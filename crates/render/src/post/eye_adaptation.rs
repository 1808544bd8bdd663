//! `EyeAdaptation`: the average luminance of an HDR image, adapted over time,
//! as breezEngine's tonemapping effect does it. The log-luminance of the
//! image is reduced to 1x1 by compute passes that each halve the size
//! (temporaries of the frame graph), then blended into a persistent 1x1
//! R32Float target: in log space, by `1 - exp(-dt * speed)` per frame, with
//! one speed for a brightening and one for a darkening scene. When the
//! persistent target is fresh (first frame, after `Renderer::reset_history`)
//! the measurement is taken as it is. The result is linear luminance, always
//! in the Minimum..Maximum pins: an all-black frame adapts to the minimum,
//! never to 0 or infinity. Shader: shaders/post/eye_adaptation.wgsl.

use std::sync::Arc;

use crate::error::RenderError;
use crate::frame_graph::{Bindings, FrameGraph, Lifetime, PassContext, SizeRule, Tex, TextureDesc};
use crate::recipe::{Recipe, TextureRef, next_recipe_id};
use crate::renderer::Renderer;
use crate::report::PassName;
use crate::shaders::Permutation;

pub use super::eye_adaptation_key::EyeAdaptationKey;

/// The reduction's format: mean log-luminance and the count of valid pixels behind it.
const REDUCED: wgpu::TextureFormat = wgpu::TextureFormat::Rg32Float;
/// The adapted luminance's format.
const ADAPTED: wgpu::TextureFormat = wgpu::TextureFormat::R32Float;

/// The lowest luminance the pins allow (the shader's log guard).
pub const MIN_PIN: f32 = 1e-6;
/// The highest luminance the pins allow.
pub const MAX_PIN: f32 = 1e9;

/// How the eye adapts: speeds per second (larger is faster) and the luminance pins.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AdaptationSettings {
    /// Towards a brighter scene (the adapted luminance rising).
    pub speed_up: f32,
    /// Towards a darker scene.
    pub speed_down: f32,
    pub min_luminance: f32,
    pub max_luminance: f32,
}

impl Default for AdaptationSettings {
    fn default() -> Self {
        AdaptationSettings {
            speed_up: 3.0,
            speed_down: 1.0,
            min_luminance: 0.01,
            max_luminance: 1000.0,
        }
    }
}

impl AdaptationSettings {
    /// The pins made usable: finite, in `MIN_PIN..=MAX_PIN`, minimum <= maximum.
    pub fn pins(&self) -> (f32, f32) {
        let pin = |v: f32, fallback: f32| {
            if v.is_finite() {
                v.clamp(MIN_PIN, MAX_PIN)
            } else {
                fallback
            }
        };
        let min = pin(self.min_luminance, MIN_PIN);
        let max = pin(self.max_luminance, MAX_PIN).max(min);
        (min, max)
    }

    /// The fraction of the way (in log luminance) one frame of `delta` seconds
    /// moves at `speed`: `1 - exp(-delta * speed)`, in 0..=1. A speed or delta
    /// that is negative or NaN does not move; an infinite one moves all the way.
    pub fn rate(speed: f32, delta: f64) -> f32 {
        let speed = f64::from(speed);
        if speed.is_nan() || delta.is_nan() || speed <= 0.0 || delta <= 0.0 {
            return 0.0;
        }
        let rate = -(-delta * speed).exp_m1();
        if rate.is_finite() {
            rate.clamp(0.0, 1.0) as f32
        } else {
            1.0
        }
    }

    /// One step of the adaptation on the CPU, as the shader does it (for tests):
    /// `last` adapted luminance (`None` when fresh) towards `measured`, both linear.
    pub fn step(&self, last: Option<f32>, measured: f32, delta: f64) -> f32 {
        let (min, max) = self.pins();
        let (lo, hi) = (min.ln(), max.ln());
        let target = if measured.is_finite() {
            measured.max(MIN_PIN).ln().clamp(lo, hi)
        } else {
            lo
        };
        let result = match last {
            Some(last) if last > 0.0 && last.is_finite() => {
                let last = last.ln().clamp(lo, hi);
                let speed = if target > last {
                    self.speed_up
                } else {
                    self.speed_down
                };
                last + (target - last) * Self::rate(speed, delta)
            }
            _ => target,
        };
        result.exp().clamp(min, max)
    }
}

/// The reduction's sizes for an image of `output` size (the source's): each
/// level half the last (rounded up), the first half the image, down to 1x1.
pub fn reduction_sizes(output: (u32, u32)) -> Vec<(u32, u32)> {
    let half = |(w, h): (u32, u32)| (w.div_ceil(2).max(1), h.div_ceil(2).max(1));
    let mut sizes = vec![half((output.0.max(1), output.1.max(1)))];
    while let Some(&last) = sizes.last() {
        if last == (1, 1) {
            break;
        }
        sizes.push(half(last));
    }
    sizes
}

pub struct EyeAdaptation {
    id: u64,
    owner: Option<u32>,
    source: TextureRef,
    /// The `Params` uniform of eye_adaptation.wgsl: [history kept, no history yet].
    params: [wgpu::Buffer; 2],
    /// The copy of last frame's adapted luminance the blend reads.
    previous: String,
    /// The persistent 1x1 adapted luminance: the recipe's output.
    pub output: String,
}

impl EyeAdaptation {
    /// `delta` is the time since the last frame in seconds (the frame clock's delta).
    /// The persistent target is named after `owner` (the node), so the recipe a
    /// node makes each frame finds last frame's value; recipes without an owner
    /// share one history per renderer (use [`EyeAdaptation::with_history`] to part them).
    pub fn new(
        renderer: &Renderer,
        owner: Option<u32>,
        source: TextureRef,
        settings: AdaptationSettings,
        delta: f64,
    ) -> Arc<Self> {
        let history = match owner {
            Some(node) => format!("adapted luminance #{node}"),
            None => "adapted luminance".to_owned(),
        };
        Self::with_history(renderer, owner, source, settings, delta, history)
    }

    /// As [`EyeAdaptation::new`], with the persistent target's name given.
    pub fn with_history(
        renderer: &Renderer,
        owner: Option<u32>,
        source: TextureRef,
        settings: AdaptationSettings,
        delta: f64,
        history: String,
    ) -> Arc<Self> {
        let id = next_recipe_id();
        let rate_up = AdaptationSettings::rate(settings.speed_up, delta);
        let rate_down = AdaptationSettings::rate(settings.speed_down, delta);
        let (min, max) = settings.pins();
        // Kept under the node: the same buffers (and bind groups) every frame.
        let params = [0u32, 1].map(|fresh| {
            renderer.kept_init_at(
                owner,
                "eye adaptation params",
                fresh,
                bytemuck::cast_slice(&[
                    rate_up.to_bits(),
                    rate_down.to_bits(),
                    min.to_bits(),
                    max.to_bits(),
                    fresh,
                    0,
                    0,
                    0,
                ]),
                wgpu::BufferUsages::UNIFORM,
            )
        });
        Arc::new(EyeAdaptation {
            id,
            owner,
            source,
            params,
            previous: format!("eye adaptation{id} previous"),
            output: history,
        })
    }

    pub fn texture(self: &Arc<Self>) -> TextureRef {
        TextureRef {
            recipe: self.clone(),
            name: self.output.clone(),
        }
    }

    fn level_name(&self, level: usize) -> String {
        format!("eye adaptation{} level{level}", self.id)
    }

    /// One reduction step: `input` (the image or the last level) into `output`.
    fn reduce(
        &self,
        cx: &mut PassContext<'_>,
        entry: &'static str,
        input: Tex,
        output: Tex,
    ) -> Result<(), RenderError> {
        let size = cx.size_of(output)?;
        // Only the first level reads the parameters (it floors pixels at the
        // Minimum pin); `downsample` does not use them, so they are left out.
        let bindings = Bindings::new()
            .buffer("params", &self.params[0])
            .texture("input", input)
            .texture("reduced", output);
        cx.dispatch_shader(
            entry,
            &EyeAdaptationKey.key(),
            entry,
            bindings,
            super::per_pixel(size),
        )
    }

    fn adapt(&self, cx: &mut PassContext<'_>, io: &AdaptIo) -> Result<(), RenderError> {
        let fresh = cx.is_fresh(io.adapted);
        // The blend reads last frame's value from a copy: a texture cannot be
        // read and written in one dispatch without read-write storage.
        let (last, copy) = (
            cx.texture(io.adapted)?.clone(),
            cx.texture(io.previous)?.clone(),
        );
        cx.encoder().copy_texture_to_texture(
            last.as_image_copy(),
            copy.as_image_copy(),
            wgpu::Extent3d {
                width: 1,
                height: 1,
                depth_or_array_layers: 1,
            },
        );
        let bindings = Bindings::new()
            .buffer("params", &self.params[usize::from(fresh)])
            .texture("measured", io.measured)
            .texture("previous", io.previous)
            .texture("adapted", io.adapted);
        cx.dispatch_shader(
            "adapt",
            &EyeAdaptationKey.key(),
            "adapt",
            bindings,
            (1, 1, 1),
        )
    }
}

/// What the adapt pass declared: the last level of the reduction, the
/// persistent adapted luminance and the copy of last frame's it reads.
struct AdaptIo {
    measured: Tex,
    previous: Tex,
    adapted: Tex,
}

impl Recipe for EyeAdaptation {
    fn declare<'a>(&'a self, renderer: &'a Renderer, fg: &mut FrameGraph<'a>) {
        if !fg.include(self.id) {
            return;
        }
        self.source.recipe.declare(renderer, fg);
        let name = |step: std::borrow::Cow<'static, str>| PassName::new("EyeAdaptation").step(step);
        // Reduced from its source's size (`FrameGraph::effect_size`): level 0 reads texel for texel.
        let sizes = reduction_sizes(fg.effect_size(&self.source.name).pixels(fg.output_size()));
        let level = |(width, height): (u32, u32)| {
            TextureDesc::storage(REDUCED).size(SizeRule::Absolute { width, height })
        };
        // Level 0: log-luminance of the image at half its size.
        let mut pass = fg.pass(name("log luminance".into()), self.owner);
        let input = pass.read(&self.source.name);
        let output = pass.write(&self.level_name(0), level(sizes[0]));
        pass.run(move |cx| self.reduce(cx, "log_luminance", input, output));
        for (l, size) in sizes.iter().enumerate().skip(1) {
            let mut pass = fg.pass(
                name(format!("reduce {}x{}", size.0, size.1).into()),
                self.owner,
            );
            let input = pass.read(&self.level_name(l - 1));
            let output = pass.write(&self.level_name(l), level(*size));
            pass.run(move |cx| self.reduce(cx, "downsample", input, output));
        }
        let last = sizes.len() - 1;
        let one = SizeRule::Absolute {
            width: 1,
            height: 1,
        };
        let adapted = TextureDesc::storage(ADAPTED)
            .size(one)
            .lifetime(Lifetime::Persistent);
        let previous = TextureDesc {
            format: ADAPTED,
            size: one,
            lifetime: Lifetime::Temporary,
            usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
            only_if_read: false,
        };
        let mut pass = fg.pass(name("adapt".into()), self.owner);
        let io = AdaptIo {
            measured: pass.read(&self.level_name(last)),
            adapted: pass.write(&self.output, adapted),
            previous: pass.write(&self.previous, previous),
        };
        pass.run(move |cx| self.adapt(cx, &io));
    }
}
