//! Shadow-map layers rasterized together ([`ShadowLayers::Together`]): every
//! layer (and scrolled strip) a frame draws from one caster set into one
//! target goes through one compute raster chain, the layer a dispatch
//! dimension (`ComputeRaster::record_layers`), then one resolve dispatch
//! writes every layer of the map. VSM's moments stay a dispatch per region
//! (`ShadowMaps::moments`): one dispatch for every region measured 0.185
//! ms on the H200 for emeshe-heavy's sun against 0.130 for four (its
//! region and blur came from a storage table, where each of the four reads
//! them from a uniform). Per layer, the sun's four cascades were four chains of a
//! buffer clear, a tile reset, the batches' dispatches, the tiles' and a
//! resolve each: 0.130 ms of CPU to record on the H200 for emeshe-heavy's
//! sun (docs/benchmarks.md, "Session 22: shadow layers together").
//!
//! [`ShadowLayers::Together`]: super::layers::ShadowLayers::Together

use crate::camera::GpuCamera;
use crate::error::RenderError;
use crate::frame_graph::{Bindings, PassContext};
use crate::gbuffer::compute_raster::LayeredView;
use crate::renderer::Renderer;
use crate::texture_pool::ViewSpec;

use super::ShadowMaps;
use super::layers::{LAYER_CHAINS, LAYERS_TOGETHER};
use super::raster::Job;
use super::scroll::Rect;
use super::store::StoredMaps;

/// Matches `Part` in shaders/shadows/resolve.wgsl: a rectangle of a layer
/// and the run of 8x8 workgroups that covers it.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq, bytemuck::Pod, bytemuck::Zeroable)]
struct GpuPart {
    layer: u32,
    /// Where the part's words start.
    words: u32,
    first_group: u32,
    groups_across: u32,
    region: [u32; 4],
}

/// A part of a layer one chain draws: its layer, its texels and the camera
/// the rasterizer sees them through (the layer's, or a strip's narrowed one).
#[derive(Clone, Copy)]
struct Part {
    layer: u32,
    rect: Rect,
    camera: GpuCamera,
}

/// The parts' table and the workgroups covering them all: each part's
/// workgroups follow the last's, `rect`'s size in 8x8 workgroups; `words`
/// is where each part's words start.
fn parts_table(parts: impl Iterator<Item = (u32, Rect, u32)>) -> (Vec<GpuPart>, u32) {
    let mut groups = 0u32;
    let table = parts
        .map(|(layer, rect, words)| {
            let across = rect.w.div_ceil(8);
            let part = GpuPart {
                layer,
                words,
                first_group: groups,
                groups_across: across,
                region: rect.to_gpu(),
            };
            groups += across * rect.h.div_ceil(8);
            part
        })
        .collect();
    (table, groups)
}

/// `groups` workgroups in x, spilling into y past 65,535 (the shaders fold
/// y back into one index).
fn spread(groups: u32) -> (u32, u32, u32) {
    let x = groups.clamp(1, 65_535);
    (x, groups.div_ceil(x).max(1), 1)
}

/// `parts` in runs whose words fit `max_words` (one storage binding); a
/// part larger than that alone (it could not be drawn layer by layer either).
fn chunks(parts: &[Part], max_words: u64) -> Vec<&[Part]> {
    let mut out = Vec::new();
    let (mut start, mut words) = (0, 0u64);
    for (i, p) in parts.iter().enumerate() {
        let w = p.rect.texels();
        if i > start && words + w > max_words {
            out.push(&parts[start..i]);
            (start, words) = (i, 0);
        }
        words += w;
    }
    if start < parts.len() {
        out.push(&parts[start..]);
    }
    out
}

