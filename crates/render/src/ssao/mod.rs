//! Screen-space ambient occlusion over the G-buffer: Emeshe's stochastic
//! wide-range AO and its short-range "HBAO", and McGuire's SAO as Castor3D
//! has it. One recipe, three estimators (shaders/ssao/ao.wgsl), and
//! the passes they share:
//!
//! 1. SAO only: view depth and a mip chain of it (shaders/ssao/linear_depth.wgsl),
//!    so far taps read coarse levels and stay in cache.
//! 2. Raw AO: per-pixel rotated samples, the rotation changing every frame.
//! 3. Temporal (when the blend is above 0): last frame's result reprojected
//!    with the G-buffer velocity, rejected where depth or normal disagree
//!    (disocclusion), sanitized on read, blended in. The history is a
//!    persistent texture named after the node; a resize, a `Reset` or
//!    `Renderer::reset_history` starts it anew.
//! 4. A depth- and normal-aware separable blur (shaders/ssao/blur.wgsl),
//!    whose last pass also multiplies in another AO (`combine`: wide-range
//!    times local, as Emeshe pairs them).
//!
//! At [`Resolution::Half`] step 2 runs for one pixel in four and is
//! upsampled with depth awareness (crate::resolution) before step 3; the
//! rest is unchanged.
//!
//! Output: visibility 0..1 in RGB of an RGBA16F texture (1 where depth is
//! empty), what `CompositeLight`'s Occlusion input reads.

use std::sync::Arc;

use crate::error::RenderError;
use crate::frame_graph::{
    Bindings, FrameGraph, PassBuilder, PassContext, SizeRule, Tex, TextureDesc,
};
use crate::gbuffer::GBuffer;
use crate::recipe::{Recipe, TextureRef, next_recipe_id};
use crate::renderer::Renderer;
use crate::report::PassName;
use crate::resolution::{
    Resolution, UpsampleFormat, UpsamplePass, declare_upsample, written_target,
};
use crate::shaders::Permutation;
use crate::temporal::{RayParams, TemporalState};

// Seen by the shader table (`shaders::SHADERS`): the key needs nothing of the pass.
pub(crate) mod key;
pub use key::{AoKey, AoMode, AoTarget, BlurKey, DepthKey, TemporalKey};

/// Every AO pin; out-of-range values are clamped where the recipe is made.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AoSettings {
    pub mode: AoMode,
    /// World units: how far occluders count.
    pub radius: f32,
    /// Rays (Stochastic), taps (SAO) or directions (HBAO): 1..=64.
    pub samples: u32,
    /// Steps along each ray or direction (Stochastic, HBAO): 1..=32.
    pub steps: u32,
    /// An exponent on visibility: 1 is the estimate as it is, 2 darker.
    pub intensity: f32,
    /// 0..=0.98: the weight of last frame's result (0: no temporal pass).
    pub temporal_blend: f32,
    /// Blur half-width in pixels, 0..=16 (0: no blur).
    pub blur_radius: u32,
    /// Drop the history this frame (a camera cut).
    pub reset: bool,
    /// Where the raw estimate runs: every pixel, or one in four upsampled.
    pub resolution: Resolution,
}

/// Counted when an AO's raw estimate ran at half resolution.
pub const HALF_RESOLUTION: &str = "AO at half resolution";
/// Statistic: AO estimates that blended their history in the same pass
/// (full resolution with temporal accumulation), writing no raw target.
pub const ESTIMATE_TEMPORAL: &str = "AO estimated and accumulated in one pass";

impl Default for AoSettings {
    fn default() -> Self {
        AoSettings {
            mode: AoMode::Stochastic,
            radius: 1.0,
            samples: 8,
            steps: 4,
            intensity: 1.0,
            temporal_blend: 0.9,
            blur_radius: 4,
            reset: false,
            resolution: Resolution::Full,
        }
    }
}

