//! What kind of adapter the renderer runs on, and the choices that depend on
//! it: the internal `Auto` settings (how work is spread over workgroups) that
//! measure fastest on one kind cost the other several times over.
//!
//! A GPU (the H200 the frame targets are measured on) runs tens of thousands
//! of workgroups at once and wants many small ones, so that a few big lights
//! or a few big triangles still fill it. A CPU adapter (Mesa's lavapipe /
//! llvmpipe, what CI and headless users without a GPU run; also WARP or
//! SwiftShader) runs one workgroup after another on a few cores: every
//! workgroup costs a fixed start (and, with a barrier, a coroutine per
//! 8 lanes), so workgroups that find nothing to do are pure cost. Measured on
//! lavapipe, 2 cores, bench-lights at 160x90 with 100 lights
//! (docs/benchmarks.md, "lavapipe (development machine, no GPU)").
//!
//! What follows the class (each where it is decided, each tested both ways):
//! - the clustered light assignment's workgroups (`lighting/clusters.rs`,
//!   `Assignment`): a GPU up to 64 a light, and from 512 lights 64 lights
//!   a workgroup with their pairs split to about `lights / 12` workgroups;
//!   a CPU adapter about 64 in all and never more than a light's froxels
//!   fill, and from 64 lights 64 a workgroup, not split;
//! - the compute raster's permutation (`gbuffer/compute_raster.rs`,
//!   `raster_key`): on a CPU adapter a raster without particle systems
//!   fetches corner positions alone (MESHES_ONLY), not whole vertices
//!   through the particle-aware `triangle_vertex`;
//! - how many workgroups share the compute raster's big-triangle tiles
//!   (`gbuffer/compute_raster.rs`, `tile_workgroups`): a GPU 1,024, a CPU
//!   adapter one per thread (a workgroup with no tile still runs its whole
//!   kernel on llvmpipe);
//! - CookTorrance's light walk under `Auto` past a handful of lights
//!   (`lighting/cook_torrance.rs`, `auto_walk`): a GPU shares each 16x16
//!   block's lights through workgroup memory (Clustered), a CPU adapter walks
//!   each pixel's froxel list alone (PerPixel: no barrier to run as a coroutine);
//! - which rasterizer draws shadow maps under `Auto`
//!   (`shadows::compute_rasterizes`): a GPU compute at every
//!   resolution, a CPU adapter the raster hardware (ten to a hundred times faster
//!   there for patches/shadows.ron's cascades).
//!
//! The class comes from the adapter's own report (`AdapterInfo::device_type`),
//! so the decision is made once per device, costs nothing per frame and is
//! the same on every run; GPU adapters take exactly the paths they took
//! before the class existed.

/// The two kinds of adapter whose `Auto` choices differ.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AdapterClass {
    /// A GPU of any kind (discrete, integrated, virtual) or one that does not say.
    Gpu,
    /// A software rasterizer on the CPU (lavapipe / llvmpipe, WARP, SwiftShader).
    Cpu,
}

impl AdapterClass {
    /// The class of the adapter `info` describes. An adapter that reports
    /// `Other` is taken for a GPU: it keeps the paths tuned on the H200.
    pub fn of(info: &wgpu::AdapterInfo) -> Self {
        match info.device_type {
            wgpu::DeviceType::Cpu => AdapterClass::Cpu,
            wgpu::DeviceType::DiscreteGpu
            | wgpu::DeviceType::IntegratedGpu
            | wgpu::DeviceType::VirtualGpu
            | wgpu::DeviceType::Other => AdapterClass::Gpu,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An adapter report as wgpu would give it, of `device_type`.
    fn fake_adapter(name: &str, device_type: wgpu::DeviceType) -> wgpu::AdapterInfo {
        wgpu::AdapterInfo {
            name: name.to_owned(),
            ..wgpu::AdapterInfo::new(device_type, wgpu::Backend::Vulkan)
        }
    }

    #[test]
    fn lavapipe_is_a_cpu_adapter_and_gpus_are_gpus() {
        let lavapipe = fake_adapter("llvmpipe (LLVM 15.0.6, 256 bits)", wgpu::DeviceType::Cpu);
        assert_eq!(AdapterClass::of(&lavapipe), AdapterClass::Cpu);
        for kind in [
            wgpu::DeviceType::DiscreteGpu,
            wgpu::DeviceType::IntegratedGpu,
            wgpu::DeviceType::VirtualGpu,
            wgpu::DeviceType::Other,
        ] {
            let gpu = fake_adapter("NVIDIA H200", kind);
            assert_eq!(AdapterClass::of(&gpu), AdapterClass::Gpu, "{kind:?}");
        }
    }
}
