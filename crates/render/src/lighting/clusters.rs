//! Clustered light assignment (shaders/lighting/clusters.wgsl): froxels of
//! `tile` pixels by exponential depth slices, an exact index list per froxel.

use std::sync::Mutex;

use super::LightBuffer;
use crate::adapter_class::AdapterClass;
use crate::context::GpuContext;
use crate::error::RenderError;
use crate::frame_graph::{Bindings, PassContext};
use crate::shaders::Permutation;

pub use super::clusters_key::ClustersKey;

/// The froxel grid for a target size and depth range.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClusterGrid {
    pub tiles_x: u32,
    pub tiles_y: u32,
    pub slices: u32,
    pub tile: u32,
    pub near: f32,
    pub far: f32,
}

// CookTorrance shades 16x16 blocks that must each lie in one tile.
const _: () = assert!(ClusterGrid::TILE.is_multiple_of(16));
// clusters.wgsl keeps the slices' depths in a table of MAX_SLICES + 1.
const _: () = assert!(ClusterGrid::SLICES <= 128 && ClusterGrid::FORWARD_SLICES <= 128);

impl ClusterGrid {
    /// Tiles of 256 pixels: the shading pass culls each froxel's list
    /// against its 16x16 blocks' depth-bounded boxes, so a coarse tile costs
    /// it little (a longer list, read once per block), while every light
    /// enters fewer lists. On the H100 at 100,000 lights, 64-pixel tiles
    /// took 1.06 ms to assign and 4.80 ms to shade, 256-pixel tiles 0.34 and
    /// 4.92 (docs/benchmarks.md, "Session 9").
    pub const TILE: u32 = 256;
    /// Tiles of 32 pixels for a forward loop (lit transparency), which has
    /// no blocks to cull a coarse list against: every fragment walks its
    /// froxel's whole list, and a 256-pixel tile's list holds about 64 times
    /// the lights a 32-pixel one does where lights are small on screen. On
    /// the H200, 1,000 lights behind 1,024 glass spheres took 13.7 ms to
    /// accumulate with 256-pixel tiles (docs/benchmarks.md, "Session 16").
    pub const FORWARD_TILE: u32 = 32;
    pub const SLICES: u32 = 32;
    /// Slices of the forward loop's grid. Over near 0.1 .. far 1,000, 32
    /// slices are each a third of their depth thick (10 units at 30 from
    /// the eye, against a 32-pixel tile about 1 unit wide there at 1080p),
    /// so a froxel's list holds every light along a long stretch of the
    /// view ray. 128 are 7.5% thick: about two tiles deep. The forward
    /// assignment lists only the froxels transparent fragments occupy
    /// (clusters.wgsl, OCCUPIED), so the thin empty ones cost a load each.
    pub const FORWARD_SLICES: u32 = 128;

    /// The grid for a `size` target and a camera whose depth runs `near`..`far`.
    pub fn new(size: (u32, u32), near: f32, far: f32) -> Self {
        Self::with_tile(size, near, far, Self::TILE)
    }

    /// The grid with square tiles of `tile` pixels (at least one).
    pub fn with_tile(size: (u32, u32), near: f32, far: f32, tile: u32) -> Self {
        Self::with_slices(size, near, far, tile, Self::SLICES)
    }

    /// The forward loop's grid: [`Self::FORWARD_TILE`] pixels by
    /// [`Self::FORWARD_SLICES`] slices.
    pub fn forward(size: (u32, u32), near: f32, far: f32) -> Self {
        Self::with_slices(size, near, far, Self::FORWARD_TILE, Self::FORWARD_SLICES)
    }

    /// The grid with square tiles of `tile` pixels (at least one) and
    /// `slices` depth slices (1..=128, clusters.wgsl's table).
    pub fn with_slices(size: (u32, u32), near: f32, far: f32, tile: u32, slices: u32) -> Self {
        let tile = tile.max(1);
        let near = if near.is_finite() && near > 0.0 {
            near
        } else {
            0.01
        };
        let far = if far.is_finite() && far > near * 1.01 {
            far
        } else {
            near * 1000.0
        };
        ClusterGrid {
            tiles_x: size.0.div_ceil(tile).max(1),
            tiles_y: size.1.div_ceil(tile).max(1),
            slices: slices.clamp(1, 128),
            tile,
            near,
            far,
        }
    }