impl AoSettings {
    /// Finite and in range: a NaN radius would reach every pixel.
    fn clamped(self) -> Self {
        let clean = |v: f32, lo: f32, hi: f32, fallback: f32| {
            if v.is_finite() {
                v.clamp(lo, hi)
            } else {
                fallback
            }
        };
        AoSettings {
            // A NaN radius occludes nothing rather than guessing one.
            radius: clean(self.radius, 0.0, 1e6, 0.0),
            samples: self.samples.clamp(1, 64),
            steps: self.steps.clamp(1, 32),
            intensity: clean(self.intensity, 0.0, 16.0, 1.0),
            temporal_blend: clean(self.temporal_blend, 0.0, 0.98, 0.0),
            blur_radius: self.blur_radius.min(16),
            ..self
        }
    }
}

/// Levels of SAO's view-depth chain (full size, then halves).
const DEPTH_LEVELS: usize = 5;

pub struct AmbientOcclusion {
    id: u64,
    owner: Option<u32>,
    gbuffer: Arc<GBuffer>,
    settings: AoSettings,
    combine: Option<TextureRef>,
    /// Key of the per-node state and the history's name.
    key: u64,
    params: wgpu::Buffer,
    /// The temporal pass's `fresh` flag: [history kept, history reset].
    fresh: [wgpu::Buffer; 2],
    state: Arc<TemporalState>,
    prefix: String,
    pub output: String,
}

impl AmbientOcclusion {
    /// `combine`: another AO texture multiplied into the result.
    pub fn new(
        renderer: &Renderer,
        owner: Option<u32>,
        gbuffer: Arc<GBuffer>,
        settings: AoSettings,
        combine: Option<TextureRef>,
    ) -> Arc<Self> {
        let id = next_recipe_id();
        let settings = settings.clamped();
        // The history outlives recipes: a node makes a new one whenever a pin
        // changes, and its history must carry over. Without a node, per recipe.
        let key = owner.map_or(id, u64::from);
        // Written each frame; kept under the node so its bind groups are reused.
        let params = renderer.kept_buffer(
            owner,
            "ao params",
            64,
            wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        );
        let prefix = format!("ao{id}");
        // The temporal pass's flag, [history kept, history reset].
        let fresh = renderer.kept_flags(owner, "ao temporal");
        Arc::new(AmbientOcclusion {
            id,
            owner,
            gbuffer,
            settings,
            combine,
            key,
            params,
            fresh,
            state: renderer.state::<TemporalState>(key),
            output: format!("{prefix}/out"),
            prefix,
        })
    }

    pub fn texture(self: &Arc<Self>) -> TextureRef {
        TextureRef {
            recipe: self.clone(),
            name: self.output.clone(),
        }
    }

    pub fn settings(&self) -> AoSettings {
        self.settings
    }

    fn name(&self, what: &str) -> String {
        format!("{}/{what}", self.prefix)
    }

    /// The persistent history texture's name (RGBA16F: visibility, view
    /// distance, world normal octahedron), kept per node and mode.
    pub fn history_name(&self) -> String {
        format!("ao-history-{}-{:?}", self.key, self.settings.mode)
    }

    /// Radius 0 occludes nothing: the raw pass writes 1 and nothing else runs.
    fn off(&self) -> bool {
        self.settings.radius <= 0.0
    }

    fn temporal(&self) -> bool {
        self.settings.temporal_blend > 0.0 && !self.off()
    }

    /// SAO's depth chain is built only when SAO runs.
    fn sao(&self) -> bool {
        self.settings.mode == AoMode::Sao && !self.off()
    }

    /// The size of SAO's depth level `k`.
    fn level_size(&self, k: usize) -> SizeRule {
        let f = 0.5f32.powi(k as i32);
        match self.gbuffer.size {
            SizeRule::Relative(s) => SizeRule::Relative(s * f),
            SizeRule::Absolute { width, height } => SizeRule::Absolute {
                width: (width >> k).max(1),
                height: (height >> k).max(1),
            },
        }
    }

