//! Which slices a frame draws and how: reused whole, drawn from every
//! caster, or (some casters still, some moving) the still ones cached per
//! slice and only the moving ones drawn over them, or nothing at all where
//! the moving ones miss the slice's views. A sun's cascade whose casters
//! held while its box moved across by whole texels is scrolled (scroll.rs).

use crate::error::RenderError;
use crate::frame_graph::PassContext;
use crate::renderer::Renderer;

use super::raster::{CasterSet, Job, SetKind, Strip, Target, strip_projection};
use super::scroll::{self, Rect};
use super::store::{MapLayout, SliceContent, StoredMaps};
use super::{Sets, ShadowFilter, ShadowMaps, all_views, caster_bounds, views};

impl ShadowMaps {
    /// Render every slice that needs it into the stored maps.
    pub(super) fn render(
        &self,
        cx: &mut PassContext<'_>,
        renderer: &Renderer,
    ) -> Result<(), RenderError> {
        let device = cx.gpu.device.clone();
        let vsm = matches!(self.settings.filter, ShadowFilter::Vsm { .. });
        let layout = MapLayout {
            layers: self.layers,
            per_slice: self.per_slice,
            resolution: self.settings.resolution,
            vsm,
            hardware: !self.compute_raster(),
        };
        let mut guard = self.store.maps.lock().unwrap_or_else(|e| e.into_inner());
        if guard.as_ref().is_none_or(|m| m.layout != layout) {
            *guard = Some(StoredMaps::allocate(&device, layout));
        }
        let Some(maps) = guard.as_mut() else {
            return Ok(());
        };
        // Layers drawn from every caster; layers whose still casters are
        // cached this frame; layers drawn from the moving casters over them.
        let (mut full, mut still, mut over) = (Vec::new(), Vec::new(), Vec::new());
        // Layers scrolled by (right, down) texels: only their new strips are drawn.
        let mut scrolled: Vec<(u32, (i32, i32))> = Vec::new();
        // Where the moving casters are, when the CPU knows: meshes it
        // uploaded, placed by their instances. (GPU-written meshes, skinned
        // or made by geometry nodes or particles, are wherever the GPU put them.)
        let moving_bounds = match &self.sets {
            Sets::Split { moving, .. } => moving
                .casters
                .iter()
                .flat_map(|l| &l.batches)
                .all(|b| !b.mesh.has_previous_positions)
                .then(|| caster_bounds(&moving.casters)),
            Sets::One(_) => None,
        };
        let res = self.settings.resolution;
        // Layers drawn over the still cache only about the moving casters:
        // where they were when the layer was last drawn, and where they are.
        let mut around_moving: Vec<(u32, Rect)> = Vec::new();
        // Layers whose still cache scrolls with the map: the shift, and the
        // texels about the moving casters (None: anywhere, the whole layer).
        let mut scrolled_over: Vec<(u32, (i32, i32), Option<Rect>)> = Vec::new();
        let mut rendered = 0;
        for plan in &self.plans {
            if plan.culled {
                cx.count("shadow maps culled", 1);
                continue;
            }
            let content = SliceContent {
                views: plan
                    .views
                    .iter()
                    .map(|v| v.view_projection.to_cols_array())
                    .collect(),
                casters: self.casters.clone(),
                filter: self.settings.filter,
            };
            let slice = plan.slice as usize;
            let Some(slot) = maps.contents.get(slice) else {
                continue;
            };
            if slot.as_ref().is_some_and(|c| c.same(&content)) {
                cx.count("shadow maps reused", 1);
                continue;
            }
            let first = plan.slice * self.per_slice;
            // Where the moving casters are in each of the slice's layers.
            let moving_now: Vec<Option<Rect>> = plan
                .views
                .iter()
                .map(|v| {
                    let (center, radius) = moving_bounds?;
                    views::sphere_texels(v.view_projection, center, radius, res)
                })
                .collect();
            let remember = |maps: &mut StoredMaps| {
                for (k, now) in moving_now.iter().enumerate() {
                    if let Some(slot) = maps.moving_rects.get_mut((first + k as u32) as usize) {
                        *slot = *now;
                    }
                }
            };
            // The same casters seen through the same filter: each cascade
            // that moved across by whole texels scrolls, one that held is
            // kept, and only the rest are drawn whole.
            if let Some(shifts) = slot.as_ref().and_then(|old| self.scrolls(old, &content)) {
                for (k, shift) in shifts.into_iter().enumerate() {
                    match shift {
                        Some((0, 0)) => {}
                        Some(shift) => scrolled.push((first + k as u32, shift)),
                        None => full.push(first + k as u32),
                    }
                }
                maps.bare[slice] = false;
                maps.contents[slice] = Some(content);
                remember(maps);
                rendered += 1;
                continue;
            }
            // Only moving casters changed, and the views moved across by
            // whole texels: the still cache scrolls with the map, its new
            // strips drawn from the still casters, and the map is drawn over
            // it in those strips and about the moving casters.
            if let Some(shifts) = self.scrolls_over_still(maps, slice, slot.as_ref(), &content) {
                for (k, shift) in shifts.into_iter().enumerate() {
                    let layer = first + k as u32;
                    let before = maps
                        .moving_rects
                        .get(layer as usize)
                        .copied()
                        .flatten()
                        .map(|r| r.shifted(shift, res));
                    let around = before.zip(moving_now[k]).map(|(b, n)| b.union(n));
                    scrolled_over.push((layer, shift, around));
                }
                if let Sets::Split { still: set, .. } = &self.sets {
                    maps.still_contents[slice] = Some(SliceContent {
                        casters: set.casters.clone(),
                        ..content.clone()
                    });
                }
                maps.bare[slice] = false;
                maps.contents[slice] = Some(content);
                remember(maps);
                rendered += 1;
                continue;
            }
            let layers = (0..plan.views.len() as u32).map(|k| first + k);
            match &self.sets {
                Sets::Split { still: set, .. } => {
                    let still_content = SliceContent {
                        casters: set.casters.clone(),
                        ..content.clone()
                    };
                    let cached = maps.still_contents[slice]
                        .as_ref()
                        .is_some_and(|c| c.same(&still_content));
                    // Views that held since the slice was last drawn are
                    // likely to hold on: worth caching the still casters for.
                    // Views that move (a sun's cascades following a moving
                    // camera) would only pay for a second raster.
                    let steady = slot.as_ref().is_some_and(|c| c.same_views(&content));
                    // The moving casters miss every view of the slice: they
                    // draw nothing in it.
                    let elsewhere = moving_bounds.is_some_and(|(center, radius)| {
                        plan.views
                            .iter()
                            .all(|v| !views::sphere_in_frustum(v.view_projection, center, radius))
                    });
                    if cached && elsewhere && maps.bare[slice] {
                        // The map is its still cache, and stays so.
                        cx.count("shadow maps reused, moving casters elsewhere", 1);
                        maps.contents[slice] = Some(content);
                        remember(maps);
                        continue;
                    }
                    maps.bare[slice] = elsewhere;
                    if cached {
                        cx.count("shadow maps drawn over cached still casters", 1);
                        for (k, layer) in layers.enumerate() {
                            // Last drawn over this cache through these views: only
                            // the texels the moving casters left or now reach change.
                            let around = steady
                                .then_some(())
                                .and(maps.moving_rects.get(layer as usize).copied().flatten())
                                .zip(moving_now[k])
                                .map(|(before, now)| before.union(now));
                            match around {
                                Some(rect) if rect.is_empty() => {
                                    cx.count("shadow layers kept, moving casters elsewhere", 1);
                                }
                                Some(rect) if rect.texels() < Rect::full(res).texels() => {
                                    around_moving.push((layer, rect));
                                }
                                _ => over.push(layer),
                            }
                        }
                    } else if steady {
                        cx.count("shadow maps still casters cached", 1);
                        maps.still_contents[slice] = Some(still_content);
                        still.extend(layers.clone());
                        over.extend(layers);
                    } else {
                        maps.bare[slice] = false;
                        full.extend(layers);
                    }
                }
                Sets::One(_) => {
                    maps.bare[slice] = false;
                    full.extend(layers);
                }
            }
            maps.contents[slice] = Some(content);
            remember(maps);
            rendered += 1;
        }
        if rendered == 0 {
            return Ok(());
        }
        cx.count("shadow maps rendered", rendered);
        let blur = match self.settings.filter {
            ShadowFilter::Vsm { blur, .. } => blur.min(8),
            _ => 0,
        };
        // Every caster together, made here only where split sets must draw a whole slice.
        let all_set;
        let mut jobs = Vec::new();
        let mut moments = Vec::new();
        if !full.is_empty() || !scrolled.is_empty() {
            let set = match &self.sets {
                Sets::One(set) => set,
                Sets::Split { .. } => {
                    all_set = CasterSet::new(
                        renderer,
                        self.owner,
                        SetKind::All,
                        self.casters.clone(),
                        self.compute_raster(),
                    );
                    &all_set
                }
            };
            jobs.extend(full.iter().map(|&layer| Job {
                set,
                layer,
                target: Target::Map,
                strips: Vec::new(),
            }));
            // The kept part of each scrolled layer moves into place first
            // (these copies precede the strips' draws in the encoder).
            let (scratch, moments_scratch) = if scrolled.is_empty() {
                (None, None)
            } else {
                let (d, m) = maps.scratch(&device);
                (Some(d), m)
            };
            let mut kept = 0u64;
            for &(layer, shift) in &scrolled {
                let uniform = self.shift_uniform(renderer, layer, shift);
                if let Some(scratch) = &scratch {
                    scroll::shift_layer(cx, &uniform, (&maps.depth, scratch), layer, res, false)?;
                }
                if let (Some(m), Some(scratch)) = (&maps.moments, &moments_scratch) {
                    scroll::shift_layer(cx, &uniform, (m, scratch), layer, res, true)?;
                }
                let rects = scroll::uncovered(res, shift);
                kept += Rect::full(res).texels() - rects.iter().map(Rect::texels).sum::<u64>();
                if vsm {
                    let regions = scroll::moments_regions(res, &rects, blur);
                    moments.extend(self.moments_regions(
                        renderer,
                        "shadow moments region",
                        layer,
                        blur,
                        regions,
                    ));
                }
                let strips = self.strips(renderer, layer, &rects, STRIP_LABELS, blur);
                jobs.push(Job {
                    set,
                    layer,
                    target: Target::Map,
                    strips,
                });
            }
            count(cx, "shadow layers scrolled", scrolled.len() as u64);
            count(cx, "shadow texels kept by scrolling", kept);
        }
        if let Sets::Split { still: s, moving } = &self.sets {
            // Scrolled still caches and maps move into place first.
            if !scrolled_over.is_empty() {
                let (scratch, moments_scratch) = maps.scratch(&device);
                let still_maps = maps.still(&device);
                let mut kept = 0u64;
                for &(layer, shift, _) in &scrolled_over {
                    if shift == (0, 0) {
                        continue;
                    }
                    let uniform = self.shift_uniform(renderer, layer, shift);
                    for texture in [&maps.depth, &still_maps] {
                        scroll::shift_layer(cx, &uniform, (texture, &scratch), layer, res, false)?;
                    }
                    if let (Some(m), Some(scratch)) = (&maps.moments, &moments_scratch) {
                        scroll::shift_layer(cx, &uniform, (m, scratch), layer, res, true)?;
                    }
                    let uncovered: u64 =
                        scroll::uncovered(res, shift).iter().map(Rect::texels).sum();
                    kept += Rect::full(res).texels() - uncovered;
                }
                count(
                    cx,
                    "shadow layers scrolled over still casters",
                    scrolled_over.len() as u64,
                );
                count(cx, "shadow texels kept by scrolling", kept);
            }
            // The still caches first: the layers drawn over them read them.
            jobs.extend(still.iter().map(|&layer| Job {
                set: s,
                layer,
                target: Target::Still,
                strips: Vec::new(),
            }));
            for &(layer, shift, _) in &scrolled_over {
                let rects = scroll::uncovered(res, shift);
                if rects.is_empty() {
                    continue;
                }
                let strips = self.strips(renderer, layer, &rects, STILL_STRIP_LABELS, blur);
                jobs.push(Job {
                    set: s,
                    layer,
                    target: Target::Still,
                    strips,
                });
            }
            jobs.extend(over.iter().map(|&layer| Job {
                set: moving,
                layer,
                target: Target::MapOverStill,
                strips: Vec::new(),
            }));
            for &(layer, rect) in &around_moving {
                jobs.push(Job {
                    set: moving,
                    layer,
                    target: Target::MapOverStill,
                    strips: self.strips(renderer, layer, &[rect], AROUND_LABELS, blur),
                });
                if vsm {
                    moments.extend(self.moments_regions(
                        renderer,
                        "shadow moments around moving casters",
                        layer,
                        blur,
                        vec![rect.grown(blur, res)],
                    ));
                }
            }
            count(
                cx,
                "shadow layers drawn about moving casters",
                around_moving.len() as u64,
            );
            for &(layer, shift, around) in &scrolled_over {
                let uncovered = scroll::uncovered(res, shift);
                // The new strips and the texels about the moving casters, or
                // the whole layer where those are not known.
                let rects: Vec<Rect> = match around {
                    Some(around) => uncovered
                        .iter()
                        .copied()
                        .chain(Some(around).filter(|r| !r.is_empty()))
                        .collect(),
                    None => Vec::new(),
                };
                let whole = around.is_none();
                if !whole && rects.is_empty() {
                    continue;
                }
                let strips = self.strips(renderer, layer, &rects, OVER_STRIP_LABELS, blur);
                jobs.push(Job {
                    set: moving,
                    layer,
                    target: Target::MapOverStill,
                    strips,
                });
                if vsm {
                    let regions = if whole {
                        vec![Rect::full(res)]
                    } else {
                        let mut regions = if uncovered.is_empty() {
                            Vec::new()
                        } else {
                            scroll::moments_regions(res, &uncovered, blur)
                        };
                        regions.extend(around.map(|r| r.grown(blur, res)));
                        regions
                    };
                    moments.extend(self.moments_regions(
                        renderer,
                        "shadow moments scrolled over still casters",
                        layer,
                        blur,
                        regions,
                    ));
                }
            }
        }
        // What was rasterized, against what drawing every job's layer whole would have.
        let whole = jobs.iter().filter(|j| j.strips.is_empty()).count() as u64;
        let drawn: u64 = jobs
            .iter()
            .map(|j| {
                if j.strips.is_empty() {
                    Rect::full(res).texels()
                } else {
                    j.strips.iter().map(|s| s.rect.texels()).sum()
                }
            })
            .sum();
        count(cx, "shadow layers drawn whole", whole);
        count(cx, "shadow texels drawn", drawn);
        match &self.cameras {
            _ if self.together => self.raster_together(cx, renderer, maps, &jobs)?,
            Some(cameras) => self.raster_compute(cx, renderer, maps, cameras, &jobs)?,
            None => self.raster_hardware(cx, renderer, maps, &jobs)?,
        }
        if vsm {
            for layer in full.into_iter().chain(over) {
                moments.push((
                    layer,
                    Rect::full(res),
                    self.layer_info[layer as usize].clone(),
                ));
            }
            maps.pending_moments = moments;
        }
        Ok(())
    }

