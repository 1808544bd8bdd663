//! Screen-space ambient occlusion over the G-buffer: Emeshe's stochastic
//! wide-range AO and its short-range "HBAO", and McGuire's SAO as Castor3D
//! has it. One recipe, three estimators (shaders/occlusion/ao.wgsl), and
//! the passes they share:
//!
//! 1. SAO only: view depth and a mip chain of it (shaders/occlusion/linear_depth.wgsl),
//!    so far taps read coarse levels and stay in cache.
//! 2. Raw AO: per-pixel rotated samples, the rotation changing every frame.
//! 3. Temporal (when the blend is above 0): last frame's result reprojected
//!    with the G-buffer velocity, rejected where depth or normal disagree
//!    (disocclusion), sanitized on read, blended in. The history is a
//!    persistent texture named after the node; a resize, a `Reset` or
//!    `Renderer::reset_history` starts it anew.
//! 4. A depth- and normal-aware separable blur (shaders/occlusion/blur.wgsl),
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
use crate::frame_graph::{FrameGraph, PassContext, SizeRule, TextureDesc};
use crate::gbuffer::GBuffer;
use crate::recipe::{Recipe, TextureRef, next_recipe_id, pass_name};
use crate::renderer::Renderer;
use crate::resolution::{
    Resolution, UpsampleFormat, UpsamplePass, declare_upsample, written_target,
};
use crate::shaders::ShaderKey;
use crate::temporal::{RayParams, TemporalState};

/// Which estimator.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum AoMode {
    /// Emeshe's stochastic wide-range AO: rays in a cosine-weighted
    /// hemisphere, each marched `steps` times against the depth buffer; a
    /// ray is blocked where it passes behind a surface within `radius`.
    /// Matches ray-cast AO of the same radius as samples grow.
    Stochastic,
    /// Scalable Ambient Obscurance (McGuire, Mara, Luebke 2012): a spiral of
    /// taps over a view-depth mip chain, the obscurance estimator with a
    /// smooth falloff. Cheap at large radii; not calibrated to ray-cast AO.
    Sao,
    /// Horizon-based AO (Bavoil 2008): `samples` directions in screen space,
    /// `steps` taps each; per direction the square of the highest horizon's
    /// sine is the (cosine-weighted) occluded share of that slice. Short
    /// range, local detail.
    Hbao,
}