    /// Upload this frame's parameters: the frame index turns the samples.
    fn write_params(&self, cx: &PassContext<'_>, frame: u32, reset: bool) {
        let s = self.settings;
        let params = RayParams {
            radius: s.radius,
            intensity: s.intensity,
            blend: s.temporal_blend,
            samples: s.samples,
            steps: s.steps,
            blur_radius: if self.off() { 0 } else { s.blur_radius },
        };
        cx.gpu.queue.write_buffer(
            &self.params,
            0,
            bytemuck::cast_slice(&params.words(frame, reset)),
        );
    }

    /// SAO's view depth (level 0, from the G-buffer's depth) or one mip of it.
    fn linear_depth(
        &self,
        cx: &mut PassContext<'_>,
        level: usize,
        source: Tex,
        output: Tex,
    ) -> Result<(), RenderError> {
        let size = cx.size_of(output)?;
        let (label, key) = match level {
            0 => ("ao view depth", DepthKey::FromGBuffer),
            _ => ("ao depth mip", DepthKey::Downsample),
        };
        cx.dispatch_image(
            label,
            &key.key(),
            Bindings::new()
                .buffer("camera", self.gbuffer.camera_buffer())
                .texture("source", source)
                .texture("output", output),
            size,
        )
    }

    /// Full resolution with accumulation: the estimate blends its history
    /// in the raw pass (ao.wgsl's TEMPORAL), with no raw target between.
    fn fused(&self) -> bool {
        self.temporal() && !self.settings.resolution.is_half()
    }

    /// The camera and parameters every AO pass binds, with the G-buffer's depth and normals.
    fn common(&self, depth: Tex, normals: Tex) -> Bindings<'_> {
        Bindings::new()
            .buffer("camera", self.gbuffer.camera_buffer())
            .buffer("params", &self.params)
            .texture("depth", depth)
            .texture("normals", normals)
    }

    fn raw(&self, cx: &mut PassContext<'_>, io: &RawIo) -> Result<(), RenderError> {
        let (frame, stale) = self.state.advance(&self.gbuffer, self.settings.reset);
        let reset = stale && self.temporal();
        if reset {
            cx.count("AO history reset", 1);
        }
        self.write_params(cx, frame, reset);
        let mut b = self.common(io.depth, io.normals);
        for (name, level) in ["z0", "z1", "z2", "z3", "z4"].into_iter().zip(&io.levels) {
            b = b.texture(name, *level);
        }
        b = match &io.target {
            RawTarget::Raw(output) => b.texture("output", *output),
            // Last frame's history handed to `previous` before the history
            // is written (the two may trade textures).
            RawTarget::Fused(h) => {
                let fresh = self.hand_over_history(cx, h)?;
                cx.count(ESTIMATE_TEMPORAL, 1);
                b.texture("history", h.history)
                    .texture("previous", h.previous)
                    .texture("velocity_uv", h.velocity_uv)
                    .buffer("fresh", &self.fresh[usize::from(fresh)])
            }
        };
        let resolution = self.settings.resolution;
        let key = AoKey {
            // Off: the plain estimator's early exit writes 1 (no SAO chain to bind).
            estimator: if self.off() {
                AoMode::Stochastic
            } else {
                self.settings.mode
            },
            target: match (resolution, &io.target) {
                (Resolution::Half, _) => AoTarget::Half,
                (Resolution::Full, RawTarget::Fused(_)) => AoTarget::FullTemporal,
                (Resolution::Full, _) => AoTarget::Full,
            },
        };
        let size = resolution.pixels(self.gbuffer.pixel_size(cx.output_size));
        cx.dispatch_image(self.settings.mode.name(), &key.key(), b, size)
    }

    /// Last frame's history handed to `previous` before the history is
    /// written again; whether it is fresh (then counted as a reset).
    fn hand_over_history(
        &self,
        cx: &mut PassContext<'_>,
        h: &HistoryIo,
    ) -> Result<bool, RenderError> {
        let fresh = cx.copy_history(h.history, h.previous)?;
        if fresh {
            cx.count("AO history reset", 1);
        }
        Ok(fresh)
    }

    fn temporal_pass(
        &self,
        cx: &mut PassContext<'_>,
        raw: Tex,
        depth: Tex,
        normals: Tex,
        h: &HistoryIo,
    ) -> Result<(), RenderError> {
        let fresh = self.hand_over_history(cx, h)?;
        let size = self.gbuffer.pixel_size(cx.output_size);
        cx.dispatch_image(
            "ao temporal",
            &TemporalKey.key(),
            self.common(depth, normals)
                .texture("raw", raw)
                .texture("velocity_uv", h.velocity_uv)
                .texture("previous", h.previous)
                .texture("history", h.history)
                .buffer("temporal", &self.fresh[usize::from(fresh)]),
            size,
        )
    }

    /// One direction of the depth-aware blur; the last pass (`vertical`, or
    /// the resolve without blur) writes the output and multiplies `combine` in.
    fn blur(
        &self,
        cx: &mut PassContext<'_>,
        io: &BlurIo,
        vertical: bool,
    ) -> Result<(), RenderError> {
        let key = match (vertical, io.combine) {
            (false, _) => BlurKey::Horizontal,
            (true, None) => BlurKey::Vertical,
            (true, Some(_)) => BlurKey::VerticalCombine,
        };
        let size = self.gbuffer.pixel_size(cx.output_size);
        cx.dispatch_image(
            if vertical { "ao blur y" } else { "ao blur x" },
            &key.key(),
            self.common(io.depth, io.normals)
                .texture("source", io.source)
                .texture("output", io.output)
                .texture_opt("combine", io.combine.filter(|_| vertical)),
            size,
        )
    }
}

