//! Screen-space ambient occlusion over the G-buffer: Emeshe's stochastic
//! wide-range AO and its short-range "HBAO", and McGuire's SAO as Castor3D
//! has it. One recipe, three estimators (shaders/ssao/ao.wgsl), and
//! the passes they share:
//!
//! 1. SAO only: view depth and a mip chain of it (shaders/ssao/linear_depth.wgsl),
//!    so far taps read coarse levels and stay in cache.
//! 2. Raw AO: per-pixel rotated samples, the rotation changing every frame.
//! 3. Temporal (when the blend is above 0), in step 2's pass: last frame's
//!    result reprojected with the G-buffer velocity, rejected where depth or
//!    normal disagree (disocclusion), sanitized on read, blended in
//!    (shaders/lib/ao_history.wgsl). The history is a
//!    persistent texture named after the node; a resize, a `Reset` or
//!    `Renderer::reset_history` starts it anew.
//! 4. A depth- and normal-aware separable blur (shaders/ssao/blur.wgsl),
//!    whose last pass also multiplies in another AO (`combine`: wide-range
//!    times local, as Emeshe pairs them).
//!
//! At [`Resolution::Half`] step 2 runs for one pixel in four, and steps 3
//! and 4 run on that half-size image too (the history at half size, the
//! blur reading the full G-buffer at each half texel's own pixel, taps two
//! pixels apart); one depth-aware upsample at the end writes the output
//! and multiplies `combine` in (crate::resolution's half chain).
//! [`Resolution::Auto`] resolves to one of the two when the passes are
//! declared, by the frame's size.
//!
//! Output: visibility 0..1 in RGB of an RGBA16F texture (1 where depth is
//! empty), what `CompositeLight`'s Occlusion input reads.

use std::sync::Arc;

use crate::error::RenderError;
use crate::finite::finite_in;
use crate::frame_graph::SizeRule;
use crate::frame_graph::{Bindings, FrameGraph, History, PassBuilder, PassContext, TextureDesc};
use crate::gbuffer::GBuffer;
use crate::packed_surface::{self, Reader, SurfaceInputs};
use crate::recipe::{Recipe, TextureRef, declare_inputs, name_of, next_recipe_id};
use crate::renderer::Renderer;
use crate::report::PassName;
use crate::resolution::{Finish, FinishPass, Resolution, declare_finish, written_target};
use crate::shaders::Permutation;
use crate::temporal::{RayParams, RayUniforms};

// The keys declare their shader files and need nothing of the pass.
pub(crate) mod key;
pub use key::{AoKey, AoMode, AoTarget, BlurKey, BlurPass, DepthKey};

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

/// Counted when a history starts anew (a resize, a `Reset`, a camera cut).
const HISTORY_RESET: &str = "AO history reset";
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
            resolution: Resolution::Auto,
        }
    }
}

impl AoSettings {
    /// Finite and in range ([`finite_in`]).
    fn clamped(self) -> Self {
        AoSettings {
            // A NaN radius occludes nothing rather than guessing one.
            radius: finite_in(self.radius, 0.0, 1e6, 0.0),
            samples: self.samples.clamp(1, 64),
            steps: self.steps.clamp(1, 32),
            intensity: finite_in(self.intensity, 0.0, 16.0, 1.0),
            temporal_blend: finite_in(self.temporal_blend, 0.0, 0.98, 0.0),
            blur_radius: self.blur_radius.min(16),
            ..self
        }
    }
}

/// Levels of SAO's view-depth chain (full size, then halves), as ao.wgsl names them.
const DEPTH_LEVELS: [&str; 5] = ["z0", "z1", "z2", "z3", "z4"];

const R32: wgpu::TextureFormat = wgpu::TextureFormat::R32Float;

