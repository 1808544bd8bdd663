//! The maps a shadow node keeps between frames, and what each slice holds,
//! so a slice is drawn again only when its views or casters changed.

use std::sync::{Arc, Mutex};

use crate::gbuffer::Layer;

use super::ShadowFilter;
use super::scroll::Rect;

/// Conventional depth (0 near, 1 far) per layer: what shading samples.
pub(super) const MAP_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Float;
pub(super) const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
const MOMENTS_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rg32Float;

/// The maps themselves, kept by the renderer between frames under the node.
#[derive(Default)]
pub(crate) struct ShadowStore {
    pub(super) maps: Mutex<Option<StoredMaps>>,
    /// The casters of the node's last recipe: those a new recipe shares with
    /// it (the same layers) are still; the others moved or changed.
    pub(super) last_casters: Mutex<Vec<Arc<Layer>>>,
}

/// Casters split into (still, moving).
pub(super) type StillAndMoving = (Vec<Arc<Layer>>, Vec<Arc<Layer>>);

impl ShadowStore {
    /// `casters` as (still, moving) against the node's last recipe's, which
    /// they then replace; None where they are all one or the other.
    pub fn split(&self, casters: &[Arc<Layer>]) -> Option<StillAndMoving> {
        let mut last = self.last_casters.lock().unwrap_or_else(|e| e.into_inner());
        // Holding the last casters keeps their allocations alive, so a new
        // layer can never be mistaken for an old one at the same address.
        let previous = std::mem::replace(&mut *last, casters.to_vec());
        let (still, moving): (Vec<_>, Vec<_>) = casters
            .iter()
            .cloned()
            .partition(|c| previous.iter().any(|p| Arc::ptr_eq(p, c)));
        (!still.is_empty() && !moving.is_empty()).then_some((still, moving))
    }
}

/// How the stored maps are laid out: a store of another layout is made anew.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct MapLayout {
    pub layers: u32,
    /// Layers per slice: a store laid out for other cascade counts does not fit.
    pub per_slice: u32,
    pub resolution: u32,
    pub vsm: bool,
    /// The raster hardware draws them (into depth attachments first).
    pub hardware: bool,
}

pub(super) struct StoredMaps {
    pub layout: MapLayout,
    /// R32F per layer: what shading samples.
    pub depth: wgpu::Texture,
    /// The still casters alone, per layer, made the first time a slice has
    /// moving casters: each frame draws only the moving ones over it.
    pub still: Option<wgpu::Texture>,
    /// The hardware path's Depth32Float attachments, copied into `depth`.
    pub attachments: Option<wgpu::Texture>,
    pub moments: Option<wgpu::Texture>,
    /// Per slice: what `depth` holds (its views and casters), to reuse it.
    pub contents: Vec<Option<SliceContent>>,
    /// Per slice: what `still` holds.
    pub still_contents: Vec<Option<SliceContent>>,
    /// Per slice: the map holds what its still cache holds and nothing
    /// more (the moving casters were outside its views when it was drawn).
    pub bare: Vec<bool>,
    /// VSM: the regions of layers drawn this frame whose moments are still
    /// to compute (whole layers, or about a scrolled layer's new strips).
    pub pending_moments: Vec<(u32, Rect, wgpu::Buffer)>,
    /// Per layer: the texels that held the moving casters when `depth` was
    /// last drawn there (empty: none; None: unknown, or anywhere), so the
    /// next frame over the still cache redraws only there and where they
    /// are now (slices.rs).
    pub moving_rects: Vec<Option<Rect>>,
    /// One layer of each map format, where scrolling a layer shifts its
    /// kept part through (made the first time a cascade scrolls).
    scratch: Option<wgpu::Texture>,
    moments_scratch: Option<wgpu::Texture>,
}

/// What a rendered slice shows: reusable while both are the same.
#[derive(Clone)]
pub(super) struct SliceContent {
    pub views: Vec<[f32; 16]>,
    pub casters: Vec<Arc<Layer>>,
    pub filter: ShadowFilter,
}

impl SliceContent {
    pub fn same(&self, other: &SliceContent) -> bool {
        self.same_views(other)
            && self.casters.len() == other.casters.len()
            && self
                .casters
                .iter()
                .zip(&other.casters)
                .all(|(a, b)| Arc::ptr_eq(a, b))
    }

    /// Seen from the same views with the same filter, whatever the casters.
    pub fn same_views(&self, other: &SliceContent) -> bool {
        self.views == other.views && self.filter == other.filter
    }
}

fn array(
    device: &wgpu::Device,
    label: &str,
    layout: MapLayout,
    format: wgpu::TextureFormat,
    usage: wgpu::TextureUsages,
) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width: layout.resolution,
            height: layout.resolution,
            depth_or_array_layers: layout.layers,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage,
        view_formats: &[],
    })
}

impl StoredMaps {
    pub fn allocate(device: &wgpu::Device, layout: MapLayout) -> StoredMaps {
        // Written by the passes (and by shadows/scroll.wgsl when a cascade
        // scrolls), read by shading.
        let sampled = wgpu::TextureUsages::STORAGE_BINDING | wgpu::TextureUsages::TEXTURE_BINDING;
        let slices = (layout.layers / layout.per_slice.max(1)) as usize;
        StoredMaps {
            layout,
            // Copied out by tools and tests (`ShadowMaps::read_depth`).
            depth: array(
                device,
                "shadow maps",
                layout,
                MAP_FORMAT,
                sampled | wgpu::TextureUsages::COPY_SRC,
            ),
            still: None,
            attachments: layout.hardware.then(|| {
                array(
                    device,
                    "shadow depth attachments",
                    layout,
                    DEPTH_FORMAT,
                    wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
                )
            }),
            moments: layout
                .vsm
                .then(|| array(device, "shadow moments", layout, MOMENTS_FORMAT, sampled)),
            contents: vec![None; slices],
            still_contents: vec![None; slices],
            bare: vec![false; slices],
            pending_moments: Vec::new(),
            moving_rects: vec![None; layout.layers as usize],
            scratch: None,
            moments_scratch: None,
        }
    }

    /// The scratch layers a scroll copies through: for the depth map and,
    /// with VSM, for its moments. Made once, kept with the maps.
    pub fn scratch(&mut self, device: &wgpu::Device) -> (wgpu::Texture, Option<wgpu::Texture>) {
        let one = MapLayout {
            layers: 1,
            ..self.layout
        };
        // Read and written by shadows/scroll.wgsl.
        let usage = wgpu::TextureUsages::STORAGE_BINDING | wgpu::TextureUsages::TEXTURE_BINDING;
        let depth = self
            .scratch
            .get_or_insert_with(|| array(device, "shadow scroll scratch", one, MAP_FORMAT, usage))
            .clone();
        let moments = self.layout.vsm.then(|| {
            self.moments_scratch
                .get_or_insert_with(|| {
                    array(
                        device,
                        "shadow moments scroll scratch",
                        one,
                        MOMENTS_FORMAT,
                        usage,
                    )
                })
                .clone()
        });
        (depth, moments)
    }

    /// The still casters' maps, made the first time they are asked for.
    pub fn still(&mut self, device: &wgpu::Device) -> wgpu::Texture {
        let layout = self.layout;
        self.still
            .get_or_insert_with(|| {
                array(
                    device,
                    "shadow maps of still casters",
                    layout,
                    MAP_FORMAT,
                    wgpu::TextureUsages::STORAGE_BINDING | wgpu::TextureUsages::TEXTURE_BINDING,
                )
            })
            .clone()
    }
}