/// The history a temporal AO pass hands over and writes, and the velocity it reprojects by.
#[derive(Clone, Copy)]
struct HistoryIo {
    history: Tex,
    previous: Tex,
    velocity_uv: Tex,
}

/// Where the raw estimate goes: its own target, or (full resolution with
/// accumulation) straight into the history.
enum RawTarget {
    Raw(Tex),
    Fused(HistoryIo),
}

/// What the raw pass declared.
struct RawIo {
    depth: Tex,
    normals: Tex,
    /// SAO's view-depth chain (empty for the other estimators).
    levels: Vec<Tex>,
    target: RawTarget,
}

/// What a blur pass declared.
struct BlurIo {
    source: Tex,
    depth: Tex,
    normals: Tex,
    output: Tex,
    combine: Option<Tex>,
}

impl Recipe for AmbientOcclusion {
    fn declare<'a>(&'a self, renderer: &'a Renderer, fg: &mut FrameGraph<'a>) {
        if !fg.include(self.id) {
            return;
        }
        self.gbuffer.declare(renderer, fg);
        if let Some(c) = &self.combine {
            c.recipe.declare(renderer, fg);
        }
        let kind = self.settings.mode.name();
        let g = &self.gbuffer.targets;
        let full = |format| TextureDesc::storage(format).size(self.gbuffer.size);
        let mut levels = Vec::new();
        if self.sao() {
            for k in 0..DEPTH_LEVELS {
                let mut pass = fg.pass(
                    PassName::new(kind).step(format!("view depth {k}")),
                    self.owner,
                );
                let source = match k {
                    0 => pass.read(&g.depth),
                    _ => pass.read(&self.name(&format!("z{}", k - 1))),
                };
                let output = pass.write(
                    &self.name(&format!("z{k}")),
                    TextureDesc::storage(wgpu::TextureFormat::R32Float).size(self.level_size(k)),
                );
                pass.run(move |cx| self.linear_depth(cx, k, source, output));
                levels.push(self.name(&format!("z{k}")));
            }
        }
        let raw = self.name("raw");
        let resolution = self.settings.resolution;
        let pixels = self.gbuffer.pixel_size(fg.output_size());
        let history = self.history_name();
        // The history and its twin, last frame's (see TextureDesc::history).
        let histories = |pass: &mut PassBuilder<'_, 'a>| HistoryIo {
            velocity_uv: pass.read(&g.velocity_uv),
            history: pass.write(
                &history,
                TextureDesc::history(wgpu::TextureFormat::Rgba16Float).size(self.gbuffer.size),
            ),
            previous: pass.write(
                &self.name("previous"),
                TextureDesc::history_twin(wgpu::TextureFormat::Rgba16Float).size(self.gbuffer.size),
            ),
        };
        let mut pass = fg.pass(
            PassName::new(kind).step(format!("raw{}", resolution.pass_suffix())),
            self.owner,
        );
        let (depth, normals) = (pass.read(&g.depth), pass.read(&g.normals));
        let levels = levels.iter().map(|l| pass.read(l)).collect();
        let target = if self.fused() {
            RawTarget::Fused(histories(&mut pass))
        } else {
            RawTarget::Raw(
                pass.write(
                    &written_target(&raw, resolution),
                    full(wgpu::TextureFormat::R32Float)
                        .size(resolution.size_rule(self.gbuffer.size, pixels)),
                ),
            )
        };
        let fused = matches!(target, RawTarget::Fused(_));
        let io = RawIo {
            depth,
            normals,
            levels,
            target,
        };
        pass.run(move |cx| self.raw(cx, &io));
        if fused {
            // The estimate and its accumulation in one pass: straight to the blur.
            self.declare_blur(fg, history);
            return;
        }
        declare_upsample(
            fg,
            resolution,
            UpsamplePass {
                name: PassName::new(kind).step("upsample"),
                owner: self.owner,
                gbuffer: &self.gbuffer,
                half: &written_target(&raw, resolution),
                full: &raw,
                desc: full(wgpu::TextureFormat::R32Float),
                format: UpsampleFormat::R32,
                counter: HALF_RESOLUTION,
                label: "ao upsample",
                detail: None,
            },
        );
        let mut source = raw.clone();
        if self.temporal() {
            let mut pass = fg.pass(PassName::new(kind).step("temporal"), self.owner);
            let (raw, depth, normals) =
                (pass.read(&raw), pass.read(&g.depth), pass.read(&g.normals));
            let h = histories(&mut pass);
            pass.run(move |cx| self.temporal_pass(cx, raw, depth, normals, &h));
            source = history;
        }
        self.declare_blur(fg, source);
    }
}