    pub fn clusters(&self) -> u32 {
        self.tiles_x * self.tiles_y * self.slices
    }

    /// `Grid` in the lighting shaders, as words, with no light cutoff.
    pub(crate) fn uniform(&self, lights: u32) -> [u32; 12] {
        self.uniform_with_cutoff(lights, 0.0)
    }

    /// `Grid` with a light cutoff ([`light_cutoff`]: 0 when not a finite
    /// positive number): each light's range becomes where its illuminance
    /// falls to it (lights.wgsl's `cutoff_range`), in the assignment and
    /// the walks alike.
    pub(crate) fn uniform_with_cutoff(&self, lights: u32, cutoff: f32) -> [u32; 12] {
        bytemuck::cast(GpuGrid {
            dims: [self.tiles_x, self.tiles_y, self.slices, lights],
            depth: [
                self.near,
                self.far,
                (self.far / self.near).ln(),
                self.tile as f32,
            ],
            falloff: [light_cutoff(cutoff), 0.0, 0.0, 0.0],
        })
    }
}

/// A light cutoff as the shaders take it: a finite positive illuminance, or
/// 0 (none: every light keeps its range) for anything else (NaN, infinity,
/// zero or less), so no value reaches the GPU that could make a range NaN.
pub fn light_cutoff(cutoff: f32) -> f32 {
    if cutoff.is_finite() && cutoff > 0.0 {
        cutoff
    } else {
        0.0
    }
}

/// The grid uniform's size in bytes (`Grid` in the lighting shaders).
pub(crate) const GRID_BYTES: u64 = std::mem::size_of::<GpuGrid>() as u64;

/// `Grid` in shaders/lighting/clusters.wgsl (and cook_torrance.wgsl).
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct GpuGrid {
    /// Tiles across, tiles down, depth slices, lights.
    dims: [u32; 4],
    /// Near, far, ln(far / near), the tile's side in pixels.
    depth: [f32; 4],
    /// The light cutoff (0: none), then padding.
    falloff: [f32; 4],
}

/// The froxel buffers, kept between frames and grown when needed.
pub(crate) struct ClusterBuffers {
    pub clusters: u32,
    pub lights: u32,
    pub capacity: u32,
    pub view_lights: wgpu::Buffer,
    /// Merged lights' bands in view space (Light Merge), one per light.
    pub view_bands: wgpu::Buffer,
    pub counts: wgpu::Buffer,
    pub offsets: wgpu::Buffer,
    pub indices: wgpu::Buffer,
    pub totals: wgpu::Buffer,
}

/// Kept per node across its recipes (`Renderer::state`): a CookTorrance
/// whose G-buffer changes every frame (a moving or jittered camera) makes a
/// new recipe every frame, and must not make new buffers (and bind groups) too.
#[derive(Default)]
pub(crate) struct ClusterStore(Mutex<Option<ClusterBuffers>>);

impl ClusterStore {
    /// Buffers for `clusters` froxels and `lights` lights, reusing last frame's when big enough.
    pub fn get(
        &self,
        gpu: &GpuContext,
        clusters: u32,
        lights: u32,
    ) -> std::sync::MutexGuard<'_, Option<ClusterBuffers>> {
        let mut guard = self.0.lock().unwrap_or_else(|e| e.into_inner());
        let fits = guard
            .as_ref()
            .is_some_and(|b| b.clusters >= clusters && b.lights >= lights.max(1));
        if !fits {
            // The index list: room for every light in 256 froxels, or 64 lights in
            // every froxel, whichever is more, within the device's binding limit.
            // A frame that needs more cuts the longest lists (the shader never
            // reads past the end); the note in docs/benchmarks.md says when.
            let max = (gpu.device.limits().max_storage_buffer_binding_size / 4)
                .min(u64::from(u32::MAX)) as u32;
            let capacity = clusters
                .saturating_mul(64)
                .max(lights.saturating_mul(256))
                .min(max);
            let storage = |label: &str, bytes: u64| {
                gpu.device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some(label),
                    size: bytes.max(16),
                    usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
                    mapped_at_creation: false,
                })
            };
            *guard = Some(ClusterBuffers {
                clusters,
                lights: lights.max(1),
                capacity,
                view_lights: storage("view-space lights", u64::from(lights.max(1)) * 16),
                view_bands: storage("view-space light bands", u64::from(lights.max(1)) * 16),
                counts: storage("froxel light counts", u64::from(clusters) * 4),
                offsets: storage("froxel light offsets", u64::from(clusters) * 4),
                indices: storage("froxel light indices", u64::from(capacity) * 4),
                totals: storage("froxel totals", 16),
            });
        }
        guard
    }
}

