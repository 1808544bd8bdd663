//! Lit transparency's lights shaded in compute (`TransparencyShading`).
//!
//! The forward path draws every transparent layer once more per light
//! buffer, and every fragment of every layer walks its froxel's lights and
//! writes the blended accumulation through the raster output. At 1080p over
//! a thousand glass spheres that costs the H200 9.6 ms for 1,000 lights and
//! 441 ms for 100,000 (docs/benchmarks.md, session 17), a hundred times
//! CookTorrance's compute shade of the same lights. Two costs there are not
//! the lights' own: the raster output (blended half-float targets, both
//! faces, several layers a pixel), and 2x2 quads shading pixels the
//! triangles do not cover (a sphere's triangle covers about 1.5 pixels).
//!
//! The compute path draws each layer once (the base pass, which writes the
//! unlit colour and the coverage as before) and has each kept fragment also
//! store its lighting inputs, 40 bytes, in the next of its pixel's
//! [`SLOTS`] (a counter per pixel; transparency.wgsl's FRAGMENT_RECORDS).
//! Then one compute pass per light buffer (COMPUTE_SHADE's `shade`) walks
//! each pixel's records with the forward walk and sums in f32 what the
//! light pass would have blended, and the resolve adds the sums
//! (LIGHT_SUMS). The picture is the forward one up to the records' packing
//! (16-bit normal, roughness, metallic, alpha and coverage) and the f32 sum
//! (the tests hold it within 4e-3, the forward half-float sum's rounding).
//!
//! A node with a coated, sheen or anisotropic layer also keeps that lobe's
//! inputs per slot, 8 bytes each, in a buffer of its own
//! (`RecordedLobes`): made, cleared, written and read only then, so a
//! frame without such a layer records what it did before.
//!
//! A pixel with more fragments than slots lights the missed ones as its
//! recorded ones on average per weight: approximate there, never dark or
//! NaN. The missed fragments are counted on the GPU ([`FragmentLists::missed`]
//! reads the count back); how many slots a pixel has is in `stats`.

use std::sync::Mutex;

use crate::adapter_class::AdapterClass;
use crate::context::GpuContext;
use crate::error::RenderError;
use crate::geometry::readback::read_storage;
use crate::renderer::Renderer;

/// How the transparent layers' lights are shaded.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum TransparencyShading {
    /// What measures faster on the adapter's class ([`auto_compute`]).
    #[default]
    Auto,
    /// Each layer drawn again per light buffer, each fragment walking its
    /// lights and blending them into the accumulation.
    Forward,
    /// Each layer drawn once, its fragments recorded per pixel and lit in
    /// compute, a pass per light buffer: each pixel walks its fragments'
    /// froxel lists alone.
    Compute,
    /// As Compute, each 8x8 tile loading its froxels' lights into workgroup
    /// memory 64 at a time for all its pixels (CookTorrance's clustered
    /// sharing); a buffer whose lights are walked naively is shaded as
    /// Compute shades it.
    Tiled,
}

impl TransparencyShading {
    /// Whether the lights are shaded in compute on an adapter of `class`.
    pub fn computes(self, class: AdapterClass) -> bool {
        match self {
            TransparencyShading::Auto => auto_compute(class),
            TransparencyShading::Forward => false,
            TransparencyShading::Compute | TransparencyShading::Tiled => true,
        }
    }
}

/// `Auto`'s choice: Compute on every adapter. On the H200 (session 18,
/// docs/benchmarks.md "Session 18 on the H200") it was never slower than
/// the forward path and up to 20x faster: lit-transparency.ron 3.11 ->
/// 1.43 ms a frame, bench-transparency's accumulation at 1,000 / 10,000 /
/// 100,000 lights 10.0 / 44.3 / 446 -> 5.2 / 7.6 / 21.7 ms, post.ron equal;
/// lavapipe measured it faster too. A device whose limits leave no slot
/// (`slots_for` 0) still draws forward. The class stays an argument: the
/// choice was per adapter until measured, and may be again.
pub fn auto_compute(_class: AdapterClass) -> bool {
    true
}

