//! Lights and shading: point-light buffers, clustered light assignment,
//! the CookTorrance pass and CompositeLight. Spot and sun lights, shadows and
//! the material buffer come with their issues; until then CookTorrance takes
//! roughness and metallic per material id from its own pins.

mod clusters;
mod composite;
mod cook_torrance;

use std::sync::Arc;

use glam::Vec3;
use wgpu::util::DeviceExt;

pub use clusters::ClusterGrid;
pub use composite::CompositeLight;
pub use cook_torrance::{CookTorrance, LightLoop};

use crate::renderer::Renderer;

/// A point light. Intensity is luminous intensity in candela (lumens / 4 pi).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointLight {
    pub position: Vec3,
    pub color: Vec3,
    pub intensity: f32,
    pub range: f32,
}

/// Matches `PointLight` in shaders/lighting/*.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
struct GpuPointLight {
    position_range: [f32; 4],
    intensity: [f32; 4],
}

/// A light buffer: what a `PointLightBuffer` node outputs, uploaded once when its inputs change.
pub struct PointLights {
    pub lights: Vec<PointLight>,
    buffer: wgpu::Buffer,
}

impl std::fmt::Debug for PointLights {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "PointLights({})", self.lights.len())
    }
}

impl PointLights {
    pub fn new(renderer: &Renderer, lights: Vec<PointLight>) -> Arc<Self> {
        let mut gpu: Vec<GpuPointLight> = lights
            .iter()
            .map(|l| GpuPointLight {
                position_range: [l.position.x, l.position.y, l.position.z, l.range.max(0.0)],
                intensity: (l.color * l.intensity.max(0.0)).extend(0.0).to_array(),
            })
            .collect();
        if gpu.is_empty() {
            // A storage binding cannot be empty; the count says there are none.
            gpu.push(bytemuck::Zeroable::zeroed());
        }
        let buffer = renderer
            .gpu
            .device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("point lights"),
                contents: bytemuck::cast_slice(&gpu),
                usage: wgpu::BufferUsages::STORAGE,
            });
        Arc::new(PointLights { lights, buffer })
    }

    pub fn count(&self) -> u32 {
        self.lights.len() as u32
    }

    pub(crate) fn buffer(&self) -> &wgpu::Buffer {
        &self.buffer
    }
}
