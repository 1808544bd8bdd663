//! `SSR`: screen-space reflection with roughness over the G-buffer
//! (shaders/environment/ssr.wgsl): a hierarchical depth (Hi-Z) of the
//! reversed-Z depth, rays traced through it in screen space reading a lit
//! image, a fallback (Reflection's specular) where rays miss or leave the
//! screen, and optionally a temporal blend with a persistent history.
//!
//! The output is reflected radiance times the split-sum factor, as
//! Reflection's specular, so the two are interchangeable. Passes: "hi-z"
//! and "trace", which at full resolution also blends in the history when
//! accumulating ([`TRACE_TEMPORAL`]). At [`Resolution::Half`] the trace runs
//! for one pixel in four ("trace (half)"), an "upsample" pass
//! (crate::resolution) fills the full-size target with depth awareness, and
//! with temporal accumulation a "resolve" pass blends it.
//!
//! A world with a Clearcoat material compiles `CLEARCOAT` into the trace:
//! a coated pixel traces the coat's lobe as well (its normal, its
//! roughness, f0 0.04) over the base's dimmed by what the coat reflects,
//! as Reflection composes the two from the environment.

use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::{Arc, Mutex};

mod hi_z;
pub(crate) mod key;

pub use hi_z::HIZ_DISPATCHES;
pub use key::{SsrKey, SsrTarget};

use super::prefilter::{SplitSumStore, split_sum_table};
use crate::error::RenderError;
use crate::frame_graph::{Bindings, FrameGraph, PassBuilder, PassContext, Tex, TextureDesc};
use crate::gbuffer::GBuffer;
use crate::material::{
    FEATURE_CLEARCOAT, FEATURE_COOK_TORRANCE, FEATURE_REFLECTION, MaterialTextures, MaterialWorld,
};
use crate::recipe::{Recipe, TextureRef, next_recipe_id};
use crate::renderer::Renderer;
use crate::report::PassName;
use crate::resolution::{
    Resolution, ResolvedCell, UpsampleFormat, UpsamplePass, declare_upsample, written_target,
};
use crate::shaders::{Permutation, Sampling};
use crate::temporal::TemporalState;

/// The quality pins.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SsrSettings {
    /// Steps per ray (each a Hi-Z cell or a level change), 1..=1024.
    pub max_steps: u32,
    /// Rays per pixel (GGX-jittered at roughness above 0.02), 1..=64.
    pub rays: u32,
    /// Blend with last frame's result (a persistent history per node).
    pub temporal: bool,
    /// The new frame's weight in the blend, 0.01..=1.
    pub blend: f32,
    /// How thick a surface is assumed behind its depth, in view units.
    pub thickness: f32,
    /// Drop the history this frame (a camera cut).
    pub reset: bool,
    /// Where rays are traced: every pixel, or one in four upsampled.
    pub resolution: Resolution,
}

/// Counted when an SSR traced at half resolution.
pub const HALF_RESOLUTION: &str = "SSR at half resolution";

impl Default for SsrSettings {
    fn default() -> Self {
        SsrSettings {
            max_steps: 64,
            rays: 1,
            temporal: true,
            blend: 0.2,
            thickness: 0.5,
            reset: false,
            resolution: Resolution::Auto,
        }
    }
}

impl SsrSettings {
    fn sanitized(self) -> Self {
        let finite = |v: f32, lo: f32, hi: f32, fallback: f32| {
            if v.is_finite() {
                v.clamp(lo, hi)
            } else {
                fallback
            }
        };
        SsrSettings {
            max_steps: self.max_steps.clamp(1, 1024),
            rays: self.rays.clamp(1, 64),
            temporal: self.temporal,
            blend: finite(self.blend, 0.01, 1.0, 0.2),
            thickness: finite(self.thickness, 1e-3, 1e3, 0.5),
            reset: self.reset,
            resolution: self.resolution,
        }
    }
}