impl AmbientOcclusion {
    /// The depth-aware blur of `source` (x then y), or with no blur the
    /// resolve; the last pass writes the output (and multiplies `combine` in).
    fn declare_blur<'a>(&'a self, fg: &mut FrameGraph<'a>, source: String) {
        let kind = self.settings.mode.name();
        let g = &self.gbuffer.targets;
        let full = |format| TextureDesc::storage(format).size(self.gbuffer.size);
        if self.off() {
            fg.count("AO off: radius 0", 1);
        }
        let blur = self.settings.blur_radius > 0 && !self.off();
        let mut source = source;
        if blur {
            let mut pass = fg.pass(PassName::new(kind).step("blur x"), self.owner);
            let io = BlurIo {
                source: pass.read(&source),
                depth: pass.read(&g.depth),
                normals: pass.read(&g.normals),
                output: pass.write(&self.name("blurred"), full(wgpu::TextureFormat::R32Float)),
                combine: None,
            };
            pass.run(move |cx| self.blur(cx, &io, false));
            source = self.name("blurred");
        }
        let step = if blur { "blur y" } else { "resolve" };
        let mut pass = fg.pass(PassName::new(kind).step(step), self.owner);
        let io = BlurIo {
            depth: pass.read(&g.depth),
            normals: pass.read(&g.normals),
            combine: pass.read_opt(self.combine.as_ref().map(|c| c.name.as_str())),
            source: pass.read(&source),
            output: pass.write(&self.output, full(wgpu::TextureFormat::Rgba16Float)),
        };
        pass.run(move |cx| self.blur(cx, &io, true));
    }
}