    /// The uniform shifting `layer` by `shift` (scroll::shift_layer), kept
    /// under the node at the layer's index.
    fn shift_uniform(&self, renderer: &Renderer, layer: u32, shift: (i32, i32)) -> wgpu::Buffer {
        renderer.kept_init_at(
            self.owner,
            "shadow scroll",
            layer,
            bytemuck::cast_slice(&scroll::shift_uniform(shift, self.settings.resolution)),
            wgpu::BufferUsages::UNIFORM,
        )
    }

    /// VSM's `regions` of `layer` to filter again, each with its region
    /// uniform kept under the node by `label` at the layer's own indices
    /// (at most eight a layer: a scroll's strips and the map's borders).
    fn moments_regions(
        &self,
        renderer: &Renderer,
        label: &'static str,
        layer: u32,
        blur: u32,
        regions: Vec<Rect>,
    ) -> Vec<(u32, Rect, wgpu::Buffer)> {
        regions
            .into_iter()
            .enumerate()
            .map(|(k, region)| {
                let info = renderer.kept_init_at(
                    self.owner,
                    label,
                    layer * 8 + k as u32,
                    bytemuck::cast_slice(&region_info(layer, blur, region)),
                    wgpu::BufferUsages::UNIFORM,
                );
                (layer, region, info)
            })
            .collect()
    }

