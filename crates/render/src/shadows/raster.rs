//! Drawing shadow-map layers: a set of casters through the compute
//! rasterizer or the raster hardware, then its depth into the map shading
//! samples (or into the still casters' cache, or over it), and VSM's moments.

use std::sync::{Arc, Mutex};

use crate::error::RenderError;
use crate::frame_graph::{Bindings, FrameGraph, PassContext};
use crate::gbuffer::compute_raster::{ComputeRaster, RasterLabels, RasterView, Words};
use crate::gbuffer::{Draw, Layer, pack_instances};
use crate::mesh_arena::pulled_pipeline;
use crate::renderer::Renderer;
use crate::shaders::{Permutation, ShaderKey};

use glam::{Mat4, Vec4};
use smallvec::{SmallVec, smallvec};

use super::scroll::Rect;
use super::store::{DEPTH_FORMAT, StoredMaps};
use super::{Sets, ShadowFilter, ShadowMaps, VIEW_STRIDE, layer_view};

pub use super::raster_key::{MomentsKey, ShadowDepthKey, ShadowResolveKey};

/// Casters drawn together: their instances, their draws and, where the
/// compute rasterizer draws the maps, its batches over them.
pub(super) struct CasterSet {
    pub casters: Vec<Arc<Layer>>,
    pub(super) instances: wgpu::Buffer,
    draws: Vec<Draw>,
    pub(super) compute: Option<ComputeRaster>,
}

/// Which of a node's caster sets: each keeps its buffers under its own names.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum SetKind {
    /// Every caster: what a slice is drawn from when nothing is cached.
    All,
    /// The casters unchanged since the node's last recipe.
    Still,
    /// The casters new or changed since then.
    Moving,
}

impl SetKind {
    fn instances_label(self) -> &'static str {
        match self {
            SetKind::All => "shadow casters",
            SetKind::Still => "shadow casters (still)",
            SetKind::Moving => "shadow casters (moving)",
        }
    }

    fn raster_labels(self) -> RasterLabels {
        match self {
            SetKind::All => RasterLabels {
                run: "shadow raster run",
                first_triangle: "shadow first triangle",
            },
            SetKind::Still => RasterLabels {
                run: "shadow raster run (still)",
                first_triangle: "shadow first triangle (still)",
            },
            SetKind::Moving => RasterLabels {
                run: "shadow raster run (moving)",
                first_triangle: "shadow first triangle (moving)",
            },
        }
    }
}

impl CasterSet {
    /// The compute rasterizer draws this set (the raster hardware otherwise).
    pub fn compute_raster(&self) -> bool {
        self.compute.is_some()
    }

    /// `compute`: the compute rasterizer draws the maps.
    pub fn new(
        renderer: &Renderer,
        owner: Option<u32>,
        kind: SetKind,
        casters: Vec<Arc<Layer>>,
        compute: bool,
    ) -> CasterSet {
        let (gpu_instances, draws, _) = pack_instances(&casters);
        let instance_count = gpu_instances.len();
        let instances = renderer.kept_storage(owner, kind.instances_label(), &gpu_instances);
        let compute = compute.then(|| {
            ComputeRaster::new(
                renderer,
                owner,
                kind.raster_labels(),
                Words::Depth32,
                &draws,
                instance_count,
            )
        });
        CasterSet {
            casters,
            instances,
            draws,
            compute,
        }
    }
}

/// The still casters' set as last packed, kept by the renderer under the
/// node: a thousand still instances are not packed and compared again every
/// frame something else moves.
#[derive(Default)]
pub(super) struct StillSets(Mutex<Option<Arc<CasterSet>>>);

