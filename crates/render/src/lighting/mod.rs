//! Lights and shading: light buffers (point, spot, sun), clustered light
//! assignment, the CookTorrance pass and CompositeLight. Shadows come with
//! their issue.

mod clusters;
mod composite;
mod cook_torrance;

use std::sync::Arc;

use glam::Vec3;
use wgpu::util::DeviceExt;

pub use clusters::ClusterGrid;
pub use composite::{CompositeInputs, CompositeLight, LightComponents, MAX_COMPONENTS};
pub use cook_torrance::{CookTorrance, LightLoop, Surfaces};

use crate::renderer::Renderer;

/// A point light. Intensity is luminous intensity in candela (lumens / 4 pi).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointLight {
    pub position: Vec3,
    pub color: Vec3,
    pub intensity: f32,
    pub range: f32,
}

/// A spot light: a point light limited to a cone around `direction`, fading
/// from the inner to the outer half-angle (radians).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpotLight {
    pub position: Vec3,
    pub direction: Vec3,
    pub color: Vec3,
    pub intensity: f32,
    pub range: f32,
    pub inner_angle: f32,
    pub outer_angle: f32,
}

/// A sun: parallel light travelling along `direction`, `illuminance` in lux.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SunLight {
    pub direction: Vec3,
    pub color: Vec3,
    pub illuminance: f32,
}

/// Which light type a buffer holds; CookTorrance compiles one permutation per type.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LightKind {
    Point,
    Spot,
    Sun,
}

impl LightKind {
    pub(crate) fn feature(self) -> Option<&'static str> {
        match self {
            LightKind::Point => None,
            LightKind::Spot => Some("LIGHT_SPOT"),
            LightKind::Sun => Some("LIGHT_SUN"),
        }
    }
}

/// Matches `Light` in shaders/lighting/*.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
struct GpuLight {
    /// xyz position, w range (suns: 0).
    position_range: [f32; 4],
    /// rgb colour times intensity (cd) or illuminance (lux).
    intensity: [f32; 4],
    /// xyz unit direction the light travels, w cosine of the outer cone angle.
    direction: [f32; 4],
    /// x cosine of the inner cone angle.
    cone: [f32; 4],
}

/// What a light-buffer node outputs: lights of one type, uploaded once when its inputs change.
pub struct LightBuffer {
    pub kind: LightKind,
    count: u32,
    buffer: wgpu::Buffer,
}

impl std::fmt::Debug for LightBuffer {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "LightBuffer({:?} x {})", self.kind, self.count)
    }
}

/// A unit vector, or straight down for a zero or non-finite one.
fn unit(v: Vec3) -> Vec3 {
    v.try_normalize().unwrap_or(Vec3::NEG_Y)
}

fn radiant(color: Vec3, intensity: f32) -> [f32; 4] {
    (color.max(Vec3::ZERO) * intensity.max(0.0))
        .extend(0.0)
        .to_array()
}

impl LightBuffer {
    pub fn points(renderer: &Renderer, lights: &[PointLight]) -> Arc<Self> {
        let gpu = lights
            .iter()
            .map(|l| GpuLight {
                position_range: l.position.extend(l.range.max(0.0)).to_array(),
                intensity: radiant(l.color, l.intensity),
                direction: [0.0, -1.0, 0.0, -1.0],
                cone: [-1.0, 0.0, 0.0, 0.0],
            })
            .collect();
        Self::upload(renderer, LightKind::Point, gpu)
    }

    pub fn spots(renderer: &Renderer, lights: &[SpotLight]) -> Arc<Self> {
        let gpu = lights
            .iter()
            .map(|l| {
                // Half-angles within 0..180 degrees; inner never wider than outer.
                let outer = l.outer_angle.clamp(0.0, std::f32::consts::PI);
                let inner = l.inner_angle.clamp(0.0, outer);
                GpuLight {
                    position_range: l.position.extend(l.range.max(0.0)).to_array(),
                    intensity: radiant(l.color, l.intensity),
                    direction: unit(l.direction).extend(outer.cos()).to_array(),
                    cone: [inner.cos(), 0.0, 0.0, 0.0],
                }
            })
            .collect();
        Self::upload(renderer, LightKind::Spot, gpu)
    }

    pub fn suns(renderer: &Renderer, lights: &[SunLight]) -> Arc<Self> {
        let gpu = lights
            .iter()
            .map(|l| GpuLight {
                position_range: [0.0; 4],
                intensity: radiant(l.color, l.illuminance),
                direction: unit(l.direction).extend(-1.0).to_array(),
                cone: [-1.0, 0.0, 0.0, 0.0],
            })
            .collect();
        Self::upload(renderer, LightKind::Sun, gpu)
    }

    fn upload(renderer: &Renderer, kind: LightKind, mut gpu: Vec<GpuLight>) -> Arc<Self> {
        let count = gpu.len() as u32;
        if gpu.is_empty() {
            // A storage binding cannot be empty; the count says there are none.
            gpu.push(bytemuck::Zeroable::zeroed());
        }
        let buffer = renderer
            .gpu
            .device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("lights"),
                contents: bytemuck::cast_slice(&gpu),
                usage: wgpu::BufferUsages::STORAGE,
            });
        Arc::new(LightBuffer {
            kind,
            count,
            buffer,
        })
    }

    pub fn count(&self) -> u32 {
        self.count
    }

    pub(crate) fn buffer(&self) -> &wgpu::Buffer {
        &self.buffer
    }
}