impl AoMode {
    fn feature(self) -> Option<&'static str> {
        match self {
            AoMode::Stochastic => None,
            AoMode::Sao => Some("SAO"),
            AoMode::Hbao => Some("HBAO"),
        }
    }

    fn name(self) -> &'static str {
        match self {
            AoMode::Stochastic => "SSAO",
            AoMode::Sao => "SAO",
            AoMode::Hbao => "HBAO",
        }
    }
}

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

    fn linear_depth(&self, cx: &mut PassContext<'_>, level: usize) -> Result<(), RenderError> {
        let output = self.name(&format!("z{level}"));
        let (source, target) = if level == 0 {
            (
                cx.view_named(&self.gbuffer.targets.depth)?,
                cx.view_named(&output)?,
            )
        } else {
            (
                cx.view_named(&self.name(&format!("z{}", level - 1)))?,
                cx.view_named(&output)?,
            )
        };
        let size = {
            let t = cx.texture_named(&output)?;
            (t.width(), t.height())
        };
        let all = [
            (0, self.gbuffer.camera_buffer().as_entire_binding()),
            (1, wgpu::BindingResource::TextureView(&source)),
            (2, wgpu::BindingResource::TextureView(&target)),
        ];
        let features = if level == 0 {
            vec![]
        } else {
            vec!["DOWNSAMPLE"]
        };
        cx.dispatch_image_numbered(
            if level == 0 {
                "ao view depth"
            } else {
                "ao depth mip"
            },
            &ShaderKey::new("occlusion/linear_depth.wgsl", features),
            &all,
            size,
        )
    }

    /// Full resolution with accumulation: the estimate blends its history
    /// in the raw pass (ao.wgsl's TEMPORAL), with no raw target between.
    fn fused(&self) -> bool {
        self.temporal() && !self.settings.resolution.is_half()
    }

    fn raw(&self, cx: &mut PassContext<'_>) -> Result<(), RenderError> {
        let g = &self.gbuffer.targets;
        let (frame, stale) = self.state.advance(&self.gbuffer, self.settings.reset);
        let reset = stale && self.temporal();
        if reset {
            cx.count("AO history reset", 1);
        }
        self.write_params(cx, frame, reset);
        let fused = self.fused();
        // Fused: last frame's history handed to `previous` before any view
        // of the history is taken (the two may trade textures).
        let (target, fresh) = if fused {
            let fresh = self.hand_over_history(cx)?;
            cx.count(ESTIMATE_TEMPORAL, 1);
            (self.history_name(), fresh)
        } else {
            (
                written_target(&self.name("raw"), self.settings.resolution),
                false,
            )
        };
        let mut views = vec![
            cx.view_named(&g.depth)?,
            cx.view_named(&g.normals)?,
            cx.view_named(&target)?,
        ];
        if self.sao() {
            for k in 0..DEPTH_LEVELS {
                views.push(cx.view_named(&self.name(&format!("z{k}")))?);
            }
        }
        let mut all = vec![
            (0, self.gbuffer.camera_buffer().as_entire_binding()),
            (1, self.params.as_entire_binding()),
        ];
        for (k, v) in views.iter().enumerate() {
            all.push((2 + k as u32, wgpu::BindingResource::TextureView(v)));
        }
        let history_views = if fused {
            Some([
                cx.view_named(&g.velocity_uv)?,
                cx.view_named(&self.name("previous"))?,
            ])
        } else {
            None
        };
        if let Some([velocity, previous]) = &history_views {
            let fresh = &self.fresh[usize::from(fresh)];
            all.push((10, wgpu::BindingResource::TextureView(velocity)));
            all.push((11, wgpu::BindingResource::TextureView(previous)));
            all.push((12, fresh.as_entire_binding()));
        }
        // Off: the plain estimator's early exit writes 1 (no SAO chain to bind).
        let feature = if self.off() {
            None
        } else {
            self.settings.mode.feature()
        };
        let resolution = self.settings.resolution;
        let key = ShaderKey::new(
            "occlusion/ao.wgsl",
            feature
                .into_iter()
                .chain(resolution.feature())
                .chain(fused.then_some("TEMPORAL")),
        );
        let size = resolution.pixels(self.gbuffer.pixel_size(cx.output_size));
        cx.dispatch_image_numbered(self.settings.mode.name(), &key, &all, size)
    }

    /// Last frame's history handed to `previous` before the history is
    /// written again; whether it is fresh (then counted as a reset).
    fn hand_over_history(&self, cx: &mut PassContext<'_>) -> Result<bool, RenderError> {
        let fresh = cx.copy_history(&self.history_name(), &self.name("previous"))?;
        if fresh {
            cx.count("AO history reset", 1);
        }
        Ok(fresh)
    }

    fn temporal_pass(&self, cx: &mut PassContext<'_>) -> Result<(), RenderError> {
        let fresh = self.hand_over_history(cx)?;
        let (history, previous) = (self.history_name(), self.name("previous"));
        let fresh_buffer = &self.fresh[usize::from(fresh)];
        let g = &self.gbuffer.targets;
        let views = [
            cx.view_named(&self.name("raw"))?,
            cx.view_named(&g.depth)?,
            cx.view_named(&g.normals)?,
            cx.view_named(&g.velocity_uv)?,
            cx.view_named(&previous)?,
            cx.view_named(&history)?,
        ];
        let mut all = vec![
            (0, self.gbuffer.camera_buffer().as_entire_binding()),
            (1, self.params.as_entire_binding()),
            (8, fresh_buffer.as_entire_binding()),
        ];
        for (k, v) in views.iter().enumerate() {
            all.push((2 + k as u32, wgpu::BindingResource::TextureView(v)));
        }
        let size = self.gbuffer.pixel_size(cx.output_size);
        cx.dispatch_image_numbered(
            "ao temporal",
            &ShaderKey::new("occlusion/temporal.wgsl", []),
            &all,
            size,
        )
    }

    fn blur(
        &self,
        cx: &mut PassContext<'_>,
        source: &str,
        vertical: bool,
    ) -> Result<(), RenderError> {
        let target = if vertical {
            self.output.clone()
        } else {
            self.name("blurred")
        };
        let g = &self.gbuffer.targets;
        let mut features = Vec::new();
        if vertical {
            features.push("VERTICAL");
        }
        let combine = match (&self.combine, vertical) {
            (Some(c), true) => {
                features.push("COMBINE");
                Some(cx.view_named(&c.name)?)
            }
            _ => None,
        };
        let views = [
            cx.view_named(source)?,
            cx.view_named(&g.depth)?,
            cx.view_named(&g.normals)?,
            cx.view_named(&target)?,
        ];
        let mut all = vec![
            (0, self.gbuffer.camera_buffer().as_entire_binding()),
            (1, self.params.as_entire_binding()),
        ];
        for (k, v) in views.iter().enumerate() {
            all.push((2 + k as u32, wgpu::BindingResource::TextureView(v)));
        }
        if let Some(c) = &combine {
            all.push((6, wgpu::BindingResource::TextureView(c)));
        }
        let size = self.gbuffer.pixel_size(cx.output_size);
        cx.dispatch_image_numbered(
            if vertical { "ao blur y" } else { "ao blur x" },
            &ShaderKey::new("occlusion/blur.wgsl", features),
            &all,
            size,
        )
    }
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
        let levels: Vec<String> = (0..DEPTH_LEVELS)
            .map(|k| self.name(&format!("z{k}")))
            .collect();
        if self.sao() {
            for (k, level) in levels.iter().enumerate() {
                let reads: Vec<&str> = if k == 0 {
                    vec![&g.depth]
                } else {
                    vec![&levels[k - 1]]
                };
                fg.add_pass(
                    pass_name(kind, self.owner, Some(&format!("view depth {k}"))),
                    self.owner,
                    &reads,
                    &[(
                        level,
                        TextureDesc::storage(wgpu::TextureFormat::R32Float)
                            .size(self.level_size(k)),
                    )],
                    move |cx| self.linear_depth(cx, k),
                );
            }
        }
        let raw = self.name("raw");
        let mut reads: Vec<&str> = vec![&g.depth, &g.normals];
        if self.sao() {
            reads.extend(levels.iter().map(String::as_str));
        }
        let resolution = self.settings.resolution;
        let pixels = self.gbuffer.pixel_size(fg.output_size());
        let raw_target = written_target(&self.name("raw"), self.settings.resolution);
        let history = self.history_name();
        let previous = self.name("previous");
        let histories = [
            (
                history.as_str(),
                TextureDesc::history(wgpu::TextureFormat::Rgba16Float).size(self.gbuffer.size),
            ),
            (
                previous.as_str(),
                TextureDesc::history_twin(wgpu::TextureFormat::Rgba16Float).size(self.gbuffer.size),
            ),
        ];
        let raw_name = pass_name(
            kind,
            self.owner,
            Some(&format!("raw{}", resolution.pass_suffix())),
        );
        if self.fused() {
            // The estimate and its accumulation in one pass: straight to the blur.
            reads.push(&g.velocity_uv);
            fg.add_pass(raw_name, self.owner, &reads, &histories, move |cx| {
                self.raw(cx)
            });
            self.declare_blur(fg, history);
            return;
        }
        fg.add_pass(
            raw_name,
            self.owner,
            &reads,
            &[(
                &raw_target,
                full(wgpu::TextureFormat::R32Float)
                    .size(resolution.size_rule(self.gbuffer.size, pixels)),
            )],
            move |cx| self.raw(cx),
        );
        declare_upsample(
            fg,
            resolution,
            UpsamplePass {
                name: pass_name(kind, self.owner, Some("upsample")),
                owner: self.owner,
                gbuffer: &self.gbuffer,
                full: &raw,
                desc: full(wgpu::TextureFormat::R32Float),
                format: UpsampleFormat::R32,
                counter: HALF_RESOLUTION,
                label: "ao upsample",
            },
        );
        let mut source = raw.clone();
        if self.temporal() {
            fg.add_pass(
                pass_name(kind, self.owner, Some("temporal")),
                self.owner,
                &[&raw, &g.depth, &g.normals, &g.velocity_uv],
                &histories,
                move |cx| self.temporal_pass(cx),
            );
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
        let blurred = self.name("blurred");
        let mut last_reads: Vec<&str> = vec![&g.depth, &g.normals];
        last_reads.extend(self.combine.as_ref().map(|c| c.name.as_str()));
        if self.off() {
            fg.count("AO off: radius 0", 1);
        }
        if self.settings.blur_radius > 0 && !self.off() {
            let src = source.clone();
            fg.add_pass(
                pass_name(kind, self.owner, Some("blur x")),
                self.owner,
                &[&source, &g.depth, &g.normals],
                &[(&blurred, full(wgpu::TextureFormat::R32Float))],
                move |cx| self.blur(cx, &src, false),
            );
            last_reads.push(&blurred);
            fg.add_pass(
                pass_name(kind, self.owner, Some("blur y")),
                self.owner,
                &last_reads,
                &[(&self.output, full(wgpu::TextureFormat::Rgba16Float))],
                move |cx| self.blur(cx, &self.name("blurred"), true),
            );
        } else {
            let src = source.clone();
            last_reads.push(&source);
            fg.add_pass(
                pass_name(kind, self.owner, Some("resolve")),
                self.owner,
                &last_reads,
                &[(&self.output, full(wgpu::TextureFormat::Rgba16Float))],
                move |cx| self.blur(cx, &src, true),
            );
        }
    }
}