impl StillSets {
    /// The set of `still` casters: the kept one while they are the same
    /// layers (and drawn by the same rasterizer), else one `make` packs.
    pub fn get(
        &self,
        still: Vec<Arc<Layer>>,
        compute: bool,
        make: impl FnOnce(Vec<Arc<Layer>>) -> CasterSet,
    ) -> Arc<CasterSet> {
        let mut kept = self.0.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(set) = kept.as_ref()
            && set.compute_raster() == compute
            && set.casters.len() == still.len()
            && set
                .casters
                .iter()
                .zip(&still)
                .all(|(a, b)| Arc::ptr_eq(a, b))
        {
            return set.clone();
        }
        let set = Arc::new(make(still));
        *kept = Some(set.clone());
        set
    }
}

/// A part of a layer the compute rasterizer draws: its camera, its region
/// uniform and its size in texels.
type CameraPart<'b> = (&'b wgpu::Buffer, &'b wgpu::Buffer, (u32, u32));

/// Where a layer's depth goes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Target {
    /// The map shading samples.
    Map,
    /// The still casters' cache.
    Still,
    /// The map: the nearer of what is drawn and the still casters' cache.
    MapOverStill,
}

/// One layer to draw from one set of casters.
pub(super) struct Job<'s> {
    pub set: &'s CasterSet,
    pub layer: u32,
    pub target: Target,
    /// Empty: the whole layer. Else only these parts of it (the strips a
    /// scrolled cascade uncovered), each rasterized clipped to itself.
    pub strips: Vec<Strip>,
}

/// A part of a layer a job draws alone: its texels, the region uniform its
/// resolve reads (`Info` in resolve.wgsl) and, where the compute rasterizer
/// draws, its camera: the layer's view narrowed to the strip, so the
/// rasterizer covers the strip's texels and no others.
pub(super) struct Strip {
    pub rect: Rect,
    pub info: wgpu::Buffer,
    pub camera: Option<wgpu::Buffer>,
    /// What `camera` holds, for a layered raster's array of cameras.
    pub gpu_camera: Option<crate::camera::GpuCamera>,
}

/// `view_projection` narrowed to `rect` of a map of `resolution` texels a
/// side: the rectangle's NDC span stretched over -1..1, so a target of the
/// rectangle's size sees exactly its texels, centre for centre.
pub(super) fn strip_projection(view_projection: Mat4, rect: Rect, resolution: u32) -> Mat4 {
    let (r, w, h) = (
        resolution as f32,
        rect.w.max(1) as f32,
        rect.h.max(1) as f32,
    );
    let cx = -1.0 + (2.0 * rect.x as f32 + w) / r;
    let cy = 1.0 - (2.0 * rect.y as f32 + h) / r;
    let narrow = Mat4::from_cols(
        Vec4::new(r / w, 0.0, 0.0, 0.0),
        Vec4::new(0.0, r / h, 0.0, 0.0),
        Vec4::Z,
        Vec4::new(-cx * r / w, -cy * r / h, 0.0, 1.0),
    );
    narrow * view_projection
}

/// The raster hardware's depth pipeline's variant name
/// (`ShaderCache::render_pipeline`).
const DEPTH_VARIANT: &str = "depth32f";

/// The raster hardware's depth pipeline, as the pass builds it and a
/// thread does where the maps' recipe announced it.
fn depth_pipeline(
    device: &wgpu::Device,
    module: &wgpu::ShaderModule,
    cache: Option<&wgpu::PipelineCache>,
) -> wgpu::RenderPipeline {
    // Both faces: open meshes (a plane) must cast too.
    pulled_pipeline(
        device,
        module,
        cache,
        "shadow depth",
        wgpu::PrimitiveState::default(),
        Some(wgpu::DepthStencilState {
            format: DEPTH_FORMAT,
            depth_write_enabled: Some(true),
            depth_compare: Some(wgpu::CompareFunction::Less),
            stencil: Default::default(),
            // Slope-scaled bias against acne on surfaces at grazing angles.
            bias: wgpu::DepthBiasState {
                constant: 0,
                slope_scale: 1.5,
                clamp: 0.0,
            },
        }),
        &[],
    )
}