/// How the count and fill steps spread the lights' froxels over workgroups.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Assignment {
    /// A light's froxels shared among the 64 lanes of each of its
    /// `workgroups` (clusters.wgsl's `count` and `fill`): few lights, each
    /// of many froxels, still fill the GPU.
    PerLight { workgroups: u32 },
    /// 64 lights a workgroup, whose lanes share all their (light, froxel)
    /// pairs (`count_packed`, `fill_packed`), split among `split`
    /// workgroups: many lights of a few froxels each leave no lane idle.
    Packed { split: u32 },
}

/// From this many lights a GPU's assignment packs 64 lights a workgroup.
const PACKED_FROM: u32 = 512;

impl Assignment {
    /// Packed from [`PACKED_FROM`] lights on a GPU (64 on a CPU adapter,
    /// where it saves workgroups, each a task with barriers), each group of
    /// 64 split so that about `lights / 12` workgroups run, at least 2,048
    /// and at most 8,192 as far as splitting a group at most 64 ways and not
    /// at all allows (512 lights: 512 workgroups; 1,000,000: 15,625).
    /// Measured on the H200 (docs/benchmarks.md, "Session 30"): the
    /// assignment of 1,000 lights took 0.051 ms a workgroup a light and
    /// 0.028 packed, 100,000 0.343 and 0.217, 1,000,000 2.96 and 1.65. Fewer
    /// workgroups left the GPU waiting on a few (10,000 lights in 157
    /// unsplit took 0.168 ms against 0.054), more repeated each one's
    /// packing for too few pairs.
    fn of(lights: u32, clusters: u32, class: AdapterClass) -> Assignment {
        let packed_from = match class {
            AdapterClass::Gpu => PACKED_FROM,
            AdapterClass::Cpu => 64,
        };
        if lights < packed_from {
            return Assignment::PerLight {
                workgroups: workgroups_per_light(lights, clusters, class),
            };
        }
        let groups = lights.div_ceil(64);
        let split = match class {
            AdapterClass::Gpu => ((lights / 12).clamp(2_048, 8_192) / groups).clamp(1, 64),
            AdapterClass::Cpu => 1,
        };
        Assignment::Packed { split }
    }

    /// The steps, in the order [`assign_lights`] dispatches them.
    fn steps(self) -> [&'static str; 4] {
        match self {
            Assignment::PerLight { .. } => ["transform", "count", "scan", "fill"],
            Assignment::Packed { .. } => ["transform", "count_packed", "scan", "fill_packed"],
        }
    }

    /// The count and fill steps' workgroups for `lights` (x up to 65,535,
    /// then y).
    fn workgroups(self, lights: u32) -> (u32, u32, u32) {
        let (groups, z) = match self {
            Assignment::PerLight { workgroups } => (lights, workgroups),
            Assignment::Packed { split } => (lights.div_ceil(64), split),
        };
        (groups.clamp(1, 65_535), groups.div_ceil(65_535).max(1), z)
    }
}