pub struct AmbientOcclusion {
    id: u64,
    owner: Option<u32>,
    gbuffer: Arc<GBuffer>,
    settings: AoSettings,
    combine: Option<TextureRef>,
    /// The parameters, written each frame, and the history's state.
    rays: RayUniforms,
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
        let labels = ["ao params", "ao temporal", HISTORY_RESET];
        Arc::new(AmbientOcclusion {
            id,
            owner,
            gbuffer,
            settings: settings.clamped(),
            combine,
            rays: RayUniforms::new(renderer, owner, id, labels),
            output: format!("ao{id}/out"),
        })
    }

    pub fn texture(self: &Arc<Self>) -> TextureRef {
        TextureRef::of(self, &self.output)
    }

    pub fn settings(&self) -> AoSettings {
        self.settings
    }

    fn name(&self, what: &str) -> String {
        format!("ao{}/{what}", self.id)
    }

    /// The half chain's targets (frame-graph names), for tests and tools:
    /// the half-size estimate (the raw target, or with a temporal blend the
    /// half-size history the raw pass blends into) and the blur's half-size
    /// result (what the upsample reads when the blur runs).
    pub fn half_targets(&self) -> [String; 2] {
        let estimate = match self.temporal() {
            true => self.history_name(),
            false => written_target(&self.name("raw"), Resolution::Half),
        };
        [estimate, self.name("out half")]
    }

    /// The persistent history texture's name (RGBA16F: visibility, view
    /// distance, world normal octahedron), kept per node and mode.
    pub fn history_name(&self) -> String {
        format!("ao-history-{}-{:?}", self.rays.key, self.settings.mode)
    }

    /// Radius 0 occludes nothing: the raw pass writes 1 and nothing else runs.
    fn off(&self) -> bool {
        self.settings.radius <= 0.0
    }

    fn temporal(&self) -> bool {
        self.settings.temporal_blend > 0.0 && !self.off()
    }

    /// What every AO pass but SAO's depth chain binds: the camera, the
    /// parameters, the G-buffer's depth and normals.
    fn common<'a>(&'a self, pass: &mut PassBuilder<'_, 'a>) {
        pass.input("depth", &self.gbuffer.targets.depth);
        pass.input("normals", &self.gbuffer.targets.normals);
        pass.bind(|b| {
            b.buffer("camera", self.gbuffer.camera_buffer())
                .buffer("params", self.rays.params())
        });
    }

    /// What a blur pass reads of the surface: the packed surface when given
    /// (and then not the G-buffer's depth and normals), else [`Self::common`].
    fn blur_inputs<'a>(&'a self, pass: &mut PassBuilder<'_, 'a>, surface: Option<&str>) {
        let Some(surface) = surface else {
            return self.common(pass);
        };
        pass.input("surface", surface);
        pass.bind(|b| {
            b.buffer("camera", self.gbuffer.camera_buffer())
                .buffer("params", self.rays.params())
        });
    }

    /// The history and its twin, last frame's (see TextureDesc::history),
    /// with the velocity that reprojects it; `size`: the G-buffer's, or half
    /// of it (a change of size starts the history anew, as a resize does).
    fn history<'a>(&'a self, pass: &mut PassBuilder<'_, 'a>, size: SizeRule) -> History {
        pass.input("velocity_uv", &self.gbuffer.targets.velocity_uv);
        pass.history(
            ["history", "previous"],
            [&self.history_name(), &self.name("previous")],
            wgpu::TextureFormat::Rgba16Float,
            size,
        )
    }

    /// A pass of this effect, at `step`.
    fn pass<'g, 'a>(
        &'a self,
        fg: &'g mut FrameGraph<'a>,
        step: impl Into<std::borrow::Cow<'static, str>>,
    ) -> PassBuilder<'g, 'a> {
        fg.pass(
            PassName::new(self.settings.mode.name()).step(step),
            self.owner,
        )
    }

    /// The raw estimate, its parameters uploaded first: the frame index turns the samples.
    fn raw<'a>(
        &'a self,
        cx: &mut PassContext<'_>,
        mut b: Bindings<'a>,
        key: AoKey,
        fused: Option<History>,
        resolution: Resolution,
    ) -> Result<(), RenderError> {
        let s = self.settings;
        let ray = RayParams {
            radius: s.radius,
            intensity: s.intensity,
            blend: s.temporal_blend,
            samples: s.samples,
            steps: s.steps,
            blur_radius: if self.off() { 0 } else { s.blur_radius },
        };
        let rays = &self.rays;
        rays.begin(cx, &self.gbuffer, &ray, s.reset, self.temporal());
        if let Some(h) = fused {
            b = b.buffer("fresh", self.rays.hand_over(cx, h)?);
            cx.count(ESTIMATE_TEMPORAL, 1);
        }
        let size = resolution.pixels(self.gbuffer.pixel_size(cx.output_size));
        cx.dispatch_image(s.mode.name(), &key.key(), b, size)
    }
}