impl ShadowMaps {
    /// Announce the pipelines drawing the maps will use
    /// (frame_graph/gather.rs), as the render and moments passes look them
    /// up: the compute rasterizer's (each caster set's, back faces kept) or
    /// the raster hardware's depth pipeline, the depth's resolve into the
    /// maps (over the still casters' cache where some casters are still),
    /// and VSM's moments.
    pub(super) fn announce(&self, renderer: &Renderer, fg: &mut FrameGraph<'_>) {
        if !fg.gathers_pipelines() {
            return;
        }
        let (sets, split): (SmallVec<[&CasterSet; 2]>, bool) = match &self.sets {
            Sets::One(set) => (smallvec![set], false),
            Sets::Split { still, moving } => (smallvec![&**still, moving], true),
        };
        let hardware = !self.compute_raster();
        for set in &sets {
            if let Some(raster) = &set.compute {
                raster.announce(renderer, fg, true, self.together);
            }
        }
        if hardware {
            fg.will_render(
                &ShadowDepthKey.key(),
                DEPTH_VARIANT,
                std::sync::Arc::new(depth_pipeline),
            );
        }
        let entry = if hardware {
            "from_depth"
        } else if self.together {
            "from_visibility_layers"
        } else {
            "from_visibility"
        };
        fg.will_dispatch(&Self::resolve_key(Target::Map), entry);
        if split {
            fg.will_dispatch(&Self::resolve_key(Target::MapOverStill), entry);
        }
        if matches!(self.settings.filter, ShadowFilter::Vsm { .. }) {
            fg.will_dispatch(&MomentsKey.key(), "main");
        }
    }

    pub(super) fn resolve_key(target: Target) -> ShaderKey {
        ShadowResolveKey {
            over_still: target == Target::MapOverStill,
        }
        .key()
    }

    /// The texture a job writes and, over the still cache, the one it reads.
    pub(super) fn outputs(
        maps: &mut StoredMaps,
        device: &wgpu::Device,
        target: Target,
    ) -> (wgpu::Texture, Option<wgpu::Texture>) {
        match target {
            Target::Map => (maps.depth.clone(), None),
            Target::Still => (maps.still(device), None),
            Target::MapOverStill => (maps.depth.clone(), Some(maps.still(device))),
        }
    }