// SHADE_TILED's 8x8 tiles each lie in one tile of the forward grid.
const _: () = assert!(crate::lighting::ClusterGrid::FORWARD_TILE.is_multiple_of(8));

/// Records a pixel has room for: the glass spheres of
/// patches/bench-transparency.ron put up to about eight layers on a pixel.
pub const SLOTS: u32 = 8;

/// One fragment record: ten u32 words (transparency.wgsl's RECORD_WORDS).
const RECORD_BYTES: u64 = 40;
/// A coated node's second record per slot: the coat's normal, factor and
/// roughness (two u32 words; transparency.wgsl's `coat_records`). A node
/// with a sheen layer has one more for its colour and roughness
/// (`sheen_records`), one with an anisotropic layer one for its direction
/// and strength (`anisotropy_records`), each of the same size.
const LOBE_RECORD_BYTES: u64 = 8;

/// Which per-slot records besides the fragment's a node's layers need: the
/// lobes some layer's material has ([`ListBuffers`]' optional buffers).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct RecordedLobes {
    pub coat: bool,
    pub sheen: bool,
    pub anisotropy: bool,
}

/// Counted: the slots per pixel of this frame's fragment lists.
pub const FRAGMENT_SLOTS: &str = "transparency fragment slots per pixel";
/// Counted: light buffers shaded in compute (one `shade` dispatch each).
pub const SHADED: &str = "transparency light buffers shaded in compute";

/// The slots per pixel that fit `pixels` records within the device's
/// binding and buffer limits: [`SLOTS`], fewer for a huge image, and 0 when
/// not even one fits (then the forward path runs).
pub fn slots_for(pixels: u64, max_binding: u64, max_buffer: u64) -> u32 {
    let per_slot = pixels.max(1) * RECORD_BYTES;
    (max_binding.min(max_buffer) / per_slot).min(u64::from(SLOTS)) as u32
}

/// [`slots_for`] `pixels` on `gpu`'s device limits.
pub(crate) fn slots_on(gpu: &GpuContext, pixels: u64) -> u32 {
    let limits = gpu.device.limits();
    slots_for(
        pixels,
        limits.max_storage_buffer_binding_size,
        limits.max_buffer_size,
    )
}

/// The buffers of one frame's fragment lists, for `pixels` pixels.
pub(crate) struct ListBuffers {
    pub pixels: u32,
    pub slots: u32,
    /// A counter per pixel, then the count of fragments no slot was left for.
    pub counts: wgpu::Buffer,
    /// `slots` records per pixel, exactly (the shader divides its length).
    pub records: wgpu::Buffer,
    /// Per pixel, the compute-shaded light (vec4<f32>).
    pub light: wgpu::Buffer,
    /// `slots` coat records per pixel, only when some layer has a coat.
    pub coat: Option<wgpu::Buffer>,
    /// `slots` sheen records per pixel, only when some layer has a sheen.
    pub sheen: Option<wgpu::Buffer>,
    /// `slots` anisotropy records per pixel, only when some layer is anisotropic.
    pub anisotropy: Option<wgpu::Buffer>,
}

impl ListBuffers {
    /// The lobes these buffers record.
    pub fn lobes(&self) -> RecordedLobes {
        RecordedLobes {
            coat: self.coat.is_some(),
            sheen: self.sheen.is_some(),
            anisotropy: self.anisotropy.is_some(),
        }
    }

    /// The lobe records, which no fragment of a layer without that lobe
    /// writes and every shade reads: a cleared record is no coat, no sheen
    /// (black) and the isotropic lobe (strength 0).
    pub fn lobe_buffers(&self) -> impl Iterator<Item = &wgpu::Buffer> {
        [&self.coat, &self.sheen, &self.anisotropy]
            .into_iter()
            .flatten()
    }
}

/// Per node: the fragment lists' buffers, kept from frame to frame while
/// the image size stays.
#[derive(Default)]
pub(crate) struct FragmentLists(Mutex<Option<std::sync::Arc<ListBuffers>>>);