impl Recipe for AmbientOcclusion {
    fn declare<'a>(&'a self, renderer: &'a Renderer, fg: &mut FrameGraph<'a>) {
        if !fg.include(self.id) {
            return;
        }
        self.gbuffer.declare(renderer, fg);
        declare_inputs(renderer, fg, &self.combine);
        let packed = packed_surface::inputs(renderer, Reader::Blurs) == SurfaceInputs::Packed;
        // SAO's depth chain is built only when SAO runs.
        let sao = self.settings.mode == AoMode::Sao && !self.off();
        let levels = if sao { &DEPTH_LEVELS[..] } else { &[] };
        for (k, level) in levels.iter().enumerate() {
            let mut pass = self.pass(fg, format!("view depth {k}"));
            let (source, label, key) = match k {
                0 => (
                    self.gbuffer.targets.depth.clone(),
                    "ao view depth",
                    DepthKey::FromGBuffer,
                ),
                _ => (
                    self.name(levels[k - 1]),
                    "ao depth mip",
                    DepthKey::Downsample,
                ),
            };
            let size = self.gbuffer.size.mip(k as u32);
            pass.input("source", &source);
            pass.output(
                "output",
                &self.name(level),
                TextureDesc::storage(R32).size(size),
            );
            pass.bind(|b| b.buffer("camera", self.gbuffer.camera_buffer()));
            pass.dispatch_image(label, key.key(), size);
        }
        let raw = self.name("raw");
        let pixels = self.gbuffer.pixel_size(fg.output_size());
        let resolution = self.settings.resolution.resolve_in(renderer, fg, pixels);
        let full = |format| TextureDesc::storage(format).size(self.gbuffer.size);
        // The plain estimator's rays read the packed view z (not when off:
        // the early exit reads nothing).
        let view_z = (self.settings.mode == AoMode::Stochastic
            && !self.off()
            && packed_surface::inputs(renderer, Reader::Rays) == SurfaceInputs::Packed)
            .then(|| packed_surface::declare(fg, &self.gbuffer).view_z);
        let mut pass = self.pass(fg, format!("raw{}", resolution.pass_suffix()));
        self.common(&mut pass);
        for &level in levels {
            pass.input(level, &self.name(level));
        }
        if let Some(view_z) = &view_z {
            pass.input("view_z", view_z);
        }
        // With accumulation the estimate blends its history in the raw pass
        // (ao.wgsl's TEMPORAL), at full or half size, with no raw target
        // between: a pass of its own cost 0.0175 ms at half 1080p on the
        // H200 (session 23).
        let size = resolution.size_rule(self.gbuffer.size, pixels);
        let fused = self.temporal().then(|| self.history(&mut pass, size));
        if fused.is_none() {
            pass.output(
                "output",
                &written_target(&raw, resolution),
                full(R32).size(size),
            );
        }
        let key = AoKey {
            // Off: the plain estimator's early exit writes 1 (no SAO chain to bind).
            estimator: if self.off() {
                AoMode::Stochastic
            } else {
                self.settings.mode
            },
            target: match (resolution.is_half(), fused) {
                (true, Some(_)) => AoTarget::HalfTemporal,
                (true, None) => AoTarget::Half,
                (false, Some(_)) => AoTarget::FullTemporal,
                (false, None) => AoTarget::Full,
            },
            packed: view_z.is_some(),
        };
        pass.will_dispatch(&key.key(), "main");
        pass.run_bound(move |cx, b| self.raw(cx, b, key, fused, resolution));
        let source = match fused {
            Some(_) => self.history_name(),
            None => written_target(&raw, resolution),
        };
        match resolution.is_half() {
            true => self.declare_half_chain(fg, source, size),
            false => self.declare_blur(fg, source, packed),
        }
    }
}