/// Matches `Params` in shaders/environment/ssr.wgsl.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct Params {
    max_steps: u32,
    rays: u32,
    frame: u32,
    flags: u32,
    near: f32,
    thickness: f32,
    blend: f32,
    max_level: u32,
}

/// Statistic: traces that blended the history in the same pass (full
/// resolution with temporal accumulation), writing no raw target.
pub const TRACE_TEMPORAL: &str = "SSR traced and blended in one pass";

/// What an SSR node keeps between frames: its Hi-Z texture and frame count.
#[derive(Default)]
pub struct SsrStore {
    hiz: Mutex<Option<wgpu::Texture>>,
    frame: AtomicU32,
}

pub struct Ssr {
    /// Last frame's camera, to tell a cut (the history no longer fits).
    temporal_state: Arc<TemporalState>,
    id: u64,
    owner: Option<u32>,
    gbuffer: Arc<GBuffer>,
    materials: Arc<MaterialWorld>,
    lit: TextureRef,
    fallback: TextureRef,
    pub settings: SsrSettings,
    store: Arc<SsrStore>,
    table: Arc<SplitSumStore>,
    trace_params: wgpu::Buffer,
    resolve_params: wgpu::Buffer,
    token: String,
    /// The half-size trace (Half only).
    current: String,
    /// The persistent history (temporal only).
    pub history: String,
    pub output: String,
    /// `settings.resolution` as it resolved when the passes were declared
    /// (Auto by the frame's size: crate::resolution).
    resolved: ResolvedCell,
}

/// The near plane of a reversed- or forward-Z perspective projection (0.1 when unknown).
fn near_plane(projection: glam::Mat4) -> f32 {
    let (a, b) = (projection.z_axis.z, projection.w_axis.z);
    let near = b / a;
    if near.is_finite() && near > 0.0 {
        near
    } else {
        0.1
    }
}

impl Ssr {
    pub fn new(
        renderer: &Renderer,
        owner: Option<u32>,
        gbuffer: Arc<GBuffer>,
        materials: Arc<MaterialWorld>,
        lit: TextureRef,
        fallback: TextureRef,
        settings: SsrSettings,
    ) -> Arc<Self> {
        let id = next_recipe_id();
        let store = match owner {
            Some(node) => renderer.state::<SsrStore>(u64::from(node)),
            None => Arc::new(SsrStore::default()),
        };
        // Written each frame; kept under the node so its bind groups are reused.
        let uniform = |label| {
            renderer.kept_buffer(
                owner,
                label,
                std::mem::size_of::<Params>() as u64,
                wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            )
        };
        let key = owner.map_or(format!("recipe{id}"), |n| format!("node{n}"));
        Arc::new(Ssr {
            id,
            owner,
            gbuffer,
            materials,
            lit,
            fallback,
            settings: settings.sanitized(),
            store,
            table: renderer.state::<SplitSumStore>(0),
            temporal_state: renderer.state::<TemporalState>(owner.map_or(id, u64::from)),
            trace_params: uniform("ssr trace params"),
            resolve_params: uniform("ssr resolve params"),
            token: format!("ssr{id}/hiz"),
            current: format!("ssr{id}/current"),
            history: format!("ssr/{key}/history"),
            resolved: ResolvedCell::default(),
            output: format!("ssr{id}/reflection"),
        })
    }

    pub fn texture(self: &Arc<Self>) -> TextureRef {
        TextureRef {
            recipe: self.clone(),
            name: self.output.clone(),
        }
    }

    /// The hierarchical depth the last frame built (R32Float, every mip),
    /// if one ran: for tests and tools.
    pub fn hi_z(&self) -> Option<wgpu::Texture> {
        self.store
            .hiz
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .clone()
    }

    /// Whether some material reflects: otherwise nothing is traced.
    pub fn active(&self) -> bool {
        self.materials.any_has(FEATURE_REFLECTION)
    }

    fn textured(&self) -> bool {
        self.materials.textured(1 << FEATURE_COOK_TORRANCE)
    }