/// Announce the pipelines of an assignment `pass` will run
/// (frame_graph/gather.rs): `occupied` where it reads froxel marks, as
/// [`assign_lights`] is given them, `merged` where the lights carry Light
/// Merge's bands; `lights` and the adapter's `class` decide the steps
/// ([`Assignment::of`]).
pub(crate) fn announce_assignment(
    pass: &mut crate::frame_graph::PassBuilder<'_, '_>,
    occupied: bool,
    merged: bool,
    lights: u32,
    class: AdapterClass,
) {
    if !pass.graph().gathers_pipelines() {
        return;
    }
    let key = ClustersKey { occupied, merged }.key();
    // The steps do not depend on the grid (only how many workgroups run them).
    for step in Assignment::of(lights, 1, class).steps() {
        pass.will_dispatch(&key, step);
    }
}

/// Lists `lights` in the froxels of `grid` (its uniform in `grid_buffer`,
/// the camera in `camera`), into `store`'s buffers: the assignment
/// CookTorrance's clustered light loop reads, and lit transparency's forward
/// one (post/transparency), so both walk lists made the same way. With
/// `occupied` (a word per froxel, non-zero where a transparent fragment
/// lies), only those froxels get lists, and the end slices are unbounded.
pub(crate) fn assign_lights(
    cx: &mut PassContext<'_>,
    store: &ClusterStore,
    grid: ClusterGrid,
    grid_buffer: &wgpu::Buffer,
    camera: &wgpu::Buffer,
    lights: &LightBuffer,
    occupied: Option<&wgpu::Buffer>,
) -> Result<(), RenderError> {
    let count = lights.count();
    let guard = store.get(cx.gpu, grid.clusters(), count);
    let Some(b) = guard.as_ref() else {
        return Ok(());
    };
    cx.encoder().clear_buffer(&b.counts, 0, None);
    cx.gpu.queue.write_buffer(
        &b.totals,
        0,
        bytemuck::cast_slice(&[0u32, b.capacity, 0, 0]),
    );
    let key = ClustersKey {
        occupied: occupied.is_some(),
        merged: lights.bands().is_some(),
    }
    .key();
    // Only the clustered walk runs this pass; the naive loop moves its
    // few lights to view space itself.
    let assignment = Assignment::of(count, grid.clusters(), cx.gpu.adapter_class());
    let mut work = Vec::new();
    for step in assignment.steps() {
        let pipeline = cx.compute_pipeline(&key, step)?;
        let bindings = Bindings::new()
            .buffer("camera", camera)
            .buffer("grid", grid_buffer)
            .buffer("lights", lights.buffer())
            .buffer("view_lights", &b.view_lights)
            .buffer("counts", &b.counts)
            .buffer("offsets", &b.offsets)
            .buffer("indices", &b.indices)
            .buffer("totals", &b.totals)
            .buffer_opt("occupied", occupied)
            .buffer_opt("bands", lights.bands())
            .buffer_opt("view_bands", lights.bands().map(|_| &b.view_bands));
        let group = cx.bind_groups(&key, step, &pipeline, bindings)?;
        // transform: a thread per light; scan: one workgroup; count and
        // fill: as the assignment spreads them.
        let groups = match step {
            "scan" => (1, 1, 1),
            "transform" => (count.div_ceil(64).max(1), 1, 1),
            _ => assignment.workgroups(count),
        };
        work.push((pipeline, group, groups));
    }
    let pass = cx.compute_pass("light assignment");
    for (pipeline, bind_groups, groups) in &work {
        pass.set_pipeline(pipeline);
        for (i, group) in bind_groups.iter().enumerate() {
            pass.set_bind_group(i as u32, group, &[]);
        }
        pass.dispatch_workgroups(groups.0, groups.1, groups.2);
    }
    Ok(())
}