impl AmbientOcclusion {
    /// The depth-aware blur of `source` (x then y), or with no blur the
    /// resolve; the last pass writes the output (and multiplies `combine` in).
    /// `packed`: the taps read the G-buffer's packed surface (crate::packed_surface).
    fn declare_blur<'a>(&'a self, fg: &mut FrameGraph<'a>, mut source: String, packed: bool) {
        if self.off() {
            fg.count("AO off: radius 0", 1);
        }
        let blur = self.settings.blur_radius > 0 && !self.off();
        let surface = (blur && packed).then(|| packed_surface::declare(fg, &self.gbuffer).surface);
        let full = |format| TextureDesc::storage(format).size(self.gbuffer.size);
        if blur {
            let mut pass = self.pass(fg, "blur x");
            pass.input("source", &source);
            self.blur_inputs(&mut pass, surface.as_deref());
            pass.output("output", &self.name("blurred"), full(R32));
            let key = BlurKey {
                pass: BlurPass::Horizontal,
                packed: surface.is_some(),
                half: false,
            };
            pass.dispatch_image("ao blur x", key.key(), self.gbuffer.size);
            source = self.name("blurred");
        }
        let mut pass = self.pass(fg, if blur { "blur y" } else { "resolve" });
        self.blur_inputs(&mut pass, surface.as_deref());
        let combine = pass.input_opt("combine", name_of(&self.combine));
        pass.input("source", &source);
        pass.output(
            "output",
            &self.output,
            full(wgpu::TextureFormat::Rgba16Float),
        );
        let key = BlurKey {
            pass: match combine {
                None => BlurPass::Vertical,
                Some(_) => BlurPass::VerticalCombine,
            },
            packed: surface.is_some(),
            half: false,
        };
        pass.dispatch_image("ao blur y", key.key(), self.gbuffer.size);
    }
}

impl AmbientOcclusion {
    /// AO's half-resolution chain after the half-size estimate `source` (its
    /// half-size history, where the raw pass blended it): both blur passes
    /// at half size (ssao/blur.wgsl's HALF), then one depth-aware upsample that writes the
    /// grey RGBA output and multiplies `combine` in
    /// (resolution/upsample.wgsl's AO / AO_COMBINE). The blurs read the
    /// G-buffer, never the packed surface (which is full size).
    fn declare_half_chain<'a>(
        &'a self,
        fg: &mut FrameGraph<'a>,
        mut source: String,
        half: SizeRule,
    ) {
        if self.off() {
            fg.count("AO off: radius 0", 1);
        }
        if self.settings.blur_radius > 0 && !self.off() {
            let steps = [
                (
                    "blur x (half)",
                    BlurPass::Horizontal,
                    "blurred half",
                    "ao blur x",
                ),
                ("blur y (half)", BlurPass::Vertical, "out half", "ao blur y"),
            ];
            for (step, blur, target, label) in steps {
                let mut pass = self.pass(fg, step);
                pass.input("source", &source);
                self.common(&mut pass);
                let target = self.name(target);
                pass.output("output", &target, TextureDesc::storage(R32).size(half));
                let key = BlurKey {
                    pass: blur,
                    packed: false,
                    half: true,
                };
                pass.dispatch_image(label, key.key(), half);
                source = target;
            }
        }
        declare_finish(
            fg,
            FinishPass {
                name: PassName::new(self.settings.mode.name()).step("upsample"),
                owner: self.owner,
                gbuffer: &self.gbuffer,
                half: &source,
                full: &self.output,
                desc: TextureDesc::storage(wgpu::TextureFormat::Rgba16Float)
                    .size(self.gbuffer.size),
                finish: Finish::Ao {
                    combine: name_of(&self.combine),
                },
                counter: HALF_RESOLUTION,
                label: "ao upsample",
            },
        );
    }
}
