//! `SSGI`: one bounce of diffuse light from what the screen sees
//! (shaders/lighting/ssgi.wgsl): stochastic rays gather the lit image where
//! they hit, accumulated over frames (reprojected with the G-buffer
//! velocity, rejected on disocclusion) and blurred with depth and normal
//! awareness. The output is indirect radiance per unit albedo, for
//! CompositeLight's GI input; an optional ambient texture (an
//! environment's diffuse light) is added so one texture carries both.
//! At [`Resolution::Half`] the gather runs for one pixel in four, and the
//! temporal blend and both blur passes run on that half-size image too (the
//! history at half size; the blur reading the full G-buffer at each half
//! texel's own pixel, taps two pixels apart); one depth-aware upsample at
//! the end writes the output and adds the ambient (crate::resolution's half
//! chain). [`Resolution::Auto`] resolves to one of the two when the passes
//! are declared, by the frame's size.

use std::sync::Arc;

use crate::error::RenderError;
use crate::frame_graph::{
    Bindings, FrameGraph, PassBuilder, PassContext, SizeRule, Tex, TextureDesc,
};
use crate::gbuffer::GBuffer;
use crate::packed_surface::{self, Reader, SurfaceInputs};
use crate::recipe::{Recipe, TextureRef, next_recipe_id};
use crate::renderer::Renderer;
use crate::report::PassName;
use crate::resolution::{Finish, FinishPass, Resolution, declare_finish, written_target};
use crate::shaders::Permutation;
use crate::temporal::{RayParams, RayUniforms};

pub use super::ssgi_key::SsgiKey;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SsgiSettings {
    /// World units a ray travels.
    pub radius: f32,
    /// Rays per pixel per frame, 1..=32.
    pub samples: u32,
    /// Steps along each ray, 1..=32.
    pub steps: u32,
    /// A scale on the gathered light (1: physically one bounce).
    pub intensity: f32,
    /// 0..=0.98: last frame's weight (0: no temporal pass).
    pub temporal_blend: f32,
    /// Blur half-width in pixels, 0..=16.
    pub blur_radius: u32,
    pub reset: bool,
    /// Where the gather runs: every pixel, or one in four upsampled.
    pub resolution: Resolution,
}

/// Counted when an SSGI's gather ran at half resolution.
pub const HALF_RESOLUTION: &str = "SSGI at half resolution";
/// Counted when the history starts anew (a resize, a `Reset`, a camera cut).
const HISTORY_RESET: &str = "SSGI history reset";
/// Statistic: SSGI gathers that blended their history in the same pass
/// (full resolution with temporal accumulation), writing no raw target.
pub const GATHER_TEMPORAL: &str = "SSGI gathered and accumulated in one pass";

impl Default for SsgiSettings {
    fn default() -> Self {
        SsgiSettings {
            radius: 2.0,
            samples: 4,
            steps: 8,
            intensity: 1.0,
            temporal_blend: 0.9,
            blur_radius: 4,
            reset: false,
            resolution: Resolution::Auto,
        }
    }
}

impl SsgiSettings {
    fn clamped(self) -> Self {
        let clean = |v: f32, lo: f32, hi: f32| if v.is_finite() { v.clamp(lo, hi) } else { 0.0 };
        SsgiSettings {
            radius: clean(self.radius, 0.0, 1e6),
            samples: self.samples.clamp(1, 32),
            steps: self.steps.clamp(1, 32),
            intensity: clean(self.intensity, 0.0, 1e3),
            temporal_blend: clean(self.temporal_blend, 0.0, 0.98),
            blur_radius: self.blur_radius.min(16),
            reset: self.reset,
            resolution: self.resolution,
        }
    }
}

pub struct Ssgi {
    id: u64,
    owner: Option<u32>,
    gbuffer: Arc<GBuffer>,
    source: TextureRef,
    ambient: Option<TextureRef>,
    settings: SsgiSettings,
    /// The parameters, written each frame, and the history's state.
    rays: RayUniforms,
    /// The blur's direction per pass: x, then y.
    axes: [wgpu::Buffer; 2],
    prefix: String,
    pub output: String,
}