    /// The trace's key: with `history`, it blends the history in itself.
    fn trace_key(&self, history: bool) -> SsrKey {
        let target = if history {
            SsrTarget::FullTemporal
        } else if self.resolution().is_half() {
            SsrTarget::Half
        } else {
            SsrTarget::Full
        };
        SsrKey {
            material_textures: self.textured(),
            surface_target: self.gbuffer.targets.surface.is_some(),
            // Only a world with a coat traces the coat's lobe.
            clearcoat: self.materials.any_has(FEATURE_CLEARCOAT),
            target,
        }
    }

    /// Full or Half: the setting as resolved when the passes were declared.
    fn resolution(&self) -> Resolution {
        self.resolved.get()
    }

    fn label(&self, what: impl Into<std::borrow::Cow<'static, str>>) -> PassName {
        PassName::new("SSR").step(what)
    }

    fn params(&self, frame: u32, flags: u32, max_level: u32) -> Params {
        Params {
            max_steps: self.settings.max_steps,
            rays: self.settings.rays,
            frame,
            flags,
            near: near_plane(self.gbuffer.camera.projection),
            thickness: self.settings.thickness,
            blend: self.settings.blend,
            max_level,
        }
    }

    /// Full resolution with temporal accumulation: the trace blends in the
    /// history itself, and there is no resolve pass.
    fn fused(&self) -> bool {
        self.settings.temporal && !self.resolution().is_half()
    }

    /// The blend's flags for this frame: bit 0 when the history holds a
    /// previous frame (not fresh, not reset, no camera cut).
    fn history_flags(&self, cx: &mut PassContext<'_>, history: Tex) -> u32 {
        let (_, stale) = self
            .temporal_state
            .advance(&self.gbuffer, self.settings.reset);
        let fresh = cx.is_fresh(history) || stale;
        cx.count(
            if fresh {
                "ssr history reset"
            } else {
                "ssr history used"
            },
            1,
        );
        u32::from(!fresh)
    }

    fn trace(&self, cx: &mut PassContext<'_>, io: &TraceIo) -> Result<(), RenderError> {
        cx.count("ssr traced", 1);
        let flags = match io.history {
            Some(h) => {
                cx.count(TRACE_TEMPORAL, 1);
                self.history_flags(cx, h.history)
            }
            None => 0,
        };
        let frame = self.store.frame.fetch_add(1, Ordering::Relaxed);
        let hiz = self
            .store
            .hiz
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .clone()
            .ok_or_else(|| RenderError::Pass {
                pass: self.label("trace").text(self.owner),
                message: "the hi-z was not built".to_owned(),
            })?;
        let lut = split_sum_table(cx, &self.table)?;
        let max_level = hiz.mip_level_count().saturating_sub(1);
        cx.gpu.queue.write_buffer(
            &self.trace_params,
            0,
            bytemuck::bytes_of(&self.params(frame, flags, max_level)),
        );
        let g = &self.gbuffer;
        let resolution = self.resolution();
        let mut b = Bindings::new()
            .buffer("camera", g.camera_buffer())
            .buffer("params", &self.trace_params)
            .texture("color", io.color)
            .texture("normals", io.normals)
            .texture("depth", io.depth)
            .view("hiz", cx.view_of(&hiz, Default::default()))
            .texture("lit", io.lit)
            .texture("fallback", io.fallback)
            .view("lut", cx.view_of(&lut, Default::default()))
            .sampler("lut_sampler", Sampling::LinearClamp)
            .texture("output", io.output)
            .texture_opt("surface_target", io.surface)
            .extend(self.materials.bindings(io.material_textures));
        if let Some(h) = io.history {
            b = b
                .texture("history", h.history)
                .texture("velocity_uv", h.velocity_uv);
        }
        let (w, h) = resolution.pixels(g.pixel_size(cx.output_size));
        cx.dispatch_shader(
            "ssr trace",
            &self.trace_key(io.history.is_some()).key(),
            "main",
            b,
            (w.div_ceil(8), h.div_ceil(8), 1),
        )?;
        if let Some(h) = io.history {
            // This frame's result is next frame's history.
            cx.keep_as_history(io.output, h.history)?;
        }
        Ok(())
    }