impl FragmentLists {
    /// Buffers for `pixels` pixels with `slots` slots each (and the
    /// records of `lobes`), last frame's when they match.
    pub fn get(
        &self,
        gpu: &GpuContext,
        pixels: u32,
        slots: u32,
        lobes: RecordedLobes,
    ) -> std::sync::Arc<ListBuffers> {
        let mut kept = self.0.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(buffers) = kept.as_ref()
            && buffers.pixels == pixels
            && buffers.slots == slots
            && buffers.lobes() == lobes
        {
            return buffers.clone();
        }
        let storage = |label: &str, bytes: u64, extra: wgpu::BufferUsages| {
            gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: bytes.max(16),
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST | extra,
                mapped_at_creation: false,
            })
        };
        let pixels64 = u64::from(pixels);
        let lobe_records = |label: &str| {
            storage(
                label,
                pixels64 * u64::from(slots) * LOBE_RECORD_BYTES,
                wgpu::BufferUsages::empty(),
            )
        };
        let buffers = std::sync::Arc::new(ListBuffers {
            pixels,
            slots,
            counts: storage(
                "transparency fragment counts",
                (pixels64 + 1) * 4,
                wgpu::BufferUsages::COPY_SRC,
            ),
            // Exactly `slots` per pixel: the shader finds `slots` as the length over the pixels.
            records: gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("transparency fragment records"),
                size: pixels64 * u64::from(slots) * RECORD_BYTES,
                usage: wgpu::BufferUsages::STORAGE,
                mapped_at_creation: false,
            }),
            light: storage(
                "transparency compute-shaded light",
                pixels64 * 16,
                wgpu::BufferUsages::empty(),
            ),
            // Each a fifth of the records: within the limits whenever they are.
            coat: lobes
                .coat
                .then(|| lobe_records("transparency coat records")),
            sheen: lobes
                .sheen
                .then(|| lobe_records("transparency sheen records")),
            anisotropy: lobes
                .anisotropy
                .then(|| lobe_records("transparency anisotropy records")),
        });
        *kept = Some(buffers.clone());
        buffers
    }

    /// The last frame's fragment lists, if any was made.
    pub fn current(&self) -> Option<std::sync::Arc<ListBuffers>> {
        self.0.lock().unwrap_or_else(|e| e.into_inner()).clone()
    }

    /// How many fragments of the last frame found their pixel's slots full
    /// (read back from the GPU, waiting for it); 0 before any compute frame.
    pub fn missed(&self, renderer: &Renderer) -> Result<u32, RenderError> {
        let Some(buffers) = self.current() else {
            return Ok(0);
        };
        let offset = u64::from(buffers.pixels) * 4;
        let bytes = read_storage(renderer, &buffers.counts, offset, 4)?;
        Ok(u32::from_le_bytes([bytes[0], bytes[1], bytes[2], bytes[3]]))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn auto_shades_in_compute_on_every_adapter_and_slots_fit_the_limits() {
        use AdapterClass::{Cpu, Gpu};
        for class in [Gpu, Cpu] {
            assert!(!TransparencyShading::Forward.computes(class));
            assert!(TransparencyShading::Compute.computes(class));
            assert!(TransparencyShading::Tiled.computes(class));
            assert_eq!(
                TransparencyShading::Auto.computes(class),
                auto_compute(class)
            );
        }
        assert!(TransparencyShading::Auto.computes(Gpu));
        assert!(TransparencyShading::Auto.computes(Cpu));
        // 1080p: eight slots are 663 MB, within a 4 GiB binding, not within 128 MiB.
        let hd = 1920 * 1080;
        assert_eq!(slots_for(hd, 4 << 30, u64::MAX), SLOTS);
        assert_eq!(slots_for(hd, 128 << 20, u64::MAX), 1);
        assert_eq!(slots_for(hd, 4 << 30, 128 << 20), 1);
        assert_eq!(slots_for(16384 * 16384, 128 << 20, u64::MAX), 0);
        assert_eq!(slots_for(0, 128 << 20, u64::MAX), SLOTS);
    }
}