impl Ssgi {
    /// `source`: the lit image light bounces from (CookTorrance's diffuse, or
    /// a CompositeLight without GI); `ambient`: light added to the result.
    pub fn new(
        renderer: &Renderer,
        owner: Option<u32>,
        gbuffer: Arc<GBuffer>,
        source: TextureRef,
        ambient: Option<TextureRef>,
        settings: SsgiSettings,
    ) -> Arc<Self> {
        let id = next_recipe_id();
        // Constant per node: kept, so the blur's bind groups are reused.
        let kept = |label: &'static str, index: u32, words: [i32; 4]| {
            renderer.kept_init_at(
                owner,
                label,
                index,
                bytemuck::cast_slice(&words),
                wgpu::BufferUsages::UNIFORM,
            )
        };
        let prefix = format!("ssgi{id}");
        Arc::new(Ssgi {
            id,
            owner,
            gbuffer,
            source,
            ambient,
            settings: settings.clamped(),
            rays: RayUniforms::new(
                renderer,
                owner,
                id,
                ["ssgi params", "ssgi fresh", HISTORY_RESET],
            ),
            axes: [
                kept("ssgi axis", 0, [1, 0, 0, 0]),
                kept("ssgi axis", 1, [0, 1, 0, 0]),
            ],
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

    fn name(&self, what: &str) -> String {
        format!("{}/{what}", self.prefix)
    }

    /// The half chain's targets (frame-graph names), for tests and tools:
    /// the half-size gather and the blur's half-size result (what the
    /// upsample reads when the blur runs).
    pub fn half_targets(&self) -> [String; 2] {
        [
            written_target(&self.name("raw"), Resolution::Half),
            self.name("out half"),
        ]
    }

    /// The persistent history (RGBA16F: bounce radiance, escaped share), per node.
    pub fn history_name(&self) -> String {
        format!("ssgi-history-{}", self.rays.key)
    }

    /// The persistent view distance under each history texel (R32F).
    fn distance_name(&self) -> String {
        format!("ssgi-distance-{}", self.rays.key)
    }

    /// Radius 0 gathers nothing: the gather writes no bounce and every ray escapes.
    fn off(&self) -> bool {
        self.settings.radius <= 0.0
    }

    fn temporal(&self) -> bool {
        self.settings.temporal_blend > 0.0 && !self.off()
    }

    fn ray_params(&self) -> RayParams {
        let s = self.settings;
        RayParams {
            radius: s.radius,
            intensity: s.intensity,
            blend: s.temporal_blend,
            samples: s.samples,
            steps: s.steps,
            blur_radius: if self.off() { 0 } else { s.blur_radius },
        }
    }

    /// One pass: the camera, the parameters, the G-buffer's depth and
    /// normals, what it reads as `source` and writes as `output`, and `more`.
    fn dispatch(
        &self,
        cx: &mut PassContext<'_>,
        label: &str,
        key: SsgiKey,
        io: &PassIo,
        more: Bindings<'_>,
    ) -> Result<(), RenderError> {
        let mut size = self.gbuffer.pixel_size(cx.output_size);
        if let SsgiKey::Gather { half: true, .. }
        | SsgiKey::Temporal { half: true, .. }
        | SsgiKey::Blur { half: true, .. } = key
        {
            size = Resolution::Half.pixels(size);
        }
        let b = Bindings::new()
            .buffer("camera", self.gbuffer.camera_buffer())
            .buffer("params", self.rays.params())
            .texture("depth", io.depth)
            .texture("normals", io.normals)
            .texture("source", io.source)
            .texture("output", io.output)
            .texture_opt("surface", io.surface)
            .texture_opt("view_z", io.view_z)
            .extend(more);
        cx.dispatch_image(label, &key.key(), b, size)
    }

    /// The frame's start, in the pass that gathers: the node's frame count
    /// advanced (it turns the rays), a stale history counted as reset, and
    /// the parameters written.
    fn begin_frame(&self, cx: &mut PassContext<'_>) {
        let (reset, temporal) = (self.settings.reset, self.temporal());
        self.rays
            .begin(cx, &self.gbuffer, &self.ray_params(), reset, temporal);
    }

    fn raw(
        &self,
        cx: &mut PassContext<'_>,
        io: &PassIo,
        resolution: Resolution,
    ) -> Result<(), RenderError> {
        self.begin_frame(cx);
        let key = SsgiKey::Gather {
            half: resolution.is_half(),
            packed: io.view_z.is_some(),
        };
        self.dispatch(cx, "ssgi", key, io, Bindings::new())
    }

    /// Full resolution: the gather and the temporal blend in one pass
    /// (GATHER), writing the history with no raw target between.
    fn fused(&self, resolution: Resolution) -> bool {
        self.temporal() && !resolution.is_half()
    }

    /// The gather and the temporal blend in one dispatch ([`Ssgi::fused`]).
    fn gather_temporal(
        &self,
        cx: &mut PassContext<'_>,
        io: &PassIo,
        t: &TemporalIo,
    ) -> Result<(), RenderError> {
        self.begin_frame(cx);
        cx.count(GATHER_TEMPORAL, 1);
        self.temporal_pass(cx, true, false, io, t)
    }

    /// The temporal blend into the history (`io.output`): of the raw target,
    /// or with `gather` of the bounce gathered in the same dispatch; `half`:
    /// the half chain's, at half size.
    fn temporal_pass(
        &self,
        cx: &mut PassContext<'_>,
        gather: bool,
        half: bool,
        io: &PassIo,
        t: &TemporalIo,
    ) -> Result<(), RenderError> {
        let fresh = cx.copy_history(io.output, t.previous)?
            | cx.copy_history(t.distance, t.previous_distance)?;
        if fresh {
            cx.count(HISTORY_RESET, 1);
        }
        let label = if gather { "ssgi" } else { "ssgi temporal" };
        let more = Bindings::new()
            .texture("velocity_uv", t.velocity_uv)
            .texture("previous", t.previous)
            .texture("previous_distance", t.previous_distance)
            .texture("distance", t.distance)
            .buffer("fresh", self.rays.fresh(fresh));
        let key = SsgiKey::Temporal {
            gather,
            packed: io.view_z.is_some(),
            half,
        };
        self.dispatch(cx, label, key, io, more)
    }

    fn blur(
        &self,
        cx: &mut PassContext<'_>,
        io: &PassIo,
        vertical: bool,
        ambient: Option<Tex>,
        half: bool,
    ) -> Result<(), RenderError> {
        let label = if vertical {
            "ssgi blur y"
        } else {
            "ssgi blur x"
        };
        let more = Bindings::new()
            .buffer("axis", &self.axes[usize::from(vertical)])
            .texture_opt("ambient", ambient);
        let key = SsgiKey::Blur {
            ambient: ambient.is_some(),
            packed: io.surface.is_some(),
            half,
        };
        self.dispatch(cx, label, key, io, more)
    }
}

/// What an SSGI pass declared: the G-buffer's depth and normals, its
/// source and its output (the history, for a temporal pass).
#[derive(Clone, Copy)]
struct PassIo {
    depth: Tex,
    normals: Tex,
    source: Tex,
    output: Tex,
    /// A blur's packed surface (crate::packed_surface), when it reads one.
    surface: Option<Tex>,
    /// A gather's packed view z, when its rays read it.
    view_z: Option<Tex>,
}

/// A temporal pass's history twins and reprojection.
#[derive(Clone, Copy)]
struct TemporalIo {
    velocity_uv: Tex,
    previous: Tex,
    distance: Tex,
    previous_distance: Tex,
}

impl Ssgi {
    /// A pass over the G-buffer reading `source` and writing `output` as `desc`.
    fn declare_pass(
        &self,
        pass: &mut PassBuilder<'_, '_>,
        source: &str,
        output: &str,
        desc: TextureDesc,
    ) -> PassIo {
        let g = &self.gbuffer.targets;
        PassIo {
            depth: pass.read(&g.depth),
            normals: pass.read(&g.normals),
            source: pass.read(source),
            output: pass.write(output, desc),
            surface: None,
            view_z: None,
        }
    }

    /// A temporal pass: the bounce history (its output) and the view
    /// distance under it, each with its twin holding last frame's; `size`:
    /// the G-buffer's, or half of it (a change of size starts the history
    /// anew, as a resize does).
    fn declare_temporal(
        &self,
        pass: &mut PassBuilder<'_, '_>,
        source: &str,
        size: SizeRule,
    ) -> (PassIo, TemporalIo) {
        let (rgba16, r32) = (
            wgpu::TextureFormat::Rgba16Float,
            wgpu::TextureFormat::R32Float,
        );
        let io = self.declare_pass(
            pass,
            source,
            &self.history_name(),
            TextureDesc::history(rgba16).size(size),
        );
        let t = TemporalIo {
            velocity_uv: pass.read(&self.gbuffer.targets.velocity_uv),
            previous: pass.write(
                &self.name("previous"),
                TextureDesc::history_twin(rgba16).size(size),
            ),
            distance: pass.write(&self.distance_name(), TextureDesc::history(r32).size(size)),
            previous_distance: pass.write(
                &self.name("previous distance"),
                TextureDesc::history_twin(r32).size(size),
            ),
        };
        (io, t)
    }
}

impl Ssgi {
    /// The gather (full or half resolution), then the temporal blend in its
    /// own pass when there is one (only at half resolution: at full the
    /// gather blends itself); returns what the blur reads, half size at Half.
    /// `view_z`: the packed view z the gather's rays read.
    fn declare_unfused<'a>(
        &'a self,
        fg: &mut FrameGraph<'a>,
        view_z: Option<&str>,
        resolution: Resolution,
    ) -> String {
        let rgba = TextureDesc::storage(wgpu::TextureFormat::Rgba16Float).size(self.gbuffer.size);
        let raw_target = written_target(&self.name("raw"), resolution);
        let pixels = self.gbuffer.pixel_size(fg.output_size());
        let size = resolution.size_rule(self.gbuffer.size, pixels);
        let mut pass = fg.pass(
            PassName::new("SSGI").step(format!("gather{}", resolution.pass_suffix())),
            self.owner,
        );
        let mut io = self.declare_pass(&mut pass, &self.source.name, &raw_target, rgba.size(size));
        io.view_z = view_z.map(|v| pass.read(v));
        let key = SsgiKey::Gather {
            half: resolution.is_half(),
            packed: io.view_z.is_some(),
        };
        pass.will_dispatch(&key.key(), "main");
        pass.run(move |cx| self.raw(cx, &io, resolution));
        if !self.temporal() {
            return raw_target;
        }
        let mut pass = fg.pass(
            PassName::new("SSGI").step(format!("temporal{}", resolution.pass_suffix())),
            self.owner,
        );
        let (io, t) = self.declare_temporal(&mut pass, &raw_target, size);
        let half = resolution.is_half();
        let key = SsgiKey::Temporal {
            gather: false,
            packed: false,
            half,
        };
        pass.will_dispatch(&key.key(), "main");
        pass.run(move |cx| self.temporal_pass(cx, false, half, &io, &t));
        self.history_name()
    }

    /// The half chain's blur (x then y at half size, from the G-buffer: the
    /// packed surface is full size) of `source`, then the upsample that
    /// writes the output and adds the ambient ([`Finish::Light`]).
    fn declare_half_blur<'a>(
        &'a self,
        fg: &mut FrameGraph<'a>,
        mut source: String,
        half: SizeRule,
    ) {
        let rgba = TextureDesc::storage(wgpu::TextureFormat::Rgba16Float).size(half);
        if self.settings.blur_radius > 0 && !self.off() {
            let key = SsgiKey::Blur {
                ambient: false,
                packed: false,
                half: true,
            };
            for (vertical, step, target) in [
                (false, "blur x (half)", "blurred half"),
                (true, "blur y (half)", "out half"),
            ] {
                let target = self.name(target);
                let mut pass = fg.pass(PassName::new("SSGI").step(step), self.owner);
                let io = self.declare_pass(&mut pass, &source, &target, rgba);
                pass.will_dispatch(&key.key(), "main");
                pass.run(move |cx| self.blur(cx, &io, vertical, None, true));
                source = target;
            }
        }
        declare_finish(
            fg,
            FinishPass {
                name: PassName::new("SSGI").step("upsample"),
                owner: self.owner,
                gbuffer: &self.gbuffer,
                half: &source,
                full: &self.output,
                desc: TextureDesc::storage(wgpu::TextureFormat::Rgba16Float)
                    .size(self.gbuffer.size),
                finish: Finish::Light {
                    ambient: self.ambient.as_ref().map(|a| a.name.as_str()),
                },
                counter: HALF_RESOLUTION,
                label: "ssgi upsample",
            },
        );
    }
}