/// How many workgroups share each light's froxels when `lights` are
/// assigned to `clusters` froxels. On a GPU: enough that a few lights still
/// fill it (three big spots took 0.22 ms at one workgroup each on the H100,
/// walking 16,000 froxels 64 at a time), one where lights alone are plenty.
/// On a CPU adapter a workgroup is a task its few cores start one after
/// another, a barrier in it a coroutine per 8 lanes: about 64 workgroups in
/// all keep the cores busy, and never more per light than 64 lanes' worth of
/// froxels (at 160x90 the grid has 32, and the GPU's 64 workgroups a light,
/// 63 of them idle, made 100 lights' assignment 18 ms on lavapipe against
/// 0.45 ms with one; docs/benchmarks.md, "lavapipe").
fn workgroups_per_light(lights: u32, clusters: u32, class: AdapterClass) -> u32 {
    match class {
        AdapterClass::Gpu => (16_384 / lights.max(1)).clamp(1, 64),
        AdapterClass::Cpu => (64 / lights.max(1)).clamp(1, clusters.div_ceil(64).clamp(1, 64)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_gpu_spreads_few_lights_over_many_workgroups_as_before() {
        for clusters in [32, 1_280, 16_320] {
            assert_eq!(workgroups_per_light(1, clusters, AdapterClass::Gpu), 64);
            assert_eq!(workgroups_per_light(100, clusters, AdapterClass::Gpu), 64);
            assert_eq!(workgroups_per_light(1_000, clusters, AdapterClass::Gpu), 16);
            assert_eq!(
                workgroups_per_light(100_000, clusters, AdapterClass::Gpu),
                1
            );
        }
    }

    #[test]
    fn many_lights_are_packed_64_a_workgroup_and_split_to_fill_the_gpu() {
        use Assignment::{Packed, PerLight};
        let of = |lights| Assignment::of(lights, 1_280, AdapterClass::Gpu);
        assert_eq!(of(100), PerLight { workgroups: 64 });
        assert_eq!(of(511), PerLight { workgroups: 32 });
        // 8 groups of 64, split the most (64 ways): 512 workgroups.
        assert_eq!(of(512), Packed { split: 64 });
        assert_eq!(of(10_000), Packed { split: 13 });
        // 1,563 groups, about lights / 12 = 8,333 workgroups capped at 8,192.
        assert_eq!(of(100_000), Packed { split: 5 });
        assert_eq!(of(1_000_000), Packed { split: 1 });
        assert_eq!(of(100_000).steps()[1], "count_packed");
        assert_eq!(of(100).steps()[1], "count");
        // Past 65,535 groups the dispatch goes on in y.
        assert_eq!(
            Packed { split: 1 }.workgroups(5_000_000),
            (65_535, 2, 1),
            "78,125 groups"
        );
        assert_eq!(of(100_000).workgroups(100_000), (1_563, 1, 5));
        // A CPU adapter packs from 64 lights and never splits: each
        // workgroup is a task its few cores start one after another.
        let cpu = |lights| Assignment::of(lights, 1_280, AdapterClass::Cpu);
        assert_eq!(cpu(63), PerLight { workgroups: 1 });
        assert_eq!(cpu(64), Packed { split: 1 });
        assert_eq!(cpu(100_000), Packed { split: 1 });
    }

    #[test]
    fn a_cpu_adapter_starts_no_workgroup_that_can_find_no_froxel() {
        // 160x90: one 256-pixel tile by 32 slices, which one workgroup's 64 lanes cover.
        assert_eq!(workgroups_per_light(1, 32, AdapterClass::Cpu), 1);
        assert_eq!(workgroups_per_light(100, 32, AdapterClass::Cpu), 1);
        // 1920x1080 (8 x 5 x 32 froxels): a lone light is shared among 20.
        assert_eq!(workgroups_per_light(1, 1_280, AdapterClass::Cpu), 20);
        assert_eq!(workgroups_per_light(3, 1_280, AdapterClass::Cpu), 20);
        assert_eq!(workgroups_per_light(16, 1_280, AdapterClass::Cpu), 4);
        assert_eq!(workgroups_per_light(100, 1_280, AdapterClass::Cpu), 1);
        assert_eq!(workgroups_per_light(0, 0, AdapterClass::Cpu), 1);
    }
}

#[cfg(test)]
mod wgsl_layout {
    #[test]
    fn gpu_grid_matches_the_shaders() {
        crate::assert_wgsl_layout!(
            super::GpuGrid,
            crate::lighting::clusters_key::ClustersKey,
            [],
            "Grid",
            [dims, depth, falloff]
        );
        crate::assert_wgsl_layout!(
            super::GpuGrid,
            crate::lighting::cook_torrance_key::CookTorranceKey,
            ["CLUSTERED"],
            "Grid",
            [dims, depth, falloff]
        );
    }
}
