//! Which slices a frame draws and how: reused whole, drawn from every
//! caster, or (some casters still, some moving) the still ones cached per
//! slice and only the moving ones drawn over them, or nothing at all where
//! the moving ones miss the slice's views.

use crate::error::RenderError;
use crate::frame_graph::PassContext;
use crate::renderer::Renderer;

use super::raster::{CasterSet, Job, SetKind, Target};
use super::store::{MapLayout, SliceContent, StoredMaps};
use super::{Sets, ShadowFilter, ShadowMaps, caster_bounds, views};

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
            hardware: self.cameras.is_none(),
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
            let layers = (0..plan.views.len() as u32).map(|k| plan.slice * self.per_slice + k);
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
                        continue;
                    }
                    maps.bare[slice] = elsewhere;
                    if cached {
                        cx.count("shadow maps drawn over cached still casters", 1);
                        over.extend(layers);
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
            rendered += 1;
        }
        if rendered == 0 {
            return Ok(());
        }
        cx.count("shadow maps rendered", rendered);
        // Every caster together, made here only where split sets must draw a whole slice.
        let all_set;
        let mut jobs = Vec::new();
        if !full.is_empty() {
            let set = match &self.sets {
                Sets::One(set) => set,
                Sets::Split { .. } => {
                    all_set = CasterSet::new(
                        renderer,
                        self.owner,
                        SetKind::All,
                        self.casters.clone(),
                        self.cameras.is_some(),
                    );
                    &all_set
                }
            };
            jobs.extend(full.iter().map(|&layer| Job {
                set,
                layer,
                target: Target::Map,
            }));
        }
        if let Sets::Split { still: s, moving } = &self.sets {
            // The still caches first: the layers drawn over them read them.
            jobs.extend(still.iter().map(|&layer| Job {
                set: s,
                layer,
                target: Target::Still,
            }));
            jobs.extend(over.iter().map(|&layer| Job {
                set: moving,
                layer,
                target: Target::MapOverStill,
            }));
        }
        match &self.cameras {
            Some(cameras) => self.raster_compute(cx, renderer, maps, cameras, &jobs)?,
            None => self.raster_hardware(cx, renderer, maps, &jobs)?,
        }
        if vsm {
            maps.pending_moments = full.into_iter().chain(over).collect();
        }
        Ok(())
    }
}