    /// [`Self::strip`] for each of `rects` of `layer`, kept at the layer's
    /// own indices (at most [`STRIPS_PER_LAYER`] a layer).
    fn strips(
        &self,
        renderer: &Renderer,
        layer: u32,
        rects: &[Rect],
        labels: [&'static str; 2],
        blur: u32,
    ) -> Vec<Strip> {
        rects
            .iter()
            .enumerate()
            .map(|(k, &rect)| {
                self.strip(
                    renderer,
                    layer,
                    rect,
                    layer * STRIPS_PER_LAYER + k as u32,
                    labels,
                    blur,
                )
            })
            .collect()
    }

    /// A part of `layer` drawn alone at `rect`: its region uniform and, for
    /// the compute rasterizer, its camera narrowed to it, kept under the
    /// node by `labels` (camera, region) at `index`.
    fn strip(
        &self,
        renderer: &Renderer,
        layer: u32,
        rect: Rect,
        index: u32,
        labels: [&'static str; 2],
        blur: u32,
    ) -> Strip {
        let res = self.settings.resolution;
        let gpu_camera = self.compute_raster().then(|| {
            crate::camera::CameraInput {
                view: glam::Mat4::IDENTITY,
                projection: strip_projection(
                    all_views(&self.plans, self.per_slice, layer),
                    rect,
                    res,
                ),
            }
            .to_gpu(None, (rect.w, rect.h))
        });
        // Rasterized together, the strip's camera joins the layers' array
        // instead (raster_layered.rs).
        let camera = gpu_camera.filter(|_| !self.together).map(|camera| {
            renderer.kept_init_at(
                self.owner,
                labels[0],
                index,
                bytemuck::bytes_of(&camera),
                wgpu::BufferUsages::UNIFORM,
            )
        });
        let info = renderer.kept_init_at(
            self.owner,
            labels[1],
            index,
            bytemuck::cast_slice(&region_info(layer, blur, rect)),
            wgpu::BufferUsages::UNIFORM,
        );
        Strip {
            rect,
            info,
            camera,
            gpu_camera,
        }
    }

    /// Per cascade of a slice whose last map was `old`, drawn over its still
    /// cache through the same views, now to show `new` from the same still
    /// casters: the whole-texel shift of each cascade, where every cascade
    /// moved across by whole texels and some moved. None otherwise: not a
    /// sun, other still casters, another filter or cascade count, a view
    /// that turned, or nothing moved (the cache serves as it is).
    fn scrolls_over_still(
        &self,
        maps: &StoredMaps,
        slice: usize,
        old: Option<&SliceContent>,
        new: &SliceContent,
    ) -> Option<Vec<(i32, i32)>> {
        let Sets::Split { still, .. } = &self.sets else {
            return None;
        };
        let old = old?;
        let cache = maps.still_contents.get(slice)?.as_ref()?;
        if self.kind != crate::light_kind::LightKind::Sun
            || !same_layers(&cache.casters, &still.casters)
            || !cache.same_views(old)
            || old.filter != new.filter
            || old.views.len() != new.views.len()
            || old.views == new.views
        {
            return None;
        }
        self.shifts(old, new).collect()
    }

    /// Per cascade, how far it moved from `old` to `new` in whole texels
    /// ((0, 0): it held), None where it did not move by a shift.
    fn shifts<'c>(
        &self,
        old: &'c SliceContent,
        new: &'c SliceContent,
    ) -> impl Iterator<Item = Option<(i32, i32)>> + 'c {
        let resolution = self.settings.resolution;
        old.views.iter().zip(&new.views).map(move |(a, b)| {
            if a == b {
                Some((0, 0))
            } else {
                views::texel_shift(a, b, resolution)
            }
        })
    }