    /// The full-size texture the trace's result lands in: the temporal
    /// resolve's input (after a half-resolution trace), or the output itself.
    fn full_target(&self) -> &str {
        if self.settings.temporal && !self.fused() {
            &self.current
        } else {
            &self.output
        }
    }

    /// Where the trace writes: the full-size target, or its half-size twin.
    fn trace_target(&self) -> String {
        written_target(self.full_target(), self.resolution())
    }

    fn resolve(&self, cx: &mut PassContext<'_>, io: &ResolveIo) -> Result<(), RenderError> {
        // Fresh (first frame, resize), asked to reset, or a camera cut: no history.
        let flags = self.history_flags(cx, io.history.history);
        let frame = self.store.frame.load(Ordering::Relaxed);
        cx.gpu.queue.write_buffer(
            &self.resolve_params,
            0,
            bytemuck::bytes_of(&self.params(frame, flags, 0)),
        );
        let g = &self.gbuffer;
        let size = g.pixel_size(cx.output_size);
        cx.dispatch_shader(
            "ssr resolve",
            &SsrKey::PLAIN.key(),
            "resolve",
            Bindings::new()
                .buffer("camera", g.camera_buffer())
                .buffer("params", &self.resolve_params)
                .texture("depth", io.depth)
                .texture("output", io.output)
                .texture("current", io.current)
                .texture("history", io.history.history)
                .texture("velocity_uv", io.history.velocity_uv),
            (size.0.div_ceil(8), size.1.div_ceil(8), 1),
        )?;
        // This frame's result is next frame's history.
        cx.keep_as_history(io.output, io.history.history)
    }

    fn clear(&self, cx: &mut PassContext<'_>, output: Tex) -> Result<(), RenderError> {
        cx.count("ssr skipped", 1);
        let (w, h) = self.gbuffer.pixel_size(cx.output_size);
        cx.dispatch_shader(
            "ssr clear",
            &SsrKey::PLAIN.key(),
            "clear",
            Bindings::new()
                .buffer("camera", self.gbuffer.camera_buffer())
                .texture("output", output),
            (w.div_ceil(8), h.div_ceil(8), 1),
        )
    }
}

/// Last frame's reflection and the reprojection that reads it.
#[derive(Clone, Copy)]
struct HistoryIo {
    history: Tex,
    velocity_uv: Tex,
}

/// What the trace declared; with `history`, it blends into it (full
/// resolution with temporal accumulation) and `output` becomes the history.
struct TraceIo {
    color: Tex,
    normals: Tex,
    depth: Tex,
    lit: Tex,
    fallback: Tex,
    output: Tex,
    surface: Option<Tex>,
    history: Option<HistoryIo>,
    material_textures: Option<MaterialTextures>,
}

/// What the temporal resolve (after a half-resolution trace) declared.
struct ResolveIo {
    current: Tex,
    depth: Tex,
    output: Tex,
    history: HistoryIo,
}

