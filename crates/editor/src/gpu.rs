//! The one device: egui-wgpu opens it with what the renderer needs, so the
//! viewports render on the device egui draws with.

use std::sync::Arc;

use spreadlight_render::Renderer;
use spreadlight_render::context::{OPTIONAL_FEATURES, REQUIRED_FEATURES};

use crate::viewport::Blitter;

/// The renderer the worker draws the viewports and previews with, on
/// egui's device (here, below both the worker and the previews' engine).
pub struct WorkerGpu {
    pub state: egui_wgpu::RenderState,
    pub renderer: Arc<Renderer>,
    pub blitter: Blitter,
}

/// Limits the renderer asks for (the same as `GpuContext::headless`): the
/// adapter's own storage limits, since buffers grow with lights and instances.
fn limits(adapter: &wgpu::Limits) -> wgpu::Limits {
    wgpu::Limits {
        max_storage_buffer_binding_size: adapter.max_storage_buffer_binding_size,
        max_buffer_size: adapter.max_buffer_size,
        max_storage_buffers_per_shader_stage: adapter.max_storage_buffers_per_shader_stage.min(16),
        max_storage_textures_per_shader_stage: adapter.max_storage_textures_per_shader_stage.min(8),
        ..wgpu::Limits::default()
    }
}

/// egui-wgpu's setup with the renderer's features and limits. `prefer_cpu`
/// picks a software adapter first (tests, for stable snapshots).
pub fn wgpu_setup(prefer_cpu: bool) -> egui_wgpu::WgpuSetup {
    let mut setup = egui_wgpu::WgpuSetupCreateNew::without_display_handle();
    setup.device_descriptor = Arc::new(|adapter: &wgpu::Adapter| wgpu::DeviceDescriptor {
        label: Some("spreadlight editor"),
        required_features: REQUIRED_FEATURES | (OPTIONAL_FEATURES & adapter.features()),
        required_limits: limits(&adapter.limits()),
        ..Default::default()
    });
    if prefer_cpu {
        setup.native_adapter_selector = Some(Arc::new(|adapters, _surface| {
            let mut adapters: Vec<&wgpu::Adapter> = adapters.iter().collect();
            adapters.sort_by_key(|a| match a.get_info().device_type {
                wgpu::DeviceType::Cpu => 0,
                wgpu::DeviceType::DiscreteGpu => 1,
                _ => 2,
            });
            adapters
                .first()
                .map(|a| (*a).clone())
                .ok_or_else(|| "no adapter found".to_owned())
        }));
    }
    egui_wgpu::WgpuSetup::CreateNew(setup)
}