    /// Per cascade of a slice whose last map was `old`, now to show `new`:
    /// Some(shift) where it moved across by whole texels (or held: (0, 0)),
    /// None where it must be drawn whole. None for the slice where it cannot
    /// scroll at all: not a sun, other casters, another filter or cascade count.
    fn scrolls(&self, old: &SliceContent, new: &SliceContent) -> Option<Vec<Option<(i32, i32)>>> {
        let scrollable = self.kind == crate::light_kind::LightKind::Sun
            && same_layers(&old.casters, &new.casters)
            && old.filter == new.filter
            && old.views.len() == new.views.len();
        scrollable.then(|| self.shifts(old, new).collect())
    }
}

/// The same layers, by identity, in the same order.
fn same_layers(
    a: &[std::sync::Arc<crate::gbuffer::Layer>],
    b: &[std::sync::Arc<crate::gbuffer::Layer>],
) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(a, b)| std::sync::Arc::ptr_eq(a, b))
}

/// The most strips a layer is drawn in: a scroll's two, and the texels
/// about the moving casters.
const STRIPS_PER_LAYER: u32 = 3;

/// The kept buffers of a scrolled layer's strips: camera, region.
const STRIP_LABELS: [&str; 2] = ["shadow strip camera", "shadow strip"];
/// The kept buffers of a scrolled still cache's strips: camera, region.
const STILL_STRIP_LABELS: [&str; 2] = ["shadow still strip camera", "shadow still strip"];
/// The kept buffers of a map drawn over its scrolled still cache: camera, region.
const OVER_STRIP_LABELS: [&str; 2] = ["shadow over strip camera", "shadow over strip"];
/// The kept buffers of a layer drawn about its moving casters: camera, region.
const AROUND_LABELS: [&str; 2] = ["shadow moving strip camera", "shadow moving strip"];

/// Counted where it happened (a counter of 0 is left out of the report).
fn count(cx: &mut PassContext<'_>, name: &'static str, n: u64) {
    if n > 0 {
        cx.count(name, n);
    }
}

/// The `Info` uniform of the resolve and moments shaders for `rect` of `layer`.
fn region_info(layer: u32, blur: u32, rect: Rect) -> [u32; 8] {
    let [x, y, w, h] = rect.to_gpu();
    [layer, blur, 0, 0, x, y, w, h]
}