impl Recipe for Ssr {
    fn declare<'a>(&'a self, renderer: &'a Renderer, fg: &mut FrameGraph<'a>) {
        if !fg.include(self.id) {
            return;
        }
        let pixels = self.gbuffer.pixel_size(fg.output_size());
        self.resolved
            .set(self.settings.resolution.resolve_in(renderer, fg, pixels));
        self.gbuffer.declare(renderer, fg);
        let hdr = TextureDesc::storage(wgpu::TextureFormat::Rgba16Float).size(self.gbuffer.size);
        if !self.active() {
            let mut pass = fg.pass(self.label("none reflective"), self.owner);
            let output = pass.write(&self.output, hdr);
            pass.run(move |cx| self.clear(cx, output));
            return;
        }
        self.lit.recipe.declare(renderer, fg);
        self.fallback.recipe.declare(renderer, fg);
        self.materials
            .declare_upstream(renderer, fg, self.textured());
        let g = &self.gbuffer.targets;
        let mut pass = fg.pass(self.label("hi-z"), self.owner);
        let depth = pass.read(&g.depth);
        pass.write(&self.token, TextureDesc::token());
        pass.run(move |cx| self.build_hiz(cx, depth));
        // The pipelines the hi-z, the trace and the resolve dispatch
        // (frame_graph/gather.rs; the hi-z's entries as hi_z.rs names them).
        let plain = SsrKey::PLAIN.key();
        for entry in ["hiz_first", "hiz_down", "hiz_down2", "hiz_tail"] {
            fg.will_dispatch(&plain, entry);
        }
        fg.will_dispatch(&self.trace_key(self.fused()).key(), "main");
        if self.settings.temporal && !self.fused() {
            fg.will_dispatch(&plain, "resolve");
        }
        let resolution = self.resolution();
        let pixels = self.gbuffer.pixel_size(fg.output_size());
        // Alike, so the output becomes the history without a copy.
        let rgba = wgpu::TextureFormat::Rgba16Float;
        let histories = |pass: &mut PassBuilder<'_, '_>| {
            let output = pass.write(
                &self.output,
                TextureDesc::history_twin(rgba).size(self.gbuffer.size),
            );
            let history = HistoryIo {
                history: pass.write(
                    &self.history,
                    TextureDesc::history(rgba).size(self.gbuffer.size),
                ),
                velocity_uv: pass.read(&g.velocity_uv),
            };
            (output, history)
        };
        let trace_target = self.trace_target();
        let mut pass = fg.pass(
            self.label(format!("trace{}", resolution.pass_suffix())),
            self.owner,
        );
        pass.read(&self.token);
        let (output, history) = if self.fused() {
            let (output, history) = histories(&mut pass);
            (output, Some(history))
        } else {
            let desc = hdr.size(resolution.size_rule(self.gbuffer.size, pixels));
            (pass.write(&trace_target, desc), None)
        };
        let io = TraceIo {
            color: pass.read(&g.color),
            normals: pass.read(&g.normals),
            depth: pass.read(&g.depth),
            lit: pass.read(&self.lit.name),
            fallback: pass.read(&self.fallback.name),
            surface: pass.read_opt(g.surface.as_deref()),
            material_textures: self.materials.read_textures(
                &mut pass,
                self.textured(),
                g.surface_targets(),
            ),
            output,
            history,
        };
        pass.run(move |cx| self.trace(cx, &io));
        declare_upsample(
            fg,
            resolution,
            UpsamplePass {
                name: self.label("upsample"),
                owner: self.owner,
                gbuffer: &self.gbuffer,
                half: &trace_target,
                full: self.full_target(),
                desc: hdr,
                format: UpsampleFormat::Rgba16,
                counter: HALF_RESOLUTION,
                label: "ssr upsample",
                detail: None,
            },
        );
        if self.settings.temporal && !self.fused() {
            let mut pass = fg.pass(self.label("resolve"), self.owner);
            let (current, depth) = (pass.read(&self.current), pass.read(&g.depth));
            let (output, history) = histories(&mut pass);
            let io = ResolveIo {
                current,
                depth,
                output,
                history,
            };
            pass.run(move |cx| self.resolve(cx, &io));
        }
    }
}

/// The layout the shader sees (shaders/layout.rs).
#[cfg(test)]
mod wgsl_layout {
    use super::*;

    #[test]
    fn params_matches_params_in_the_shader() {
        crate::assert_wgsl_layout!(
            Params,
            crate::environment::ssr::key::SsrKey,
            [],
            "Params",
            [
                max_steps, rays, frame, flags, near, thickness, blend, max_level
            ]
        );
    }
}