impl ShadowMaps {
    /// The jobs through the compute rasterizer, every run of jobs drawing
    /// from one set into one target together (in the jobs' order, so the
    /// still casters' cache is drawn before the layers drawn over it).
    pub(super) fn raster_together(
        &self,
        cx: &mut PassContext<'_>,
        renderer: &Renderer,
        maps: &mut StoredMaps,
        jobs: &[Job<'_>],
    ) -> Result<(), RenderError> {
        let res = self.settings.resolution;
        let max_words = cx.gpu.device.limits().max_storage_buffer_binding_size / 4;
        let mut chain = 0u32;
        let mut start = 0;
        while start < jobs.len() {
            let first = &jobs[start];
            let run = jobs[start..]
                .iter()
                .take_while(|j| std::ptr::eq(j.set, first.set) && j.target == first.target)
                .count();
            let run = &jobs[start..start + run];
            start += run.len();
            let mut parts = Vec::new();
            for job in run {
                if job.strips.is_empty() {
                    parts.push(Part {
                        layer: job.layer,
                        rect: Rect::full(res),
                        camera: self.layer_cameras[job.layer as usize],
                    });
                } else {
                    parts.extend(job.strips.iter().filter_map(|s| {
                        Some(Part {
                            layer: job.layer,
                            rect: s.rect,
                            camera: s.gpu_camera?,
                        })
                    }));
                }
            }
            for chunk in chunks(&parts, max_words) {
                self.raster_chain(cx, renderer, maps, first, chunk, chain)?;
                chain += 1;
            }
        }
        Ok(())
    }

    /// One chain: `parts` of layers drawn from `job`'s set into its target,
    /// its kept buffers the `chain`th of the frame's.
    fn raster_chain(
        &self,
        cx: &mut PassContext<'_>,
        renderer: &Renderer,
        maps: &mut StoredMaps,
        job: &Job<'_>,
        parts: &[Part],
        chain: u32,
    ) -> Result<(), RenderError> {
        let Some(raster) = job.set.compute.as_ref() else {
            return Ok(());
        };
        let device = cx.gpu.device.clone();
        // Each part's words follow the last's (a part's are as wide as its camera's target).
        let mut words = 0u64;
        let mut layer_words = Vec::with_capacity(parts.len());
        for p in parts {
            layer_words.push(words as u32);
            words += p.rect.texels();
        }
        let (table, groups) = parts_table(
            parts
                .iter()
                .zip(&layer_words)
                .map(|(p, &w)| (p.layer, p.rect, w)),
        );
        let cameras: Vec<GpuCamera> = parts.iter().map(|p| p.camera).collect();
        // The chain's buffers, kept under the node by chain index.
        let kept = |name: &'static str, bytes: &[u8]| {
            renderer.kept_init_at(self.owner, name, chain, bytes, wgpu::BufferUsages::STORAGE)
        };
        let cameras = kept("shadow layered cameras", bytemuck::cast_slice(&cameras));
        let layer_words = kept("shadow layered words", bytemuck::cast_slice(&layer_words));
        let table = kept("shadow layered parts", bytemuck::cast_slice(&table));
        let view = LayeredView {
            cameras: &cameras,
            layer_words: &layer_words,
            layers: parts.len() as u32,
            words,
            instances: &job.set.instances,
        };
        let visibility = raster.record_layers(&view, renderer, cx)?;
        let (out, under) = Self::outputs(maps, &device, job.target);
        let mut b = Bindings::new()
            .buffer("visibility", &visibility)
            .buffer("parts", &table)
            .view("out_layers", cx.view_of(&out, ViewSpec::array()));
        if let Some(under) = &under {
            b = b.view("still_layers", cx.view_of(under, ViewSpec::array()));
        }
        cx.dispatch_shader(
            "shadow depth from visibility",
            &Self::resolve_key(job.target),
            "from_visibility_layers",
            b,
            spread(groups),
        )?;
        cx.count(LAYERS_TOGETHER, parts.len() as u64);
        cx.count(LAYER_CHAINS, 1);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rect(x: u32, y: u32, w: u32, h: u32) -> Rect {
        Rect { x, y, w, h }
    }

    #[test]
    fn each_part_starts_where_the_last_parts_workgroups_end() {
        let (table, groups) = parts_table(
            [
                (0, rect(0, 0, 1024, 1024), 0),
                (3, rect(0, 0, 3, 1024), 7),
                (3, rect(3, 0, 1021, 2), 9),
            ]
            .into_iter(),
        );
        assert_eq!(table[0].first_group, 0);
        assert_eq!(table[0].groups_across, 128);
        assert_eq!(table[1].first_group, 128 * 128);
        assert_eq!(table[1].groups_across, 1);
        assert_eq!(table[2].first_group, 128 * 128 + 128);
        assert_eq!(table[2].groups_across, 128);
        assert_eq!(groups, 128 * 128 + 128 + 128);
        assert_eq!((table[1].layer, table[1].words), (3, 7));
        assert_eq!(table[2].region, [3, 0, 1021, 2]);
        // Four cascades of 1024 spill into y.
        assert_eq!(spread(4 * 128 * 128), (65_535, 2, 1));
        assert_eq!(spread(0), (1, 1, 1));
    }

    #[test]
    fn chains_split_where_the_words_would_pass_one_binding() {
        let camera = bytemuck::Zeroable::zeroed();
        let parts: Vec<Part> = (0..5)
            .map(|layer| Part {
                layer,
                rect: Rect::full(4),
                camera,
            })
            .collect();
        let sizes = |max| {
            chunks(&parts, max)
                .iter()
                .map(|c| c.len())
                .collect::<Vec<_>>()
        };
        assert_eq!(sizes(1 << 20), vec![5]);
        assert_eq!(sizes(32), vec![2, 2, 1]);
        // A part too large alone still goes, alone.
        assert_eq!(sizes(8), vec![1, 1, 1, 1, 1]);
    }
}

/// The layout the shaders see (shaders/layout.rs).
#[cfg(test)]
mod wgsl_layout {
    use super::*;

    #[test]
    fn gpu_part_matches_part_in_the_resolve() {
        crate::assert_wgsl_layout!(
            GpuPart,
            crate::shadows::raster_key::ShadowResolveKey,
            [],
            "Part",
            [layer, words, first_group, groups_across, region]
        );
    }
}