    /// Each job's layer through the compute rasterizer, then its depth into its target.
    pub(super) fn raster_compute(
        &self,
        cx: &mut PassContext<'_>,
        renderer: &Renderer,
        maps: &mut StoredMaps,
        cameras: &[wgpu::Buffer],
        jobs: &[Job<'_>],
    ) -> Result<(), RenderError> {
        let device = cx.gpu.device.clone();
        let res = self.settings.resolution;
        for job in jobs {
            let Some(raster) = &job.set.compute else {
                continue;
            };
            // The whole layer through its own camera, or each strip through its narrowed one.
            // Inline: a layer or its two strips (an allocation a job a frame otherwise).
            let parts: SmallVec<[CameraPart<'_>; 2]> = if job.strips.is_empty() {
                smallvec![(
                    &cameras[job.layer as usize],
                    &self.layer_info[job.layer as usize],
                    (res, res),
                )]
            } else {
                job.strips
                    .iter()
                    .filter_map(|s| Some((s.camera.as_ref()?, &s.info, (s.rect.w, s.rect.h))))
                    .collect()
            };
            for (camera, info, size) in parts {
                let view = RasterView {
                    camera,
                    instances: &job.set.instances,
                    size,
                    two_sided: true,
                };
                let visibility = raster.record_view(&view, renderer, cx, None)?;
                let (out, under) = Self::outputs(maps, &device, job.target);
                let mut b = Bindings::new()
                    .buffer("visibility", &visibility)
                    .buffer("camera", camera)
                    .buffer("info", info)
                    .view("out_depth", layer_view(cx, &out, job.layer));
                if let Some(under) = under {
                    b = b.view("still", layer_view(cx, &under, job.layer));
                }
                cx.dispatch_shader(
                    "shadow depth from visibility",
                    &Self::resolve_key(job.target),
                    "from_visibility",
                    b,
                    (size.0.div_ceil(8), size.1.div_ceil(8), 1),
                )?;
            }
        }
        Ok(())
    }

    /// The jobs through the raster hardware into depth attachments, then
    /// into their targets. A job drawing the still cache must come first:
    /// a layer's attachment is drawn again by its moving casters after.
    pub(super) fn raster_hardware(
        &self,
        cx: &mut PassContext<'_>,
        renderer: &Renderer,
        maps: &mut StoredMaps,
        jobs: &[Job<'_>],
    ) -> Result<(), RenderError> {
        let (still, rest): (Vec<&Job<'_>>, Vec<&Job<'_>>) =
            jobs.iter().partition(|j| j.target == Target::Still);
        for phase in [still, rest] {
            if !phase.is_empty() {
                self.raster_hardware_phase(cx, renderer, maps, &phase)?;
            }
        }
        Ok(())
    }

    fn raster_hardware_phase(
        &self,
        cx: &mut PassContext<'_>,
        renderer: &Renderer,
        maps: &mut StoredMaps,
        jobs: &[&Job<'_>],
    ) -> Result<(), RenderError> {
        let device = cx.gpu.device.clone();
        let Some(attachments) = maps.attachments.clone() else {
            return Err(RenderError::Pass {
                pass: "shadow depth".to_owned(),
                message: "no depth attachments for the raster hardware".to_owned(),
            });
        };
        let key = ShadowDepthKey.key();
        let pipeline =
            cx.shaders
                .render_pipeline(&device, &key, DEPTH_VARIANT, |module, cache| {
                    depth_pipeline(&device, module, cache)
                })?;
        let (vertices, indices, _) = renderer.meshes.buffers();
        let mut work = Vec::new();
        for job in jobs {
            let b = Bindings::new()
                .buffer_range(
                    "view_projection",
                    &self.view_uniforms,
                    u64::from(job.layer) * VIEW_STRIDE,
                    64,
                )
                .buffer("vertices", &vertices)
                .buffer("indices", &indices)
                .buffer("instances", &job.set.instances);
            let groups = cx.render_bind_groups(&key, &["vs"], &pipeline, b)?;
            work.push((
                groups,
                layer_view(cx, &attachments, job.layer),
                &job.set.draws,
                &job.strips,
            ));
        }
        let mut draws = 0;
        // Time the whole set as one: the first pass writes the beginning, the last the end.
        let pair = cx.render_timestamps();
        let last = work.len().saturating_sub(1);
        for (index, (groups, view, set_draws, strips)) in work.iter().enumerate() {
            let timestamps = pair.as_ref().and_then(|p| {
                let begin = (index == 0)
                    .then_some(p.beginning_of_pass_write_index)
                    .flatten();
                let end = (index == last)
                    .then_some(p.end_of_pass_write_index)
                    .flatten();
                (begin.is_some() || end.is_some()).then_some(wgpu::RenderPassTimestampWrites {
                    query_set: p.query_set,
                    beginning_of_pass_write_index: begin,
                    end_of_pass_write_index: end,
                })
            });
            let mut pass = cx.encoder().begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("shadow depth"),
                color_attachments: &[],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(1.0),
                        store: wgpu::StoreOp::Store,
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes: timestamps,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_pipeline(&pipeline);
            for (i, group) in groups.iter().enumerate() {
                pass.set_bind_group(i as u32, group, &[]);
            }
            // A whole layer once, or each strip clipped to itself (the
            // attachment is cleared whole; only the strips are resolved).
            let scissors: SmallVec<[Option<Rect>; 2]> = if strips.is_empty() {
                smallvec![None]
            } else {
                strips.iter().map(|s| Some(s.rect)).collect()
            };
            for scissor in scissors {
                if let Some(r) = scissor {
                    pass.set_scissor_rect(r.x, r.y, r.w, r.h);
                }
                for draw in set_draws
                    .iter()
                    .filter(|d| d.instance_count > 0 && d.index_count > 0)
                {
                    pass.draw(
                        0..draw.index_count,
                        draw.first_instance..draw.first_instance + draw.instance_count,
                    );
                    draws += 1;
                }
            }
        }
        cx.draws += draws;
        // Into the targets, a dispatch per layer.
        let res = self.settings.resolution;
        // A view the pool keeps: a view made here each frame would make the
        // copy's bind group anew each frame too.
        let depth = cx.view_of(
            &attachments,
            crate::texture_pool::ViewSpec {
                aspect: wgpu::TextureAspect::DepthOnly,
                ..crate::texture_pool::ViewSpec::array()
            },
        );
        for job in jobs {
            let parts: SmallVec<[(&wgpu::Buffer, (u32, u32)); 2]> = if job.strips.is_empty() {
                smallvec![(&self.layer_info[job.layer as usize], (res, res))]
            } else {
                job.strips
                    .iter()
                    .map(|s| (&s.info, (s.rect.w, s.rect.h)))
                    .collect()
            };
            for (info, size) in parts {
                let (out, under) = Self::outputs(maps, &device, job.target);
                let mut b = Bindings::new()
                    .view("depth", depth.clone())
                    .view("out_depth", layer_view(cx, &out, job.layer))
                    .buffer("info", info);
                if let Some(under) = under {
                    b = b.view("still", layer_view(cx, &under, job.layer));
                }
                cx.dispatch_shader(
                    "shadow depth copy",
                    &Self::resolve_key(job.target),
                    "from_depth",
                    b,
                    (size.0.div_ceil(8), size.1.div_ceil(8), 1),
                )?;
            }
        }
        Ok(())
    }

    /// VSM's second pass: moments of the layers the render pass just drew.
    pub(super) fn moments_pass(&self, cx: &mut PassContext<'_>) -> Result<(), RenderError> {
        if !matches!(self.settings.filter, ShadowFilter::Vsm { .. }) {
            return Ok(());
        }
        let mut guard = self.store.maps.lock().unwrap_or_else(|e| e.into_inner());
        let Some(maps) = guard.as_mut() else {
            return Ok(());
        };
        let regions = std::mem::take(&mut maps.pending_moments);
        match (&maps.moments, regions.is_empty()) {
            (Some(moments), false) => self.moments(cx, &maps.depth, moments, &regions),
            _ => Ok(()),
        }
    }

    /// VSM: the depth just rendered as blurred moments of linear depth, in
    /// each (layer, region, its `Info` uniform) given.
    fn moments(
        &self,
        cx: &mut PassContext<'_>,
        depth: &wgpu::Texture,
        moments: &wgpu::Texture,
        regions: &[(u32, Rect, wgpu::Buffer)],
    ) -> Result<(), RenderError> {
        let key = MomentsKey.key();
        let pipeline = cx.compute_pipeline(&key, "main")?;
        // The view cache's: a view made here each frame was a new bind group each frame.
        let depth_view = cx.view_of(depth, crate::texture_pool::ViewSpec::array());
        let mut groups = Vec::new();
        for (layer, rect, info) in regions {
            let b = Bindings::new()
                .view("depth", depth_view.clone())
                .buffer("views", &self.views)
                .buffer("info", info)
                .view("moments", layer_view(cx, moments, *layer));
            groups.push((cx.bind_groups(&key, "main", &pipeline, b)?, *rect));
        }
        let pass = cx.compute_pass("shadow moments");
        pass.set_pipeline(&pipeline);
        for (layer_groups, rect) in &groups {
            for (i, group) in layer_groups.iter().enumerate() {
                pass.set_bind_group(i as u32, group, &[]);
            }
            pass.dispatch_workgroups(rect.w.div_ceil(8), rect.h.div_ceil(8), 1);
        }
        Ok(())
    }
}