impl Recipe for Ssgi {
    fn declare<'a>(&'a self, renderer: &'a Renderer, fg: &mut FrameGraph<'a>) {
        if !fg.include(self.id) {
            return;
        }
        self.gbuffer.declare(renderer, fg);
        self.source.recipe.declare(renderer, fg);
        if let Some(a) = &self.ambient {
            a.recipe.declare(renderer, fg);
        }
        let rgba = TextureDesc::storage(wgpu::TextureFormat::Rgba16Float).size(self.gbuffer.size);
        // The rays read the packed view z (not when off: the early exit reads nothing).
        let view_z = (!self.off()
            && packed_surface::inputs(renderer, Reader::Rays) == SurfaceInputs::Packed)
            .then(|| packed_surface::declare(fg, &self.gbuffer).view_z);
        let pixels = self.gbuffer.pixel_size(fg.output_size());
        let resolution = self.settings.resolution.resolve_in(renderer, fg, pixels);
        let source = if self.fused(resolution) {
            let mut pass = fg.pass(PassName::new("SSGI").step("gather"), self.owner);
            let (mut io, t) =
                self.declare_temporal(&mut pass, &self.source.name, self.gbuffer.size);
            io.view_z = view_z.as_deref().map(|v| pass.read(v));
            let key = SsgiKey::Temporal {
                gather: true,
                packed: io.view_z.is_some(),
                half: false,
            };
            pass.will_dispatch(&key.key(), "main");
            pass.run(move |cx| self.gather_temporal(cx, &io, &t));
            self.history_name()
        } else {
            self.declare_unfused(fg, view_z.as_deref(), resolution)
        };
        let mut last = source;
        if self.off() {
            fg.count("SSGI off: radius 0", 1);
        }
        if resolution.is_half() {
            let half = resolution.size_rule(self.gbuffer.size, pixels);
            return self.declare_half_blur(fg, last, half);
        }
        let blur = self.settings.blur_radius > 0 && !self.off();
        // The taps of a blur (radius above 0) read the packed surface; the
        // resolve alone (radius 0) reads only its own pixel.
        let packed =
            blur && packed_surface::inputs(renderer, Reader::Blurs) == SurfaceInputs::Packed;
        let surface = packed.then(|| packed_surface::declare(fg, &self.gbuffer).surface);
        if blur {
            let blurred = self.name("blurred");
            let mut pass = fg.pass(PassName::new("SSGI").step("blur x"), self.owner);
            let mut io = self.declare_pass(&mut pass, &last, &blurred, rgba);
            io.surface = surface.as_deref().map(|s| pass.read(s));
            let key = SsgiKey::Blur {
                ambient: false,
                packed,
                half: false,
            };
            pass.will_dispatch(&key.key(), "main");
            pass.run(move |cx| self.blur(cx, &io, false, None, false));
            last = blurred;
        }
        let mut pass = fg.pass(PassName::new("SSGI").step("blur y"), self.owner);
        let mut io = self.declare_pass(&mut pass, &last, &self.output, rgba);
        io.surface = surface.as_deref().map(|s| pass.read(s));
        let ambient = pass.read_opt(self.ambient.as_ref().map(|a| a.name.as_str()));
        let key = SsgiKey::Blur {
            ambient: ambient.is_some(),
            packed,
            half: false,
        };
        pass.will_dispatch(&key.key(), "main");
        pass.run(move |cx| self.blur(cx, &io, true, ambient, false));
    }
}
